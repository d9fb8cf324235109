//! Camera modes: what a film is developed into.
//!
//! - `color`: spectral radiance → CIE XYZ → sRGB (the wavelength set's own
//!   white balance, so a white light renders white).
//! - `mono`: radiance at one wavelength as grey (radiance / D65 there).
//! - `dop`: degree of polarization P at one wavelength as grey (P × D65 →
//!   grey: P = 1 white, P = 0 black), the seed paper's map.
//! - `ellipticity`: b/a of the polarized part, grey.
//! - `ellipticity-paper`: the seed's E_paper = tan(½ asin(|S3|/S0)), grey;
//!   this one reproduces the seed's figures.
//! - `azimuth`: ellipse azimuth ψ as hue (ψ = 0, horizontal, red; ±90°
//!   wraps), brightness P (unpolarized light is black).
//! - `stokes`: an EXR of S0..S3 for every traced wavelength, in the Stokes
//!   frame of [`super::camera`] (Mitsuba 3's: x image right, y image up,
//!   looking back along the light; S1 > 0 horizontal, S2 > 0 at +45° from
//!   right toward up, S3 > 0 right-handed as the receiver sees it).
//!
//! Grey maps are written as sRGB-encoded 8-bit PNGs; values are clamped to
//! [0, 1] and NaN never reaches a pixel (the maps are NaN-free by
//! construction and the film is checked).

use super::film::Film;
use crate::image::{Image, ImageError};
use crate::optics::{Polarimetry, Stokes};
use crate::spectrum::{cie, srgb, Observer, WavelengthSet};

/// A camera mode (`--mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum OutputMode {
    Color,
    Mono,
    Dop,
    Ellipticity,
    EllipticityPaper,
    Azimuth,
    Stokes,
}

impl OutputMode {
    /// The mode's name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            OutputMode::Color => "color",
            OutputMode::Mono => "mono",
            OutputMode::Dop => "dop",
            OutputMode::Ellipticity => "ellipticity",
            OutputMode::EllipticityPaper => "ellipticity-paper",
            OutputMode::Azimuth => "azimuth",
            OutputMode::Stokes => "stokes",
        }
    }

    /// File extension of the mode's output.
    pub fn extension(self) -> &'static str {
        match self {
            OutputMode::Stokes => "exr",
            _ => "png",
        }
    }

    /// True for modes that need the colour wavelength set (the others use
    /// one wavelength).
    pub fn is_spectral(self) -> bool {
        matches!(self, OutputMode::Color | OutputMode::Stokes)
    }
}

fn polarimetry(s: [f64; 4]) -> Polarimetry {
    Polarimetry::from_stokes(Stokes {
        s0: s[0],
        s1: s[1],
        s2: s[2],
        s3: s[3],
    })
}

/// HSV with full saturation to linear-free display RGB: hue in [0, 1).
fn hue(h: f64) -> [f64; 3] {
    let h6 = (h.rem_euclid(1.0)) * 6.0;
    let f = h6 - h6.floor();
    match h6 as u32 {
        0 => [1.0, f, 0.0],
        1 => [1.0 - f, 1.0, 0.0],
        2 => [0.0, 1.0, f],
        3 => [0.0, 1.0 - f, 1.0],
        4 => [f, 0.0, 1.0],
        _ => [1.0, 0.0, 1.0 - f],
    }
}

/// Develops a film into the image of `mode`. `colour` is the wavelength set
/// for `color` (its wavelengths must be in the film), `mono_nm` the
/// wavelength of the single-wavelength maps.
pub fn develop(
    film: &Film,
    mode: OutputMode,
    colour: &WavelengthSet,
    mono_nm: f64,
) -> Result<Image, String> {
    let (w, h) = (film.width, film.height);
    let npix = w as usize * h as usize;
    let finite = |v: f64| {
        if v.is_finite() {
            v.clamp(0.0, 1.0) as f32
        } else {
            0.0
        }
    };
    let rgb_image = |rgb: Vec<f32>| -> Result<Image, String> {
        Image::new(
            w as usize,
            h as usize,
            vec!["R".into(), "G".into(), "B".into()],
            rgb,
        )
        .map_err(|e: ImageError| e.to_string())
    };
    match mode {
        OutputMode::Color => {
            let observer = Observer::new(colour).map_err(|e| e.to_string())?;
            let idx: Vec<usize> = colour
                .lambdas()
                .iter()
                .map(|&l| {
                    film.lambda_index(l)
                        .ok_or_else(|| format!("wavelength {l} nm was not traced"))
                })
                .collect::<Result<_, _>>()?;
            let mut out = Vec::with_capacity(npix * 3);
            let mut radiance = vec![0.0; idx.len()];
            for y in 0..h {
                for x in 0..w {
                    for (r, &i) in radiance.iter_mut().zip(&idx) {
                        *r = film.stokes(x, y, i)[0];
                    }
                    let c = observer.linear_srgb(&radiance);
                    out.extend(c.iter().map(|&v| finite(srgb::encode(v.max(0.0)))));
                }
            }
            rgb_image(out)
        }
        OutputMode::Stokes => {
            let single = film.lambdas.len() == 1;
            let mut planes: Vec<(String, Vec<f32>)> = Vec::new();
            for (i, &l) in film.lambdas.iter().enumerate() {
                for c in 0..4 {
                    let name = if single {
                        format!("S{c}")
                    } else {
                        format!("S{c}_{l:.0}nm")
                    };
                    let mut plane = Vec::with_capacity(npix);
                    for y in 0..h {
                        for x in 0..w {
                            plane.push(film.stokes(x, y, i)[c] as f32);
                        }
                    }
                    planes.push((name, plane));
                }
            }
            Image::from_planes(w as usize, h as usize, planes).map_err(|e| e.to_string())
        }
        _ => {
            let i = film
                .lambda_index(mono_nm)
                .ok_or_else(|| format!("wavelength {mono_nm} nm was not traced"))?;
            let d65 = cie::d65(mono_nm);
            let mut out = Vec::with_capacity(npix * 3);
            for y in 0..h {
                for x in 0..w {
                    let s = film.stokes(x, y, i);
                    let rgb = match mode {
                        OutputMode::Mono => [srgb::encode((s[0] / d65).max(0.0)); 3],
                        OutputMode::Azimuth => {
                            let p = polarimetry(s);
                            let c = hue((p.azimuth / std::f64::consts::PI).rem_euclid(1.0));
                            c.map(|v| v * p.degree_of_polarization)
                        }
                        _ => {
                            let p = polarimetry(s);
                            let v = match mode {
                                OutputMode::Dop => p.degree_of_polarization,
                                OutputMode::Ellipticity => p.ellipticity,
                                _ => p.ellipticity_paper,
                            };
                            [srgb::encode(v); 3]
                        }
                    };
                    out.extend(rgb.iter().map(|&v| finite(v)));
                }
            }
            rgb_image(out)
        }
    }
}
