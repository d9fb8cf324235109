//! RGB → spectrum for emitter textures: Jakob & Hanika 2019, "A
//! Low-Dimensional Function Space for Efficient Spectral Upsampling"
//! (Computer Graphics Forum 38(2)).
//!
//! A texel's linear sRGB value in [0, 1]³ becomes a smooth reflectance-like
//! spectrum `s(λ) = ½ + x / (2 √(1 + x²))`, `x = c0 t² + c1 t + c2` (the
//! paper's sigmoid of a quadratic, here of the normalised wavelength
//! `t = (λ − 380 nm) / 400 nm`), bounded in (0, 1), which multiplies D65: its
//! colour under D65 is the texel's colour. Texture loaders decode sRGB to
//! linear first.
//!
//! # Why Jakob–Hanika, and why this implementation
//!
//! Smits 1999 builds spectra from seven box-shaped basis spectra: they are
//! piecewise constant (dispersion through a prism would show the steps), can
//! exceed 1, and reproduce the RGB only for the observer and white they were
//! derived for. The sigmoid-quadratic spectra are smooth, stay in (0, 1), and
//! are fitted here against *this* crate's CIE tables, D65 and white balance
//! (the 1 nm [`Observer::reference`]), so a round trip is limited only by
//! the fit, the table interpolation and the render's wavelength sampling.
//!
//! The `rgb2spec` crate (0.1.1, a port of the paper's reference code) was
//! measured for this: it offers no pre-computed table, so one must be made by
//! its optimiser: single-threaded, 1.4 s at resolution 16, 8.9 s at 32 and
//! 80 s at its customary 64 (a 9.4 MB table), in f32, against its own 5 nm
//! CIE data integrated over 360–830 nm and with the paper's white rather than
//! this renderer's 380–780 nm balance. spar cannot run that at build time
//! (the build script is not this module's to change, and 80 s per clean build
//! is too much) and the 9.4 MB table is too big to commit. So the fit below is
//! this crate's own (Gauss–Newton with Levenberg–Marquardt damping on the
//! CIELAB residual, analytic Jacobian, f64), and its coefficient table
//! ([`RgbToSpectrumTable`]) is built lazily once per process, in parallel, at
//! the resolution [`DEFAULT_RESOLUTION`]: 0.6 s on two idle cores, up to
//! 3 s on a busy machine (a renderer can call [`RgbToSpectrumTable::global`]
//! while it loads the scene). Greys (r = g = b) skip the table: their
//! spectrum is the exact constant. [`SigmoidSpectrum::fit`] fits one colour
//! directly (about 0.15 ms), for a uniform colour given in a scene file.
//!
//! The paper spaces the two minor channels' nodes uniformly; near the gamut
//! boundary the coefficients change fastest at both ends of that axis, so
//! here they are smoothstep-spaced. At resolution 24 that cut the largest
//! round-trip error from 1.2e-2 to 5.2e-3 (measured on the grid of
//! `tests/spectrum_material/spectrum_rgb_round_trip.rs`, whose header lists all the numbers).

use super::observer::Observer;
use super::srgb::LINEAR_SRGB_TO_XYZ;
use super::wavelengths::{LAMBDA_MIN_NM, LAMBDA_RANGE_NM};
use rayon::prelude::*;
use std::sync::OnceLock;

/// Resolution of the lazily built global table (nodes per axis).
pub const DEFAULT_RESOLUTION: usize = 24;

/// Largest magnitude of a fitted coefficient: bounds the fit of colours at
/// the edge of the reachable gamut (pure sRGB primaries), where the best
/// spectrum is a step and the coefficients would grow without bound.
const COEFF_LIMIT: f64 = 300.0;

/// The sigmoid `½ + x / (2 √(1 + x²))`, safe for any `x` (±∞ give 1 and 0).
#[inline]
fn sigmoid(x: f64) -> f64 {
    if x.abs() < 1e150 {
        0.5 + 0.5 * x / (1.0 + x * x).sqrt()
    } else if x > 0.0 {
        1.0
    } else if x < 0.0 {
        0.0
    } else {
        0.5 // NaN: the middle, never NaN
    }
}

