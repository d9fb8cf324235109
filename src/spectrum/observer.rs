//! From spectral samples to colour: the camera's response for one
//! wavelength set.
//!
//! Chain: spectral radiance samples → CIE XYZ (1931 2° observer, by the
//! set's quadrature) → linear sRGB (IEC 61966-2-1 matrix) → per-channel white
//! balance → encoded sRGB with [`super::srgb::encode`].
//!
//! # White normalisation
//!
//! Radiance is relative to CIE D65 (the light of every scene): the D65
//! spectrum itself must come out as sRGB (1, 1, 1), whatever the sampling.
//! A 21-sample sum of D65 is not the 1 nm white point: its chromaticity is
//! (0.3132, 0.3276) instead of (0.3127, 0.3291), which the sRGB matrix turns
//! into (1.016, 0.997, 1.011); and the published matrix maps even the 1 nm
//! D65 white to (1, 1, 1) only to 2e-4. So [`Observer::new`] integrates D65
//! with *the same wavelengths and weights* it will integrate every spectrum
//! with, and divides each linear sRGB channel by that sampled white (a
//! diagonal gain in the sRGB primaries, within 2% of 1 for 21 samples). Then a flat
//! spectrum times D65 is white to rounding for every set, and the quadrature
//! error of the white cancels from every colour that is near white: the
//! error that remains is in saturation only. This is the same as deriving the
//! sRGB matrix from its primaries with the white point taken to be D65 as
//! the set sees it. XYZ is scaled so that D65 at that sampling has Y = 1.
//!
//! A one-wavelength set has no colour: by this rule it renders grey,
//! `(v, v, v)` with `v` the radiance divided by D65 at that wavelength. A set
//! so sparse that one channel of its sampled white is near zero or negative
//! cannot be balanced and is refused.
//!
//! Monte Carlo sets (hero wavelengths, a new set per sample) want an
//! unbiased estimator instead: [`Observer::with_reference_white`] uses the
//! gains and the Y scale of the 1 nm reference sampling for any set, so the
//! average over samples converges to the 1 nm colour and white is exact in
//! the limit, not per sample.

use super::cie;
use super::srgb::{self, XYZ_TO_LINEAR_SRGB};
use super::wavelengths::WavelengthSet;
use super::SpectrumError;
use std::sync::OnceLock;

/// Smallest sampled-white channel, relative to the largest, that
/// [`Observer::new`] accepts.
const MIN_WHITE_CHANNEL: f64 = 1e-3;

/// The colour response of a wavelength set: per-wavelength weights that turn
/// spectral samples into XYZ and white-balanced linear sRGB.
#[derive(Clone, Debug)]
pub struct Observer {
    lambdas: Vec<f64>,
    /// D65 at each wavelength (relative, 100 at 560 nm).
    d65: Vec<f64>,
    /// XYZ per unit radiance at each wavelength, quadrature weight included.
    xyz: Vec<[f64; 3]>,
    /// Linear sRGB per unit radiance at each wavelength, weight and white
    /// balance included.
    rgb: Vec<[f64; 3]>,
}

/// The scale (1 / Y of sampled D65) and the per-channel sRGB gains that make
/// sampled D65 white, for a set; `None` when the set cannot be balanced.
fn white_normalisation(set: &WavelengthSet) -> Option<(f64, [f64; 3])> {
    let mut xyz_white = [0.0; 3];
    for (lambda, w) in set.iter() {
        let bar = cie::cmf(lambda);
        let p = w * cie::d65(lambda);
        for c in 0..3 {
            xyz_white[c] += p * bar[c];
        }
    }
    // Also refuses NaN.
    if xyz_white[1].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let y_scale = 1.0 / xyz_white[1];
    let rgb_white = srgb::xyz_to_linear_srgb(xyz_white.map(|v| v * y_scale));
    if set.is_monochrome() {
        // rgb_white is that wavelength's colour; dividing by it channel by
        // channel turns every radiance there into grey. Guard the (never
        // seen) exact zero channel.
        return rgb_white
            .iter()
            .all(|&c| c != 0.0 && c.is_finite())
            .then(|| (y_scale, rgb_white.map(|c| 1.0 / c)));
    }
    let largest = rgb_white.iter().fold(0.0_f64, |m, &c| m.max(c));
    if rgb_white.iter().all(|&c| c > MIN_WHITE_CHANNEL * largest) {
        Some((y_scale, rgb_white.map(|c| 1.0 / c)))
    } else {
        None
    }
}

