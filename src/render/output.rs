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
//!   right toward up, S3 > 0 right-handed as the receiver sees it), in the
//!   spectral-polarized layout of Fichet, Pacanowski & Wilkie (JCGT 10(3),
//!   2021): channels `S0.580nm` … ([`stokes_channel`]), linear sRGB preview
//!   channels `R`, `G`, `B`, and the layout's header attributes
//!   ([`SPECTRAL_ATTRIBUTES`]).
//! - `stokes-rgb`: the Stokes vector integrated to linear sRGB per
//!   component, as Mitsuba 3's `stokes` integrator writes it: `R`, `G`, `B`
//!   and `S0.R` … `S3.B`.
//! - `aolp`, `dolp`: polarization-camera practice as polanalyser draws it
//!   (`polanalyser/vis/polar_colorize.py`): the angle of linear
//!   polarization as hue over [0°, 180°) with the degree of linear
//!   polarization as value; DoLP as a black-to-red ramp ([`Map`]).
//! - `polvis-stokes`, `polvis-dop`, `polvis-top`, `polvis-lin`,
//!   `polvis-cir`: the false colours of Wilkie & Weidlich, "A Standardised
//!   Polarisation Visualisation for Images" (SCCG 2010), as Mitsuba 3's
//!   `polvis.py` draws them ([`Map`]).
//! - `sheet`: the first-run picture: `color`, `polvis-dop` and `aolp` side
//!   by side with titles and legends, composed by the command line
//!   (`spar::cli::legend::sheet`); `spar render`'s default without a scene.
//! - `polcam`: a polarization camera: four images of the intensity behind
//!   ideal linear polarizers at 0°, 45°, 90° and 135° from image right
//!   toward image up (the Stokes frame's angles), at one wavelength:
//!   I(θ) = ½(S0 + S1 cos 2θ + S2 sin 2θ) ([`polarizer`]).
//! - `dichroscope`: what a gemmologist's dichroscope shows, two colour
//!   images side by side, the light behind an ideal linear polarizer
//!   along image right (left half) and along image up (right half). A
//!   dichroic stone whose optic axis lies along image right shows its
//!   extraordinary colour (field along the axis) on the left and its
//!   ordinary colour on the right ([`DICHROSCOPE_ANGLES`]).
//! - `polcam-mosaic`: the same intensities as the 2×2 micro-polarizer
//!   mosaic of a Sony IMX250MZR-type sensor, one image of the film's size
//!   ([`MOSAIC`], [`mosaic_angle`]).
//!
//! Most modes have one storage; the polarization-camera modes are written
//! as display images (sRGB-encoded I(θ)/D65(λ), as `mono`) or as linear
//! float EXR (I(θ) in the Stokes EXR's units), chosen by the output file's
//! extension ([`OutputMode::storage`], [`Storage`]).
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
    StokesRgb,
    Polcam,
    PolcamMosaic,
    Aolp,
    Dolp,
    PolvisStokes,
    PolvisDop,
    PolvisTop,
    PolvisLin,
    PolvisCir,
    Sheet,
    Dichroscope,
}

/// A false-colour map of the field's conventions: the colour of each
/// pixel from its Stokes vector alone ([`Map::colour`]), with a legend
/// ([`Map::legend`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Map {
    /// AoLP = ½ atan2(S2, S1) in [0°, 180°) as hue (0° red, 60° green,
    /// 120° blue, the full hue circle over 180°), DoLP = √(S1² + S2²)/S0
    /// as value: polanalyser's `colorize_aolp(aolp, dolp_val=dolp)`.
    Aolp,
    /// DoLP from black (0) to red (1): polanalyser's `colorize_dop`.
    Dolp,
    /// S1/S0, S2/S0 or S3/S0 (component 1..=3): red where negative,
    /// green where positive (polvis `--stokes_nrm`).
    Stokes(usize),
    /// The degree of polarization √(S1² + S2² + S3²)/S0 in red (polvis
    /// `--dop`).
    Dop,
    /// The type of polarization: cyan linear, yellow circular, in
    /// between for elliptical light, scaled by DoP (polvis `--top`).
    Type,
    /// The orientation of the linear part: S1/S0 red (−) / green (+) plus
    /// S2/S0 blue (−) / yellow (+), scaled by the linear share of the
    /// polarized light (polvis `--lin`).
    Linear,
    /// The chirality of the circular part: blue for S3 > 0, yellow for
    /// S3 < 0, scaled by the circular share (polvis `--cir`).
    Circular,
}