/// A smooth spectrum in (0, 1) (exactly 0 or 1 for black and white):
/// `s(λ) = sigmoid(c0 t² + c1 t + c2)`, `t = (λ − 380) / 400`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidSpectrum {
    c: [f64; 3],
}

impl SigmoidSpectrum {
    /// The spectrum with these coefficients (of the normalised wavelength
    /// `t`).
    pub fn from_coefficients(c: [f64; 3]) -> Self {
        SigmoidSpectrum { c }
    }

    /// The constant spectrum `v` (clamped to [0, 1]; 0 and 1 exactly).
    pub fn constant(v: f64) -> Self {
        let v = if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c2 = if v <= 0.0 {
            f64::NEG_INFINITY
        } else if v >= 1.0 {
            f64::INFINITY
        } else {
            // Inverse of the sigmoid: x = (v − ½) / √(v (1 − v)).
            (v - 0.5) / (v * (1.0 - v)).sqrt()
        };
        SigmoidSpectrum { c: [0.0, 0.0, c2] }
    }

    /// The coefficients `[c0, c1, c2]`.
    pub fn coefficients(&self) -> [f64; 3] {
        self.c
    }

    /// The spectrum's value at `lambda_nm`.
    #[inline]
    pub fn eval(&self, lambda_nm: f64) -> f64 {
        let t = (lambda_nm - LAMBDA_MIN_NM) / LAMBDA_RANGE_NM;
        let x = if self.c[0] == 0.0 && self.c[1] == 0.0 {
            self.c[2] // constant spectra, including ±∞
        } else {
            (self.c[0] * t + self.c[1]) * t + self.c[2]
        };
        sigmoid(x)
    }

    /// The spectrum at each of `lambdas`.
    pub fn sample(&self, lambdas: &[f64]) -> Vec<f64> {
        lambdas.iter().map(|&l| self.eval(l)).collect()
    }

    /// Looks `rgb` (linear sRGB, clamped to [0, 1]) up in the global table
    /// (built on first use).
    pub fn from_linear_srgb(rgb: [f64; 3]) -> Self {
        RgbToSpectrumTable::global().lookup(rgb)
    }

    /// Fits `rgb` (linear sRGB, clamped to [0, 1]) directly, without the
    /// table: the spectrum whose colour under D65, by the 1 nm reference
    /// observer, is closest to `rgb` in CIELAB. Costs tens of microseconds.
    pub fn fit(rgb: [f64; 3]) -> Self {
        let rgb = clamp_rgb(rgb);
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return Self::constant(rgb[0]);
        }
        let fitter = Fitter::global();
        // Continuation from the grey of the same luminance (a constant
        // spectrum, known exactly) to the target in a few steps along the
        // straight line between them, each step starting from the last
        // solution: plain Gauss–Newton from a constant can stall far from
        // saturated colours.
        let grey = luminance(rgb).clamp(0.02, 0.98);
        let mut c = Self::constant(grey).c;
        const STEPS: usize = 8;
        for k in 1..=STEPS {
            let f = k as f64 / STEPS as f64;
            let waypoint = rgb.map(|v| grey + (v - grey) * f);
            c = fitter.solve(waypoint, c);
        }
        SigmoidSpectrum { c }
    }
}

fn clamp_rgb(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(|v| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    })
}

fn luminance(rgb: [f64; 3]) -> f64 {
    let m = &LINEAR_SRGB_TO_XYZ[1];
    m[0] * rgb[0] + m[1] * rgb[1] + m[2] * rgb[2]
}

/// Precomputed data for fitting: the reference observer's response to a
/// spectral factor under D65 at 1 nm, and the CIELAB white.
struct Fitter {
    /// Normalised wavelength t of each sample.
    t: Vec<f64>,
    /// Linear sRGB per unit factor at each sample (D65, weight and white
    /// balance included); they sum to (1, 1, 1).
    w: Vec<[f64; 3]>,
    white_xyz: [f64; 3],
}

