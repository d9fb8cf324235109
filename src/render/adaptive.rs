//! Adaptive sampling: each pixel takes samples until its own samples say
//! its value is known to the noise asked for, or the render's sample
//! count is reached.
//!
//! A pixel takes `min_samples` samples, then doubles its count (`min`,
//! `2·min`, `4·min`, … and finally `samples`) until, at one of these
//! counts `c`, the standard error of its mean is at most `noise` in every
//! quantity below. The standard error is the sample standard deviation
//! over `√c`, raised to its one-sided 95 % upper confidence bound
//! (× √((c − 1) / χ²₀.₀₅(c − 1)): 1.80 at 8 samples, 1.44 at 16, 1.27 at
//! 32), so a
//! pixel whose few samples happen to spread little is not stopped on that
//! luck: checking at every doubling would otherwise stop such pixels
//! early (measured: at 8 minimum samples, the plain estimate gave the
//! glass gem a worse error than fixed sampling at equal rays). Its
//! value is then the mean of those `c` samples (the film stores it as the
//! sum of a full render: the `c`-sample sum × `samples / c`, rounded to
//! `f32` once).
//!
//! The quantities are those the error measures of `spar speed-error`
//! read (docs/speed-vs-error.md), each in the units of a display value:
//! - **colour**: each of R, G, B of the `color` image, as sRGB-encoded
//!   display values in [0, 1]: the error is half the spread of
//!   `encode(clamp(m ± se))` (the curve's slope at the mean, and none
//!   where the pixel is saturated); and its polarized part,
//!   `√((se(Y1)² + se(Y2)² + se(Y3)²) / Y0)` with `Yc` the luminance of
//!   `Sc` integrated like the colour (white: Y0 = 1), for the Stokes
//!   images;
//! - **the single wavelength** (the `mono` and polarization maps'), when
//!   traced: its S0 displayed as `mono` (I = S0 / D65(λ), encoded), and
//!   its polarized part `√((se(S1)² + se(S2)² + se(S3)²) / D65(λ)² / I)`.
//!
//! The polarized parts are the DoP's error as the intensity-weighted DoP
//! error counts it: a pixel of intensity I (in units of white, a radiance
//! 1 light seen directly) and DoP error e adds I·e² to its sum, and e is
//! about `se(S1..S3) / I`, so √(I·e²) = `se(S1..S3) / √I`. A dark pixel
//! is held to a stricter polarization error than a bright one, since its
//! DoP error is larger for the same spread; a black one (I below 1e-4 of
//! white is taken as 1e-4) does not hold the render forever. (The plain
//! DoP error, which counts black pixels' 0/0 as much as lit ones, is not
//! what this aims at; docs/speed-vs-error.md says why.)
//!
//! Everything is decided from the pixel's own samples, in sample order:
//! the image does not depend on tiles, threads or farm regions (tiles
//! merge bit for bit). A sample block (`--samples k0..k1`) cannot decide,
//! and is refused with adaptive sampling on.
//!
//! The estimate is biased where a pixel's first samples all miss a rare
//! bright path (a small variance from few samples, or none when they are
//! all equal): `min_samples` bounds that risk. 32 by default, from
//! measurement (docs/speed-vs-error.md, "What adaptive sampling buys"): on
//! the glass gem at 128×128, 8 and 16 gave a worse image than fixed
//! sampling for the same rays.

use crate::spectrum::{cie, srgb, Observer, WavelengthSet};

/// The `[render] adaptive` and `min_samples` settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    /// The standard error a pixel stops at, in display units (0: off,
    /// every pixel takes every sample).
    pub noise: f64,
    /// Samples every pixel takes before its first check (at least 2).
    pub min_samples: u32,
    /// Edge-adaptive sampling's contrast threshold (0: off): after
    /// `min_samples` samples, a pixel goes on only if what it shows
    /// differs from one of its eight neighbours by more than this, in
    /// display units ([`contrast`]).
    pub edges: f64,
    /// Edge refinement's most samples per pixel (0: off; at least the
    /// render's samples): a pixel at an edge that has taken its `samples`
    /// goes on, four times as many at a time, while what it shows still
    /// moves by more than `edges` (since its first samples, then since the
    /// step before; [`Adaptive::refines_to`]).
    pub max_samples: u32,
}