/// A map's legend: a title, a bar whose pixel at (x, y) ∈ [0, 1]² (x to
/// the right, y down) shows the map's colour of the Stokes vector
/// [`Legend::stokes`] gives, and labels at positions along x.
pub struct Legend {
    pub title: &'static str,
    pub ticks: Vec<(f64, String)>,
    /// The Stokes vector the bar shows at (x, y).
    pub stokes: fn(f64, f64) -> [f64; 4],
}

impl Map {
    /// The display colour of a pixel whose Stokes vector is `s`: three
    /// values in [0, 1] as stored (already display-encoded: polvis's
    /// linear colours through the sRGB curve, as Mitsuba's Bitmap writes
    /// them; polanalyser's colours are defined on display values and are
    /// stored as they are). Black where S0 ≤ 0 or the value is undefined.
    pub fn colour(self, s: [f64; 4]) -> [f64; 3] {
        if !(s[0] > 0.0) || s.iter().any(|v| !v.is_finite()) {
            return [0.0; 3];
        }
        let n = [s[1] / s[0], s[2] / s[0], s[3] / s[0]];
        let lin = n[0].hypot(n[1]);
        let all = lin.hypot(n[2]);
        let dop = all.min(1.0);
        // The linear and circular shares of the polarized part (polvis's
        // rdop_l and rdop_c, with |S3| as polvis takes it).
        let (share_l, share_c) = if all > 0.0 {
            (lin / all, n[2].abs() / all)
        } else {
            (0.0, 0.0)
        };
        let pos = |v: f64| v.max(0.0);
        let polvis = |c: [f64; 3]| c.map(|v| srgb::encode(v.clamp(0.0, 1.0)));
        match self {
            Map::Aolp => {
                let aolp = (0.5 * n[1].atan2(n[0])).rem_euclid(std::f64::consts::PI);
                let c = hue(aolp / std::f64::consts::PI);
                c.map(|v| v * lin.min(1.0))
            }
            Map::Dolp => [lin.min(1.0), 0.0, 0.0],
            Map::Stokes(k) => {
                let v = n[k - 1].clamp(-1.0, 1.0);
                polvis([pos(-v), pos(v), 0.0])
            }
            Map::Dop => polvis([dop, 0.0, 0.0]),
            Map::Type => polvis([share_c, share_l + share_c, share_l].map(|v| v * dop)),
            Map::Linear => {
                let (a, b) = (n[0].clamp(-1.0, 1.0), n[1].clamp(-1.0, 1.0));
                polvis([pos(-a) + pos(b), pos(a) + pos(b), pos(-b)].map(|v| v * share_l))
            }
            Map::Circular => {
                let c = n[2].clamp(-1.0, 1.0);
                polvis([pos(-c), pos(-c), pos(c)].map(|v| v * share_c))
            }
        }
    }

    /// The map's legend.
    pub fn legend(self) -> Legend {
        let signed = |t: &'static str| Legend {
            title: t,
            ticks: vec![(0.0, "-1".into()), (0.5, "0".into()), (1.0, "+1".into())],
            stokes: |x, _| [1.0, 2.0 * x - 1.0, 0.0, 0.0],
        };
        let degrees = |t: &'static str, f: fn(f64, f64) -> [f64; 4]| Legend {
            title: t,
            ticks: (0..=4)
                .map(|i| (i as f64 / 4.0, format!("{}°", 45 * i)))
                .collect(),
            stokes: f,
        };
        match self {
            Map::Aolp => degrees(
                "AoLP as hue (from image right toward up), DoLP as brightness",
                |x, y| {
                    let t = 2.0 * std::f64::consts::PI * x;
                    [1.0, (1.0 - y) * t.cos(), (1.0 - y) * t.sin(), 0.0]
                },
            ),
            Map::Dolp => Legend {
                title: "DoLP",
                ticks: vec![(0.0, "0".into()), (0.5, "0.5".into()), (1.0, "1".into())],
                stokes: |x, _| [1.0, x, 0.0, 0.0],
            },
            Map::Stokes(1) => signed("S1/S0: red -, green + (horizontal)"),
            Map::Stokes(2) => Legend {
                stokes: |x, _| [1.0, 0.0, 2.0 * x - 1.0, 0.0],
                ..signed("S2/S0: red -, green + (+45°)")
            },
            Map::Stokes(_) => Legend {
                stokes: |x, _| [1.0, 0.0, 0.0, 2.0 * x - 1.0],
                ..signed("S3/S0: red -, green + (right-handed)")
            },
            Map::Dop => Legend {
                title: "degree of polarization",
                ticks: vec![(0.0, "0".into()), (0.5, "0.5".into()), (1.0, "1".into())],
                stokes: |x, _| [1.0, x, 0.0, 0.0],
            },
            Map::Type => Legend {
                title: "type: linear cyan, circular yellow (x DoP)",
                ticks: vec![(0.0, "linear".into()), (1.0, "circular".into())],
                // The ellipticity angle from 0 to 45°, fully polarized.
                stokes: |x, _| {
                    let t = std::f64::consts::FRAC_PI_2 * x;
                    [1.0, t.cos(), 0.0, t.sin()]
                },
            },
            Map::Linear => degrees("orientation of the linear part", |x, _| {
                let t = 2.0 * std::f64::consts::PI * x;
                [1.0, t.cos(), t.sin(), 0.0]
            }),
            Map::Circular => Legend {
                title: "chirality: S3 < 0 yellow, S3 > 0 (right-handed) blue",
                ticks: vec![(0.0, "-1".into()), (0.5, "0".into()), (1.0, "+1".into())],
                stokes: |x, _| {
                    let c = 2.0 * x - 1.0;
                    [1.0, (1.0 - c * c).max(0.0).sqrt(), 0.0, c]
                },
            },
        }
    }
}