impl Observer {
    /// The response of `set`, white-balanced with the set's own sampling of
    /// D65 (see the module documentation). Fails for a set too sparse to
    /// carry colour (a channel of its sampled white below 1e-3 of the
    /// largest).
    pub fn new(set: &WavelengthSet) -> Result<Self, SpectrumError> {
        let (y_scale, gains) = white_normalisation(set).ok_or(SpectrumError::TooSparse)?;
        Ok(Self::build(set, y_scale, gains))
    }

    /// The response of `set` with the white normalisation of the 1 nm
    /// reference sampling (380–780 nm): for Monte Carlo wavelength sets,
    /// where each set is one sample of an estimator.
    pub fn with_reference_white(set: &WavelengthSet) -> Self {
        let (y_scale, gains) = reference_normalisation();
        Self::build(set, y_scale, gains)
    }

    /// The 1 nm reference observer (401 wavelengths, 380–780 nm), built once.
    pub fn reference() -> &'static Observer {
        static REFERENCE: OnceLock<Observer> = OnceLock::new();
        REFERENCE
            .get_or_init(|| Observer::new(&reference_set()).expect("the 1 nm set carries colour"))
    }

    fn build(set: &WavelengthSet, y_scale: f64, gains: [f64; 3]) -> Self {
        let mut xyz = Vec::with_capacity(set.len());
        let mut rgb = Vec::with_capacity(set.len());
        for (lambda, w) in set.iter() {
            let per_radiance = cie::cmf(lambda).map(|v| v * w * y_scale);
            let lin = srgb::mul3(&XYZ_TO_LINEAR_SRGB, per_radiance);
            xyz.push(per_radiance);
            rgb.push([lin[0] * gains[0], lin[1] * gains[1], lin[2] * gains[2]]);
        }
        Observer {
            lambdas: set.lambdas().to_vec(),
            d65: set.lambdas().iter().map(|&l| cie::d65(l)).collect(),
            xyz,
            rgb,
        }
    }

    /// The wavelengths this observer samples, nm.
    pub fn lambdas(&self) -> &[f64] {
        &self.lambdas
    }

    /// CIE D65 at this observer's wavelengths (relative, 100 at 560 nm):
    /// multiply a reflectance-like spectral factor by it to get radiance.
    pub fn d65(&self) -> &[f64] {
        &self.d65
    }

    /// Linear sRGB per unit radiance at each wavelength (quadrature weight
    /// and white balance included): `rgb = Σ_i radiance_i · weights[i]`.
    pub fn rgb_weights(&self) -> &[[f64; 3]] {
        &self.rgb
    }

    /// XYZ of spectral radiance samples (one per wavelength), D65 having
    /// Y = 1.
    pub fn xyz(&self, radiance: &[f64]) -> [f64; 3] {
        dot3(&self.xyz, radiance)
    }

    /// White-balanced linear sRGB of spectral radiance samples (one per
    /// wavelength): D65 gives (1, 1, 1).
    pub fn linear_srgb(&self, radiance: &[f64]) -> [f64; 3] {
        dot3(&self.rgb, radiance)
    }

    /// Linear sRGB of a reflectance-like factor under D65: the samples of
    /// `factor` are multiplied by D65 first, so a factor of 1 is white.
    pub fn linear_srgb_under_d65(&self, factor: &[f64]) -> [f64; 3] {
        assert_eq!(factor.len(), self.rgb.len(), "one factor per wavelength");
        let mut out = [0.0; 3];
        for ((w, &f), &e) in self.rgb.iter().zip(factor).zip(&self.d65) {
            for c in 0..3 {
                out[c] += w[c] * f * e;
            }
        }
        out
    }

    /// Encoded sRGB of spectral radiance samples (no clamping).
    pub fn srgb(&self, radiance: &[f64]) -> [f64; 3] {
        srgb::encode_rgb(self.linear_srgb(radiance))
    }
}

/// The 1 nm reference set, 380–780 nm.
fn reference_set() -> WavelengthSet {
    WavelengthSet::uniform(401).expect("401 is a valid count")
}

fn reference_normalisation() -> (f64, [f64; 3]) {
    static NORM: OnceLock<(f64, [f64; 3])> = OnceLock::new();
    *NORM
        .get_or_init(|| white_normalisation(&reference_set()).expect("the 1 nm set carries colour"))
}

fn dot3(weights: &[[f64; 3]], samples: &[f64]) -> [f64; 3] {
    assert_eq!(weights.len(), samples.len(), "one sample per wavelength");
    let mut out = [0.0; 3];
    for (w, &s) in weights.iter().zip(samples) {
        for c in 0..3 {
            out[c] += w[c] * s;
        }
    }
    out
}