/// Default samples before a pixel's first check.
pub const DEFAULT_MIN_SAMPLES: u32 = 32;

impl Default for Adaptive {
    fn default() -> Self {
        Adaptive {
            noise: 0.0,
            min_samples: DEFAULT_MIN_SAMPLES,
            edges: 0.0,
            max_samples: 0,
        }
    }
}

impl Adaptive {
    /// Whether pixels stop early on their own noise.
    pub fn is_on(&self) -> bool {
        self.noise > 0.0
    }

    /// Whether pixels away from edges stop at `min_samples`.
    pub fn edges_on(&self) -> bool {
        self.edges > 0.0
    }

    /// Whether a pixel's sample count is decided while it renders (by its
    /// noise, its neighbours or both): it then needs all its samples in
    /// one part.
    pub fn decides(&self) -> bool {
        self.is_on() || self.edges_on()
    }

    /// The sample count after `taken` of edge refinement's next step
    /// (`None`: no step left): four times `taken`, at most `max_samples`.
    /// Only pixels flagged at an edge refine, after all `total` samples.
    pub fn refines_to(&self, taken: u32, total: u32) -> Option<u32> {
        let most = self.most_samples(total);
        (taken >= total && taken < most).then(|| taken.saturating_mul(4).min(most))
    }

    /// The most samples a pixel of a `total`-sample render takes: more
    /// than `total` only with edge refinement on.
    pub fn most_samples(&self, total: u32) -> u32 {
        if self.edges_on() {
            self.max_samples.max(total)
        } else {
            total
        }
    }

    /// Whether a pixel that has taken `taken` of `total` samples checks
    /// its error now: at `min`, `2·min`, `4·min`, … below `total` (a pixel
    /// that reaches `total` is done anyway).
    pub fn checks_at(&self, taken: u32, total: u32) -> bool {
        let min = self.min_samples.max(2);
        taken < total && taken >= min && taken % min == 0 && (taken / min).is_power_of_two()
    }
}

/// What a pixel's samples are measured in: linear sRGB weights of the
/// colour wavelengths' S0, and the single wavelength's index and D65.
#[derive(Clone, Debug)]
pub struct NoiseMeasure {
    /// `(channel index of S0, [r, g, b] weight)` per colour wavelength.
    colour: Vec<(usize, [f64; 3])>,
    /// `(index of the wavelength, D65 there)`.
    mono: Option<(usize, f64)>,
}

/// The number of quantities a [`PixelNoise`] tracks: linear R, G, B of S0;
/// the luminance of S1, S2, S3; the single wavelength's S0..S3 over D65.
const QUANTITIES: usize = 10;

/// Rec. 709 / sRGB luminance of linear R, G, B (IEC 61966-2-1).
const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The intensity (in units of white) below which a pixel's polarization
/// error is weighed as at this one.
const DARKEST: f64 = 1e-4;

/// Index of the single wavelength's S0 among the quantities.
const MONO: usize = 6;

impl NoiseMeasure {
    /// `colour`: the film index of each colour wavelength and its linear
    /// sRGB weights (`Observer::rgb_weights`); `mono`: the film index of
    /// the single wavelength and D65 there.
    pub fn new(colour: Vec<(usize, [f64; 3])>, mono: Option<(usize, f64)>) -> NoiseMeasure {
        NoiseMeasure { colour, mono }
    }

    /// The measure of a render of `lambdas` whose colour modes use
    /// `colour_set` (found in `lambdas` wherever they are; no colour
    /// quantities if one is missing or the set carries no colour) and
    /// whose single wavelength, if any, is the entry after the first
    /// `colour` (`render::prepare::options`' order).
    pub fn for_render(colour_set: &WavelengthSet, lambdas: &[f64], colour: usize) -> NoiseMeasure {
        let same = |a: f64, b: f64| (a - b).abs() < 1e-9;
        let colour_entries = Observer::new(colour_set).ok().and_then(|observer| {
            colour_set
                .lambdas()
                .iter()
                .zip(observer.rgb_weights())
                .map(|(&l, &w)| lambdas.iter().position(|&x| same(x, l)).map(|i| (i, w)))
                .collect::<Option<Vec<_>>>()
        });
        let mono = lambdas.get(colour).map(|&l| (colour, cie::d65(l)));
        NoiseMeasure::new(colour_entries.unwrap_or_default(), mono)
    }