impl Fitter {
    fn global() -> &'static Fitter {
        static FITTER: OnceLock<Fitter> = OnceLock::new();
        FITTER.get_or_init(|| {
            let obs = Observer::reference();
            let t = obs
                .lambdas()
                .iter()
                .map(|&l| (l - LAMBDA_MIN_NM) / LAMBDA_RANGE_NM)
                .collect();
            let w = obs
                .rgb_weights()
                .iter()
                .zip(obs.d65())
                .map(|(r, &e)| r.map(|v| v * e))
                .collect();
            Fitter {
                t,
                w,
                white_xyz: mul3(&LINEAR_SRGB_TO_XYZ, [1.0; 3]),
            }
        })
    }

    /// Linear sRGB of the sigmoid spectrum `c` and its derivatives with
    /// respect to `c` (`d[k][channel]`).
    fn rgb_and_jacobian(&self, c: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let mut rgb = [0.0; 3];
        let mut d = [[0.0; 3]; 3];
        for (&t, w) in self.t.iter().zip(&self.w) {
            let x = (c[0] * t + c[1]) * t + c[2];
            let q = 1.0 + x * x;
            let s = 0.5 + 0.5 * x / q.sqrt();
            // dS/dx = ½ (1 + x²)^(−3/2)
            let ds = 0.5 / (q * q.sqrt());
            let dt = [ds * t * t, ds * t, ds];
            for ch in 0..3 {
                rgb[ch] += w[ch] * s;
                for k in 0..3 {
                    d[k][ch] += w[ch] * dt[k];
                }
            }
        }
        (rgb, d)
    }

    /// CIELAB (CIE 1976 L*a*b*, CIE 015:2018) of linear sRGB, with its Jacobian
    /// `dlab[i][channel]`.
    fn lab_and_jacobian(&self, rgb: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let xyz = mul3(&LINEAR_SRGB_TO_XYZ, rgb);
        let mut f = [0.0; 3];
        let mut df = [0.0; 3]; // df/d(xyz component), through the ratio to white
        const DELTA: f64 = 6.0 / 29.0;
        for i in 0..3 {
            let r = xyz[i] / self.white_xyz[i];
            if r > DELTA * DELTA * DELTA {
                f[i] = r.cbrt();
                df[i] = 1.0 / (3.0 * f[i] * f[i]) / self.white_xyz[i];
            } else {
                f[i] = r / (3.0 * DELTA * DELTA) + 4.0 / 29.0;
                df[i] = 1.0 / (3.0 * DELTA * DELTA) / self.white_xyz[i];
            }
        }
        let lab = [
            116.0 * f[1] - 16.0,
            500.0 * (f[0] - f[1]),
            200.0 * (f[1] - f[2]),
        ];
        // d lab / d xyz, then through the rgb → xyz matrix.
        let dxyz = [
            [0.0, 116.0 * df[1], 0.0],
            [500.0 * df[0], -500.0 * df[1], 0.0],
            [0.0, 200.0 * df[1], -200.0 * df[2]],
        ];
        let mut j = [[0.0; 3]; 3];
        for i in 0..3 {
            for ch in 0..3 {
                j[i][ch] = (0..3).map(|m| dxyz[i][m] * LINEAR_SRGB_TO_XYZ[m][ch]).sum();
            }
        }
        (lab, j)
    }

    /// Residual (CIELAB of the spectrum minus the target's) and its Jacobian
    /// with respect to the coefficients.
    fn residual(&self, c: [f64; 3], target_lab: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
        let (rgb, drgb) = self.rgb_and_jacobian(c);
        let (lab, dlab) = self.lab_and_jacobian(rgb);
        let r = [
            lab[0] - target_lab[0],
            lab[1] - target_lab[1],
            lab[2] - target_lab[2],
        ];
        let mut jac = [[0.0; 3]; 3]; // jac[i][k] = d r_i / d c_k
        for i in 0..3 {
            for k in 0..3 {
                jac[i][k] = (0..3).map(|ch| dlab[i][ch] * drgb[k][ch]).sum();
            }
        }
        (r, jac)
    }

    /// Levenberg–Marquardt on the CIELAB residual from `start`.
    fn solve(&self, rgb: [f64; 3], start: [f64; 3]) -> [f64; 3] {
        let (target_lab, _) = self.lab_and_jacobian(rgb);
        let mut c = limit(start);
        let (mut r, mut jac) = self.residual(c, target_lab);
        let mut cost = dot(r, r);
        let mut mu = 1e-3;
        for _ in 0..40 {
            if cost < 1e-14 {
                break;
            }
            // Normal equations (JᵀJ + μ diag(JᵀJ)) δ = −Jᵀ r.
            let mut a = [[0.0; 3]; 3];
            let mut g = [0.0; 3];
            for k in 0..3 {
                for m in 0..3 {
                    a[k][m] = (0..3).map(|i| jac[i][k] * jac[i][m]).sum();
                }
                g[k] = -(0..3).map(|i| jac[i][k] * r[i]).sum::<f64>();
            }
            let mut improved = false;
            for _ in 0..12 {
                let mut damped = a;
                for k in 0..3 {
                    damped[k][k] += mu * a[k][k].max(1e-12);
                }
                let Some(step) = solve3(damped, g) else {
                    mu *= 10.0;
                    continue;
                };
                let trial = limit([c[0] + step[0], c[1] + step[1], c[2] + step[2]]);
                let (tr, tj) = self.residual(trial, target_lab);
                let tcost = dot(tr, tr);
                if tcost < cost {
                    c = trial;
                    r = tr;
                    jac = tj;
                    cost = tcost;
                    mu = (mu * 0.3).max(1e-12);
                    improved = true;
                    break;
                }
                mu *= 10.0;
            }
            if !improved {
                break;
            }
        }
        c
    }
}