/// The legend and false-colour bar of a display map's PNG: [`Map`] of
/// `mode`'s `part`, if it is one.
pub fn map_of(mode: OutputMode, part: usize) -> Option<Map> {
    Some(match mode {
        OutputMode::Aolp => Map::Aolp,
        OutputMode::Dolp => Map::Dolp,
        OutputMode::PolvisStokes => Map::Stokes(part + 1),
        OutputMode::PolvisDop => Map::Dop,
        OutputMode::PolvisTop => Map::Type,
        OutputMode::PolvisLin => Map::Linear,
        OutputMode::PolvisCir => Map::Circular,
        _ => return None,
    })
}

/// How a mode's file holds its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Storage {
    /// A display image: values in [0, 1], sRGB-encoded, 8 bits.
    Display,
    /// Linear values as 32-bit floats (OpenEXR).
    Float,
}

/// Extensions of display images: PNG in every build, TIFF and JPEG where
/// OpenImageIO writes them (the `native` feature).
pub const DISPLAY_EXTENSIONS: [&str; 5] = ["png", "tif", "tiff", "jpg", "jpeg"];

/// The header attributes of the JCGT 2021 spectral layout (Fichet,
/// Pacanowski & Wilkie, "An OpenEXR Layout for Spectral Images", JCGT
/// 10(3)) that a `stokes` EXR carries: the layout's version, the unit of
/// its emissive (`S0`..`S3`) channels, and the handedness of S3 ("right":
/// S3 > 0 is right-handed circular light, as the layout's reference
/// implementation and colour-science write it; spar's S3 > 0 is
/// right-handed, clockwise as the receiver sees it, physics.md §1.4).
pub const SPECTRAL_ATTRIBUTES: [(&str, &str); 3] = [
    ("spectralLayoutVersion", "1.0"),
    ("emissiveUnits", "W.m^-2.sr^-1"),
    ("polarisationHandedness", "right"),
];

/// The channel of Stokes component `component` (0..=3) at `nm` in the JCGT
/// 2021 layout: `S<component>.<wavelength>nm`, the wavelength in nm as the
/// shortest decimal that reads back as the same number, with a comma as
/// the decimal separator (a dot separates OpenEXR layers): `S0.580nm`,
/// `S3.580,5nm`. The layout's readers parse the number before the unit
/// (`nm`) with an optional comma and exponent (its reference code and
/// colour-science's `read_spectral_image_Fichet2021`).
pub fn stokes_channel(component: usize, nm: f64) -> String {
    format!("S{component}.{}nm", format!("{nm}").replace('.', ","))
}

/// The polarizer angles of `dichroscope`'s left and right halves,
/// degrees from image right toward image up.
pub const DICHROSCOPE_ANGLES: [u32; 2] = [0, 90];

/// The polarizer angles of `polcam`'s four images, degrees from image
/// right toward image up, in the order of its files.
pub const POLCAM_ANGLES: [u32; 4] = [0, 45, 90, 135];

/// The polarizer angle of each pixel of a 2×2 block of `polcam-mosaic`,
/// `MOSAIC[row][column]` with row 0 the block's top row as the image is
/// displayed (image rows run down): 90° 45° over 135° 0°, the layout of
/// Sony's IMX250MZR (as Morimatsu et al., ICIP 2020, and polanalyser's
/// `IMX250MZR` demosaicing read it).
pub const MOSAIC: [[u32; 2]; 2] = [[90, 45], [135, 0]];