    /// `(index, linear sRGB weight)` of each colour wavelength.
    pub fn colour_weights(&self) -> impl Iterator<Item = (usize, [f64; 3])> + '_ {
        self.colour.iter().copied()
    }

    /// The quantities of one sample's values (`S0..S3` per wavelength).
    fn quantities(&self, v: &[f32]) -> [f64; QUANTITIES] {
        let mut q = [0.0; QUANTITIES];
        for &(i, w) in &self.colour {
            let s0 = v[4 * i] as f64;
            for k in 0..3 {
                q[k] += w[k] * s0;
            }
            let y: f64 = (0..3).map(|k| w[k] * LUMINANCE[k]).sum();
            for c in 1..4 {
                q[2 + c] += y * v[4 * i + c] as f64;
            }
        }
        if let Some((i, d65)) = self.mono {
            for c in 0..4 {
                q[MONO + c] = v[4 * i + c] as f64 / d65;
            }
        }
        q
    }
}

/// A pixel's running sums: of each quantity and of its square.
#[derive(Clone, Debug, Default)]
pub struct PixelNoise {
    n: u32,
    sum: [f64; QUANTITIES],
    sum_sq: [f64; QUANTITIES],
}

/// The 5 % quantile of the χ² distribution with `k` degrees of freedom,
/// by the Wilson–Hilferty approximation (Wilson & Hilferty, PNAS 17, 1931):
/// `k (1 − 2/(9k) + z √(2/(9k)))³` with z = −1.6449, the normal 5 % point.
fn chi_square_lower_5(k: f64) -> f64 {
    let a = 2.0 / (9.0 * k);
    (k * (1.0 - a - 1.644_854 * a.sqrt()).powi(3)).max(f64::MIN_POSITIVE)
}

/// Half the spread of the displayed value over mean ± standard error.
fn display_error(mean: f64, se: f64) -> f64 {
    let shown = |v: f64| srgb::encode(v.clamp(0.0, 1.0));
    0.5 * (shown(mean + se) - shown(mean - se))
}

impl PixelNoise {
    /// Forgets every sample.
    pub fn clear(&mut self) {
        *self = PixelNoise::default();
    }

    /// Adds one sample's values.
    pub fn push(&mut self, measure: &NoiseMeasure, v: &[f32]) {
        let q = measure.quantities(v);
        self.n += 1;
        for ((sum, sum_sq), q) in self.sum.iter_mut().zip(&mut self.sum_sq).zip(q) {
            *sum += q;
            *sum_sq += q * q;
        }
    }

    /// The standard error of the mean of quantity `k` (sample variance
    /// with n − 1; 0 before two samples).
    fn standard_error(&self, k: usize) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        let n = self.n as f64;
        let mean = self.sum[k] / n;
        let var = ((self.sum_sq[k] - n * mean * mean) / (n - 1.0)).max(0.0);
        (var / n).sqrt()
    }

    /// [`Self::standard_error`] at its one-sided 95 % upper confidence
    /// bound: the variance's bound is (n − 1) s² / χ²₀.₀₅(n − 1).
    fn standard_error_bound(&self, k: usize) -> f64 {
        let dof = (self.n.max(2) - 1) as f64;
        self.standard_error(k) * (dof / chi_square_lower_5(dof)).sqrt()
    }

    /// The largest estimated display error of the pixel's mean (the
    /// module documentation's quantities).
    pub fn error(&self, measure: &NoiseMeasure) -> f64 {
        if self.n < 2 {
            return f64::INFINITY;
        }
        let n = self.n as f64;
        let mut worst: f64 = 0.0;
        // The intensity-weighted error of the polarization (module
        // documentation): the spread of S1..S3 over √I.
        let polarized = |first: usize, intensity: f64| {
            let spread: f64 = (first..first + 3)
                .map(|k| self.standard_error_bound(k).powi(2))
                .sum();
            (spread / intensity.max(DARKEST)).sqrt()
        };
        if !measure.colour.is_empty() {
            for k in 0..3 {
                worst = worst.max(display_error(self.sum[k] / n, self.standard_error_bound(k)));
            }
            let y0: f64 = (0..3).map(|k| LUMINANCE[k] * self.sum[k] / n).sum();
            worst = worst.max(polarized(3, y0));
        }
        if measure.mono.is_some() {
            worst = worst.max(display_error(
                self.sum[MONO] / n,
                self.standard_error_bound(MONO),
            ));
            worst = worst.max(polarized(MONO + 1, self.sum[MONO] / n));
        }
        worst
    }
}