/// Scales coefficients down so that none exceeds [`COEFF_LIMIT`].
fn limit(c: [f64; 3]) -> [f64; 3] {
    let m = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if m > COEFF_LIMIT {
        c.map(|v| v * (COEFF_LIMIT / m))
    } else {
        c
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn mul3(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    super::srgb::mul3(m, v)
}

/// Solves a 3×3 system by Cramer's rule; `None` when singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det3 = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(&a);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let mut x = [0.0; 3];
    for (col, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for row in 0..3 {
            m[row][col] = b[row];
        }
        *xc = det3(&m) / det;
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// A table of fitted coefficients over linear sRGB, laid out as in Jakob &
/// Hanika 2019: for each choice of largest channel, a grid over that
/// channel's value `z` (spaced by `smoothstep(smoothstep(k / (n − 1)))`,
/// denser near black and white) and over the other two channels divided by
/// `z` (smoothstep-spaced here, see the module documentation). Lookups
/// interpolate the coefficients trilinearly.
pub struct RgbToSpectrumTable {
    resolution: usize,
    z_nodes: Vec<f64>,
    /// `[largest channel][z][y][x]` → coefficients.
    coeffs: Vec<[f64; 3]>,
}

static TABLE: OnceLock<RgbToSpectrumTable> = OnceLock::new();

/// The `i`-th of `n` nodes over the ratio of a channel to the largest one:
/// quadratically spaced, dense near 0 where the coefficients of saturated
/// colours change fastest.
fn ratio_node(i: usize, n: usize) -> f64 {
    smoothstep(i as f64 / (n - 1) as f64)
}

/// Continuous node index of a ratio in [0, 1] (inverse of [`ratio_node`]).
fn ratio_position(ratio: f64, n: usize) -> f64 {
    // Inverse of the smoothstep 3u² − 2u³ on [0, 1].
    let u = 0.5 - ((1.0 - 2.0 * ratio.clamp(0.0, 1.0)).asin() / 3.0).sin();
    u.clamp(0.0, 1.0) * (n - 1) as f64
}

fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

impl RgbToSpectrumTable {
    /// The global table at [`DEFAULT_RESOLUTION`], built on first use.
    pub fn global() -> &'static RgbToSpectrumTable {
        TABLE.get_or_init(|| Self::build(DEFAULT_RESOLUTION))
    }

    /// Fits a table of `resolution` nodes per axis (at least 4), using the
    /// rayon thread pool. Each column of nodes along `z` is solved in order,
    /// each node starting from its neighbour's solution.
    pub fn build(resolution: usize) -> Self {
        let n = resolution.max(4);
        let z_nodes: Vec<f64> = (0..n)
            .map(|k| smoothstep(smoothstep(k as f64 / (n - 1) as f64)))
            .collect();
        let fitter = Fitter::global();
        let columns: Vec<(usize, usize, usize)> = (0..3)
            .flat_map(|l| (0..n).flat_map(move |j| (0..n).map(move |i| (l, j, i))))
            .collect();
        let solved: Vec<Vec<[f64; 3]>> = columns
            .par_iter()
            .map(|&(l, j, i)| {
                let x = ratio_node(i, n);
                let y = ratio_node(j, n);
                let rgb_at = |k: usize| {
                    let z = z_nodes[k];
                    let mut rgb = [0.0; 3];
                    rgb[l] = z;
                    rgb[(l + 1) % 3] = x * z;
                    rgb[(l + 2) % 3] = y * z;
                    rgb
                };
                let mut column = vec![[0.0; 3]; n];
                let start = n / 5;
                let mut c = [0.0; 3];
                for (k, node) in column.iter_mut().enumerate().skip(start) {
                    c = fitter.solve(rgb_at(k), c);
                    *node = c;
                }
                let mut c = column[start];
                for (k, node) in column.iter_mut().enumerate().take(start).rev() {
                    c = fitter.solve(rgb_at(k), c);
                    *node = c;
                }
                column
            })
            .collect();
        let mut coeffs = vec![[0.0; 3]; 3 * n * n * n];
        for (&(l, j, i), column) in columns.iter().zip(&solved) {
            for (k, c) in column.iter().enumerate() {
                coeffs[((l * n + k) * n + j) * n + i] = *c;
            }
        }
        RgbToSpectrumTable {
            resolution: n,
            z_nodes,
            coeffs,
        }
    }

    /// Nodes per axis.
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// The spectrum of `rgb` (linear sRGB, clamped to [0, 1]; non-finite
    /// channels count as 0). Black and greys are exact constants.
    pub fn lookup(&self, rgb: [f64; 3]) -> SigmoidSpectrum {
        let rgb = clamp_rgb(rgb);
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return SigmoidSpectrum::constant(rgb[0]);
        }
        let n = self.resolution;
        // Largest channel (ties go to the later channel; both tables agree on
        // the shared edge).
        let mut l = 0;
        for ch in 1..3 {
            if rgb[ch] >= rgb[l] {
                l = ch;
            }
        }
        let z = rgb[l];
        let x = ratio_position(rgb[(l + 1) % 3] / z, n);
        let y = ratio_position(rgb[(l + 2) % 3] / z, n);
        let xi = (x as usize).min(n - 2);
        let yi = (y as usize).min(n - 2);
        // Interval of z among the nodes: the last node not above z.
        let zi = self.z_nodes[..n - 1]
            .partition_point(|&node| node <= z)
            .saturating_sub(1);
        let (fx, fy) = (x - xi as f64, y - yi as f64);
        let fz =
            ((z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi])).clamp(0.0, 1.0);
        let at = |k: usize, j: usize, i: usize| self.coeffs[((l * n + k) * n + j) * n + i];
        let mut c = [0.0; 3];
        for (dk, wz) in [(0, 1.0 - fz), (1, fz)] {
            for (dj, wy) in [(0, 1.0 - fy), (1, fy)] {
                for (di, wx) in [(0, 1.0 - fx), (1, fx)] {
                    let w = wz * wy * wx;
                    let node = at(zi + dk, yi + dj, xi + di);
                    for m in 0..3 {
                        c[m] += w * node[m];
                    }
                }
            }
        }
        SigmoidSpectrum { c }
    }
}