/// The polarizer angle of image pixel (x, y) (y counted down from the top
/// row) in `polcam-mosaic`.
pub fn mosaic_angle(x: u32, y: u32) -> u32 {
    MOSAIC[(y % 2) as usize][(x % 2) as usize]
}

/// The intensity behind an ideal linear polarizer at `angle` degrees
/// (one of [`POLCAM_ANGLES`]) from image right toward image up, of light
/// with Stokes vector `s` in the film's frame: Malus's law,
/// I(θ) = ½(S0 + S1 cos 2θ + S2 sin 2θ), with the cosines and sines of
/// the four angles exact.
pub fn polarizer(s: [f64; 4], angle: u32) -> f64 {
    match angle {
        0 => 0.5 * (s[0] + s[1]),
        45 => 0.5 * (s[0] + s[2]),
        90 => 0.5 * (s[0] - s[1]),
        135 => 0.5 * (s[0] - s[2]),
        _ => {
            let t = 2.0 * (angle as f64).to_radians();
            0.5 * (s[0] + s[1] * t.cos() + s[2] * t.sin())
        }
    }
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
            OutputMode::StokesRgb => "stokes-rgb",
            OutputMode::Polcam => "polcam",
            OutputMode::PolcamMosaic => "polcam-mosaic",
            OutputMode::Aolp => "aolp",
            OutputMode::Dolp => "dolp",
            OutputMode::PolvisStokes => "polvis-stokes",
            OutputMode::PolvisDop => "polvis-dop",
            OutputMode::PolvisTop => "polvis-top",
            OutputMode::PolvisLin => "polvis-lin",
            OutputMode::PolvisCir => "polvis-cir",
            OutputMode::Sheet => "sheet",
            OutputMode::Dichroscope => "dichroscope",
        }
    }

    /// The extension of the mode's output when the output name has none
    /// (and of its file among several modes whose name's extension does
    /// not fit it).
    pub fn extension(self) -> &'static str {
        match self {
            OutputMode::Stokes | OutputMode::StokesRgb => "exr",
            _ => "png",
        }
    }

    /// How a file of this mode named with extension `ext` holds its
    /// values, or `None` if the mode cannot be written so: `stokes` is an
    /// EXR only, the polarization-camera modes an EXR (float) or a display
    /// image, the others display images only ([`DISPLAY_EXTENSIONS`]).
    pub fn storage(self, ext: &str) -> Option<Storage> {
        let ext = ext.to_ascii_lowercase();
        let exr = ext == "exr";
        let display = DISPLAY_EXTENSIONS.contains(&ext.as_str());
        match self {
            OutputMode::Stokes | OutputMode::StokesRgb => exr.then_some(Storage::Float),
            OutputMode::Polcam | OutputMode::PolcamMosaic if exr => Some(Storage::Float),
            _ => display.then_some(Storage::Display),
        }
    }

    /// The extensions [`Self::storage`] takes, for messages.
    pub fn extensions(self) -> Vec<&'static str> {
        let mut e = Vec::new();
        if self.storage("exr").is_some() {
            e.push("exr");
        }
        e.extend(
            DISPLAY_EXTENSIONS
                .iter()
                .filter(|x| self.storage(x).is_some()),
        );
        e
    }

    /// The suffixes of the mode's files after the output's stem: one file
    /// (no suffix) for every mode but `polcam`, whose four images are
    /// `-000`, `-045`, `-090` and `-135` ([`POLCAM_ANGLES`]).
    pub fn parts(self) -> &'static [&'static str] {
        match self {
            OutputMode::Polcam => &["000", "045", "090", "135"],
            OutputMode::PolvisStokes => &["s1", "s2", "s3"],
            _ => &[""],
        }
    }

    /// True for modes that need the colour wavelength set (the others use
    /// one wavelength).
    pub fn is_spectral(self) -> bool {
        matches!(
            self,
            OutputMode::Color
                | OutputMode::Stokes
                | OutputMode::StokesRgb
                | OutputMode::Dichroscope
        )
    }

    /// True for the modes that need the colour wavelengths traced: the
    /// spectral ones and `sheet` (whose colour panel needs them besides
    /// its maps' one wavelength).
    pub fn needs_colour(self) -> bool {
        self.is_spectral() || self == OutputMode::Sheet
    }

    /// True for the modes `--wavelength` sets (the single-wavelength modes
    /// and `stokes`); `color` and `stokes-rgb` integrate the colour
    /// wavelengths and never use it.
    pub fn uses_wavelength(self) -> bool {
        !matches!(
            self,
            OutputMode::Color | OutputMode::StokesRgb | OutputMode::Dichroscope
        )
    }

    /// True for the modes whose file holds float values rather than a
    /// display image whatever its extension (`stokes`, `stokes-rgb`).
    pub fn is_stokes(self) -> bool {
        matches!(self, OutputMode::Stokes | OutputMode::StokesRgb)
    }

    /// True for the polarization-camera modes (`polcam`, `polcam-mosaic`).
    pub fn is_polcam(self) -> bool {
        matches!(self, OutputMode::Polcam | OutputMode::PolcamMosaic)
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

/// Develops a film into the files of `mode` stored as `storage`, one image
/// per [`OutputMode::parts`] entry: [`develop`]'s image for one-file modes,
/// `polcam`'s four, the polarization-camera images as display images or
/// linear floats. `storage` must be one the mode has
/// ([`OutputMode::storage`]).
pub fn develop_files(
    film: &Film,
    mode: OutputMode,
    colour: &WavelengthSet,
    mono_nm: f64,
    storage: Storage,
) -> Result<Vec<Image>, String> {
    match mode {
        OutputMode::Polcam => POLCAM_ANGLES
            .iter()
            .map(|&a| polcam_image(film, mono_nm, storage, |_, _| a))
            .collect(),
        OutputMode::PolcamMosaic => Ok(vec![polcam_image(film, mono_nm, storage, mosaic_angle)?]),
        OutputMode::PolvisStokes => (1..=3)
            .map(|k| map_image(film, Map::Stokes(k), mono_nm))
            .collect(),
        OutputMode::Sheet => develop(film, mode, colour, mono_nm).map(|i| vec![i]),
        _ => develop(film, mode, colour, mono_nm).map(|i| vec![i]),
    }
}

/// The intensities behind the polarizer `angle(x, y)` gives each pixel, at
/// `nm`, as one grey channel `Y`: I(θ) for [`Storage::Float`] (the Stokes
/// EXR's units), sRGB-encoded I(θ)/D65(λ) clamped to [0, 1] for
/// [`Storage::Display`] (as `mono` shows S0).
fn polcam_image(
    film: &Film,
    nm: f64,
    storage: Storage,
    angle: impl Fn(u32, u32) -> u32,
) -> Result<Image, String> {
    let i = film
        .lambda_index(nm)
        .ok_or_else(|| format!("wavelength {nm} nm was not traced"))?;
    let d65 = cie::d65(nm);
    let mut out = Vec::with_capacity(film.width as usize * film.height as usize);
    for y in 0..film.height {
        for x in 0..film.width {
            let v = polarizer(film.stokes(x, y, i), angle(x, y));
            out.push(match storage {
                Storage::Float => v as f32,
                Storage::Display => {
                    let e = srgb::encode((v / d65).max(0.0));
                    if e.is_finite() {
                        e.clamp(0.0, 1.0) as f32
                    } else {
                        0.0
                    }
                }
            });
        }
    }
    Image::new(
        film.width as usize,
        film.height as usize,
        vec!["Y".into()],
        out,
    )
    .map_err(|e| e.to_string())
}

/// The `stokes` file's preview channels `R`, `G`, `B`: linear sRGB of S0
/// over the colour wavelengths (the CIE 1931 observer, white balanced as
/// `color`: a white light of radiance 1 is (1, 1, 1)), or `None` where the
/// film does not hold them or they carry no colour (a `--wavelength` file
/// of one wavelength).
pub fn stokes_preview(film: &Film, colour: &WavelengthSet) -> Option<[Vec<f32>; 3]> {
    let (observer, idx) = colour_indices(film, colour)?;
    Some(stokes_rgb_planes(film, &observer, &idx, 0))
}

/// The observer of the colour wavelengths and each one's index in the
/// film, if the film holds them all and they carry colour.
fn colour_indices(film: &Film, colour: &WavelengthSet) -> Option<(Observer, Vec<usize>)> {
    let idx: Option<Vec<usize>> = colour
        .lambdas()
        .iter()
        .map(|&l| film.lambda_index(l))
        .collect();
    Some((Observer::new(colour).ok()?, idx?))
}

/// Stokes component `c` integrated to linear sRGB over the colour
/// wavelengths `idx` (the CIE 1931 observer, then the sRGB matrix: linear,
/// so it holds for the signed S1..S3 as for S0): three planes R, G, B.
fn stokes_rgb_planes(film: &Film, observer: &Observer, idx: &[usize], c: usize) -> [Vec<f32>; 3] {
    let npix = film.width as usize * film.height as usize;
    let mut out: [Vec<f32>; 3] = std::array::from_fn(|_| Vec::with_capacity(npix));
    let mut spectrum = vec![0.0; idx.len()];
    for y in 0..film.height {
        for x in 0..film.width {
            for (v, &i) in spectrum.iter_mut().zip(idx) {
                *v = film.stokes(x, y, i)[c];
            }
            let rgb = observer.linear_srgb(&spectrum);
            for k in 0..3 {
                out[k].push(rgb[k] as f32);
            }
        }
    }
    out
}

/// The false-colour map `map` of the film at `nm` (the values
/// [`Map::colour`] gives, without legend).
pub fn map_image(film: &Film, map: Map, nm: f64) -> Result<Image, String> {
    let i = film
        .lambda_index(nm)
        .ok_or_else(|| format!("wavelength {nm} nm was not traced"))?;
    let mut out = Vec::with_capacity(film.width as usize * film.height as usize * 3);
    for y in 0..film.height {
        for x in 0..film.width {
            out.extend(map.colour(film.stokes(x, y, i)).map(|v| v as f32));
        }
    }
    Image::new(
        film.width as usize,
        film.height as usize,
        vec!["R".into(), "G".into(), "B".into()],
        out,
    )
    .map_err(|e| e.to_string())
}

/// Develops a film into the image of `mode`. `colour` is the wavelength set
/// for `color` (its wavelengths must be in the film), `mono_nm` the
/// wavelength of the single-wavelength maps. `polcam`, four images, is
/// [`develop_files`]'; `polcam-mosaic` is developed as a display image.
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
        OutputMode::Dichroscope => {
            // Two colour images, each pixel's spectrum the intensity behind
            // the half's polarizer (Malus, [`polarizer`]), side by side.
            let (observer, idx) = colour_indices(film, colour).ok_or_else(|| {
                "the dichroscope mode needs the colour wavelengths in the film".to_string()
            })?;
            let mut out = vec![0.0f32; 2 * npix * 3];
            let mut radiance = vec![0.0; idx.len()];
            for y in 0..h {
                for x in 0..w {
                    for (half, &angle) in DICHROSCOPE_ANGLES.iter().enumerate() {
                        for (r, &i) in radiance.iter_mut().zip(&idx) {
                            *r = polarizer(film.stokes(x, y, i), angle);
                        }
                        let c = observer.linear_srgb(&radiance);
                        let at = 3 * (y as usize * 2 * w as usize + half * w as usize + x as usize);
                        for (o, v) in out[at..at + 3].iter_mut().zip(c) {
                            *o = finite(srgb::encode(v.max(0.0)));
                        }
                    }
                }
            }
            Image::new(
                2 * w as usize,
                h as usize,
                vec!["R".into(), "G".into(), "B".into()],
                out,
            )
            .map_err(|e: ImageError| e.to_string())
        }
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
            // S0..S3 of each wavelength in turn, four channels a
            // wavelength (the file's R, G, B preview is added by
            // [`stokes_preview`] where the file is written).
            let mut planes: Vec<(String, Vec<f32>)> = Vec::new();
            for (i, &l) in film.lambdas.iter().enumerate() {
                for c in 0..4 {
                    let mut plane = Vec::with_capacity(npix);
                    for y in 0..h {
                        for x in 0..w {
                            plane.push(film.stokes(x, y, i)[c] as f32);
                        }
                    }
                    planes.push((stokes_channel(c, l), plane));
                }
            }
            let mut image =
                Image::from_planes(w as usize, h as usize, planes).map_err(|e| e.to_string())?;
            for (k, v) in SPECTRAL_ATTRIBUTES {
                image = image.with_metadata(k, v);
            }
            Ok(image)
        }
        OutputMode::StokesRgb => {
            let (observer, idx) = colour_indices(film, colour).ok_or_else(|| {
                "the stokes-rgb mode needs the colour wavelengths in the film".to_string()
            })?;
            let mut planes: Vec<(String, Vec<f32>)> = Vec::new();
            for c in 0..4 {
                let rgb = stokes_rgb_planes(film, &observer, &idx, c);
                for (name, plane) in ["R", "G", "B"].iter().zip(rgb) {
                    if c == 0 {
                        planes.push((name.to_string(), plane.clone()));
                    }
                    planes.push((format!("S{c}.{name}"), plane));
                }
            }
            Image::from_planes(w as usize, h as usize, planes).map_err(|e| e.to_string())
        }
        OutputMode::Polcam => Err(
            "the polcam mode is four images (one per polarizer): develop them with develop_files"
                .into(),
        ),
        OutputMode::Sheet => Err(
            "the sheet mode is composed with its titles by the command line (spar render)".into(),
        ),
        OutputMode::PolcamMosaic => polcam_image(film, mono_nm, Storage::Display, mosaic_angle),
        OutputMode::PolvisStokes => map_image(film, Map::Stokes(1), mono_nm),
        m if map_of(m, 0).is_some() => map_image(film, map_of(m, 0).expect("a map"), mono_nm),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_four_polarizers_are_malus_with_exact_angles() {
        let s = [2.0, 0.3, -0.7, 0.4];
        for a in POLCAM_ANGLES {
            let t = 2.0 * (a as f64).to_radians();
            let general = 0.5 * (s[0] + s[1] * t.cos() + s[2] * t.sin());
            assert!((polarizer(s, a) - general).abs() < 1e-15, "{a}");
        }
        // S0 = I0 + I90, S1 = I0 − I90, S2 = I45 − I135 (to rounding).
        let i = POLCAM_ANGLES.map(|a| polarizer(s, a));
        let back = [i[0] + i[2], i[0] - i[2], i[1] - i[3]];
        for (b, s) in back.iter().zip(&s[..3]) {
            assert!((b - s).abs() < 1e-15, "{back:?}");
        }
        // Horizontal light passes 0° whole and 90° not at all.
        assert_eq!(polarizer([1.0, 1.0, 0.0, 0.0], 0), 1.0);
        assert_eq!(polarizer([1.0, 1.0, 0.0, 0.0], 90), 0.0);
        assert_eq!(polarizer([1.0, 0.0, 0.0, 0.0], 22), 0.5);
    }

    /// develop's Stokes image is S0..S3 of each wavelength in turn, four
    /// channels a wavelength and nothing else (the Python module reads it
    /// by position); the preview is the file writer's, from
    /// stokes_preview.
    #[test]
    fn the_stokes_image_is_four_channels_a_wavelength() {
        let lambdas = vec![450.0, 550.5, 650.0];
        let mut film = Film::new(2, 1, lambdas.clone(), 1);
        for (k, d) in film.data.iter_mut().enumerate() {
            *d = [10.0 + k as f32, 1.0, -2.0, 0.5];
        }
        let set = WavelengthSet::from_list(&lambdas).unwrap();
        let img = develop(&film, OutputMode::Stokes, &set, 580.0).unwrap();
        let want: Vec<String> = lambdas
            .iter()
            .flat_map(|&l| (0..4).map(move |c| stokes_channel(c, l)))
            .collect();
        assert_eq!(img.channels(), want);
        for (i, _) in lambdas.iter().enumerate() {
            assert_eq!(img.pixel(1, 0)[4 * i], 10.0 + (3 + i) as f32);
            assert_eq!(img.pixel(1, 0)[4 * i + 2], -2.0);
        }
        let rgb = stokes_preview(&film, &set).expect("the colour set is in the film");
        let observer = Observer::new(&set).unwrap();
        let s0: Vec<f64> = (0..3).map(|i| film.stokes(0, 0, i)[0]).collect();
        let want = observer.linear_srgb(&s0);
        for k in 0..3 {
            assert!((rgb[k][0] as f64 - want[k]).abs() <= 1e-6 * want[k].abs().max(1.0));
        }
        assert!(stokes_preview(&film.only(550.5).unwrap(), &set).is_none());
    }

    #[test]
    fn stokes_channels_follow_the_jcgt_2021_names() {
        assert_eq!(stokes_channel(0, 580.0), "S0.580nm");
        assert_eq!(stokes_channel(3, 580.5), "S3.580,5nm");
        assert_eq!(stokes_channel(1, 412.25), "S1.412,25nm");
        // No dot but the layer's: OpenEXR reads `S2` as the layer.
        assert_eq!(stokes_channel(2, 700.125).matches('.').count(), 1);
    }

    /// The field's colours for states whose colour the conventions name.
    #[test]
    fn maps_give_the_conventions_colours() {
        let h = [1.0, 1.0, 0.0, 0.0]; // horizontal
        let v = [1.0, -1.0, 0.0, 0.0]; // vertical
        let d = [1.0, 0.0, 1.0, 0.0]; // +45°
        let r = [1.0, 0.0, 0.0, 1.0]; // right-handed circular
        let l = [1.0, 0.0, 0.0, -1.0];
        let unpolarized = [1.0, 0.0, 0.0, 0.0];
        let (red, green, blue) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        let (cyan, yellow, black) = ([0.0, 1.0, 1.0], [1.0, 1.0, 0.0], [0.0; 3]);
        let near = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12);
        for (map, s, want) in [
            (Map::Stokes(1), h, green),
            (Map::Stokes(1), v, red),
            (Map::Stokes(2), d, green),
            (Map::Stokes(3), l, red),
            (Map::Dop, r, red),
            (Map::Dop, unpolarized, black),
            (Map::Type, h, cyan),
            (Map::Type, r, yellow),
            (Map::Type, unpolarized, black),
            (Map::Linear, h, green),
            (Map::Linear, v, red),
            (Map::Linear, d, yellow),
            (Map::Linear, [1.0, 0.0, -1.0, 0.0], blue),
            (Map::Linear, r, black),
            (Map::Circular, r, blue),
            (Map::Circular, l, yellow),
            (Map::Circular, h, black),
            (Map::Aolp, h, red),
            (Map::Aolp, v, cyan),
            // 60°: a third of the hue circle.
            (Map::Aolp, [1.0, -0.5, 0.75f64.sqrt(), 0.0], green),
            (Map::Aolp, r, black),
            (Map::Dolp, d, red),
            (Map::Dolp, [2.0, 0.0, 0.0, 0.0], black),
            (Map::Dop, [0.0, 0.0, 0.0, 0.0], black),
        ] {
            assert!(
                near(map.colour(s), want),
                "{map:?} of {s:?}: {:?}",
                map.colour(s)
            );
        }
        // Half polarized: polanalyser scales its colours on display values
        // (value 0.5); polvis encodes its linear 0.5 with the sRGB curve.
        let half = [1.0, 0.5, 0.0, 0.0];
        assert!(near(Map::Aolp.colour(half), [0.5, 0.0, 0.0]));
        assert!(near(Map::Dolp.colour(half), [0.5, 0.0, 0.0]));
        assert!(near(Map::Dop.colour(half), [srgb::encode(0.5), 0.0, 0.0]));
        // The legends' bars span the conventions' colours.
        let ends = |m: Map| {
            let l = m.legend();
            (
                m.colour((l.stokes)(0.0, 0.0)),
                m.colour((l.stokes)(1.0, 0.0)),
            )
        };
        assert!(near(ends(Map::Stokes(2)).0, red) && near(ends(Map::Stokes(2)).1, green));
        assert!(near(ends(Map::Type).0, cyan) && near(ends(Map::Type).1, yellow));
        assert!(near(ends(Map::Circular).0, yellow) && near(ends(Map::Circular).1, blue));
        assert!(near(ends(Map::Dolp).1, red) && near(ends(Map::Aolp).0, red));
    }

    #[test]
    fn the_mosaic_repeats_90_45_over_135_0() {
        let block: Vec<u32> = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|&(x, y)| mosaic_angle(x, y))
            .collect();
        assert_eq!(block, [90, 45, 135, 0]);
        assert_eq!(mosaic_angle(6, 8), 90);
        assert_eq!(mosaic_angle(7, 9), 0);
    }

    #[test]
    fn each_mode_names_the_extensions_it_takes() {
        use OutputMode::*;
        assert_eq!(Stokes.storage("EXR"), Some(Storage::Float));
        assert_eq!(Stokes.storage("png"), None);
        assert_eq!(Polcam.storage("exr"), Some(Storage::Float));
        assert_eq!(PolcamMosaic.storage("png"), Some(Storage::Display));
        assert_eq!(Dop.storage("exr"), None);
        assert_eq!(Color.storage("Tiff"), Some(Storage::Display));
        assert_eq!(Color.storage("txt"), None);
        assert_eq!(Stokes.extensions(), ["exr"]);
        assert_eq!(StokesRgb.extensions(), ["exr"]);
        assert!(!StokesRgb.uses_wavelength() && !Color.uses_wavelength());
        assert!(Stokes.uses_wavelength() && Dop.uses_wavelength());
        assert_eq!(Polcam.extensions()[..2], ["exr", "png"]);
        assert_eq!(Mono.extensions()[0], "png");
        for m in [Color, Mono, Dop, Stokes, StokesRgb, Polcam, PolcamMosaic] {
            assert!(m.storage(m.extension()).is_some(), "{m:?}");
        }
        assert_eq!(Polcam.parts().len(), 4);
    }
}