/// The number of values [`PixelNoise::shown`] gives.
pub const SHOWN: usize = 10;

impl PixelNoise {
    /// What the pixel's mean shows, as edge-adaptive sampling compares it
    /// with its neighbours': the colour's sRGB-encoded R, G, B in [0, 1];
    /// its polarization as the luminance Stokes vector over Y0 (the
    /// normalized Stokes vector, whose length is the DoP); the single
    /// wavelength's encoded intensity and its normalized Stokes vector.
    /// Quantities the render does not trace, and the polarization of a
    /// pixel darker than [`DARKEST`], are 0.
    pub fn shown(&self, measure: &NoiseMeasure) -> [f64; SHOWN] {
        let mut v = [0.0; SHOWN];
        if self.n == 0 {
            return v;
        }
        let n = self.n as f64;
        let mean = |k: usize| self.sum[k] / n;
        let shown = |x: f64| srgb::encode(x.clamp(0.0, 1.0));
        let normalized = |v: &mut [f64], first: usize, intensity: f64| {
            if intensity > DARKEST {
                for (c, x) in v.iter_mut().enumerate() {
                    *x = mean(first + c) / intensity;
                }
            }
        };
        if !measure.colour.is_empty() {
            for (k, x) in v[..3].iter_mut().enumerate() {
                *x = shown(mean(k));
            }
            let y0: f64 = (0..3).map(|k| LUMINANCE[k] * mean(k)).sum();
            normalized(&mut v[3..6], 3, y0);
        }
        if measure.mono.is_some() {
            v[6] = shown(mean(MONO));
            normalized(&mut v[7..10], MONO + 1, mean(MONO));
        }
        v
    }
}

/// How much two pixels' [`PixelNoise::shown`] values differ: the largest
/// difference of a displayed value (R, G, B, the single wavelength's
/// intensity) or of a normalized Stokes vector (the length of their
/// difference: a change of DoP, angle or ellipticity).
pub fn contrast(a: &[f64; SHOWN], b: &[f64; SHOWN]) -> f64 {
    let d = |k: usize| (a[k] - b[k]).abs();
    let vector = |first: usize| (first..first + 3).map(|k| d(k) * d(k)).sum::<f64>().sqrt();
    d(0).max(d(1))
        .max(d(2))
        .max(vector(3))
        .max(d(6))
        .max(vector(7))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refinement_steps_by_four_up_to_the_most_and_only_with_edges() {
        let a = Adaptive {
            edges: 0.02,
            max_samples: 1000,
            ..Adaptive::default()
        };
        let steps = |a: &Adaptive, total: u32| {
            let mut at = vec![total];
            while let Some(next) = a.refines_to(*at.last().unwrap(), total) {
                at.push(next);
            }
            at
        };
        assert_eq!(steps(&a, 16), [16, 64, 256, 1000]);
        assert_eq!(steps(&a, 250), [250, 1000]);
        assert_eq!(steps(&a, 1000), [1000]);
        assert_eq!(a.refines_to(8, 16), None, "not before all samples");
        let off = Adaptive {
            max_samples: 0,
            ..a
        };
        assert_eq!(steps(&off, 16), [16]);
        let no_edges = Adaptive { edges: 0.0, ..a };
        assert_eq!(steps(&no_edges, 16), [16]);
    }

    #[test]
    fn checks_come_at_min_then_doubling_below_the_total() {
        let a = Adaptive {
            noise: 0.01,
            min_samples: 4,
            edges: 0.0,
            max_samples: 0,
        };
        let at: Vec<u32> = (1..=64).filter(|&t| a.checks_at(t, 64)).collect();
        assert_eq!(at, [4, 8, 16, 32]);
        let at: Vec<u32> = (1..=20).filter(|&t| a.checks_at(t, 20)).collect();
        assert_eq!(at, [4, 8, 16]);
        let b = Adaptive {
            noise: 0.01,
            min_samples: 6,
            edges: 0.0,
            max_samples: 0,
        };
        let at: Vec<u32> = (1..=100).filter(|&t| b.checks_at(t, 100)).collect();
        assert_eq!(at, [6, 12, 24, 48, 96]);
    }

    /// The standard error against the textbook formula on a known set:
    /// values 1..=5 have sample variance 2.5, so se = √(2.5/5).
    #[test]
    fn the_standard_error_is_the_sample_deviation_over_root_n() {
        let m = NoiseMeasure::new(vec![], Some((0, 1.0)));
        let mut p = PixelNoise::default();
        for x in 1..=5 {
            p.push(&m, &[4.0, x as f32, 0.0, 0.0]);
        }
        assert!((p.standard_error(MONO + 1) - 0.5f64.sqrt()).abs() < 1e-12);
        // S0 is constant (4, saturated on display): no display error; the
        // polarized part is se(S1) at its upper bound, × √(4 / χ²₀.₀₅(4))
        // with χ²₀.₀₅(4) = 0.7107, over √I = 2.
        let bound = 0.5f64.sqrt() * (4.0f64 / 0.7107).sqrt() / 2.0;
        assert!((p.error(&m) / bound - 1.0).abs() < 0.02, "{}", p.error(&m));
    }

    /// Against the 5 % points of χ² in published tables (e.g. NIST/SEMATECH
    /// e-Handbook, table 1.3.6.7.4): within 1.5 % from 7 degrees of freedom
    /// (8 samples, the default first check), 5 % at 4.
    #[test]
    fn the_chi_square_quantile_matches_the_tables() {
        for (k, table, tol) in [
            (4.0, 0.711, 0.05),
            (7.0, 2.167, 0.015),
            (15.0, 7.261, 0.015),
            (31.0, 19.281, 0.015),
            (63.0, 45.741, 0.015),
        ] {
            let got = chi_square_lower_5(k);
            assert!((got / table - 1.0).abs() < tol, "k = {k}: {got} vs {table}");
        }
    }

    /// What a pixel shows, against the sRGB curve written out (IEC
    /// 61966-2-1: 1.055 x^(1/2.4) − 0.055 above 0.0031308) and the
    /// normalized Stokes vector by hand; the contrast of two pixels of
    /// equal intensity and perpendicular polarizations is the length of
    /// the difference of their normalized Stokes vectors.
    #[test]
    fn shown_values_and_contrast_match_the_display_curve_and_the_stokes_vector() {
        let m = NoiseMeasure::new(vec![], Some((0, 2.0)));
        let pixel = |s: [f32; 4]| {
            let mut p = PixelNoise::default();
            p.push(&m, &s);
            p.push(&m, &s);
            p.shown(&m)
        };
        // S0 = 0.5 over D65 = 2: I = 0.25; S1 / S0 = 0.4.
        let a = pixel([0.5, 0.2, 0.0, 0.0]);
        let b = pixel([0.5, 0.0, 0.2, 0.0]);
        let encoded = 1.055 * 0.25f64.powf(1.0 / 2.4) - 0.055;
        assert!((a[6] - encoded).abs() < 1e-12, "{}", a[6]);
        assert!(
            (a[7] - 0.4).abs() < 1e-7 && a[8] == 0.0 && a[9] == 0.0,
            "{a:?}"
        );
        assert_eq!(a[..6], [0.0; 6], "no colour traced");
        let c = contrast(&a, &b);
        assert!((c - 0.32f64.sqrt()).abs() < 1e-7, "{c}");
        assert_eq!(contrast(&a, &a), 0.0);
        // A dark pixel shows no polarization, so its neighbour's DoP alone
        // is not an edge; its intensity is.
        let dark = pixel([1e-5, 1e-5, 0.0, 0.0]);
        assert_eq!(dark[7], 0.0);
        assert!((contrast(&a, &dark) - encoded).abs() < 1e-3);
    }

    #[test]
    fn a_saturated_or_constant_pixel_has_no_display_error() {
        assert_eq!(display_error(3.0, 0.5), 0.0);
        assert_eq!(display_error(0.4, 0.0), 0.0);
        // In the linear toe the slope is 12.92.
        assert!((display_error(0.001, 0.0001) - 12.92 * 0.0001).abs() < 1e-12);
    }
}
