//! Coherence matrices J = ⟨E Eᴴ⟩ of partially polarized light, and the
//! Stokes parameters derived from them.
//!
//! # Conventions (docs/physics.md §1)
//!
//! - Time dependence: fields are phasors of `exp(i(k·r − ωt))`. (The seed
//!   paper writes `exp(i(ωt + δ))`; that flips the sign of S3 and nothing
//!   else.)
//! - `J` is expressed in an orthonormal transverse basis `(x, y)`, as the
//!   receiver sees it looking back at the source; `Jxy = ⟨Ex Ey*⟩`.
//! - Stokes: `S0 = Jxx + Jyy`, `S1 = Jxx − Jyy`, `S2 = 2 Re Jxy`,
//!   `S3 = 2 Im Jxy`. With `exp(−iωt)` phasors `S3 > 0` means the field turns
//!   clockwise as the receiver sees it: right-handed in the receiver's
//!   (optics) convention, Mitsuba 3's. Example: `Ex = 1, Ey = i` gives
//!   `E(t) = (cos ωt, sin ωt)`, counter-clockwise, and `S3 = −2`.
//! - A crystal eigenwave (o or e) has one mode: its "coherence matrix" is a
//!   single intensity. [`Coherence`] holds both kinds (`modes()` is 1 or 2);
//!   a one-mode matrix behaves, for Stokes parameters, as light fully
//!   polarized along its mode, taken as the basis vector x.
//!
//! # Robustness
//!
//! The renderer sums millions of these; one NaN would reach a pixel. Every
//! derived quantity is finite for any input: non-finite entries count as
//! zero (NaN) or the largest finite number (±∞); the matrix is scaled by its
//! largest entry before anything is squared (so 1e300 and denormals are
//! safe); and a matrix that rounding has left slightly non-positive is
//! replaced by the nearest positive semidefinite one (its negative
//! eigenvalue clipped to zero), so `S0 ≥ |(S1, S2, S3)|` always holds.

use super::jones::Jones;
use glam::DVec3;
use num_complex::Complex64;
use std::iter::Sum;
use std::ops::{Add, AddAssign, Mul};

/// Sense of rotation of the polarized part, as the receiver sees it
/// (optics convention, docs/physics.md §1.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handedness {
    /// Clockwise for the receiver: `S3 > 0`.
    Right,
    /// Counter-clockwise for the receiver: `S3 < 0`.
    Left,
}

/// The coherence matrix of a wave with one or two modes. Stored Hermitian
/// (`Jyx = conj(Jxy)` by construction); 40 bytes, `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coherence {
    modes: u8,
    xx: f64,
    yy: f64,
    xy: Complex64,
}

/// Stokes parameters `[S0, S1, S2, S3]` (see the module conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stokes {
    pub s0: f64,
    pub s1: f64,
    pub s2: f64,
    pub s3: f64,
}

const ZERO: Complex64 = Complex64::new(0.0, 0.0);

/// NaN → 0, ±∞ → ±f64::MAX.
#[inline]
fn finite(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else if v.is_nan() {
        0.0
    } else {
        v.signum() * f64::MAX
    }
}

impl Coherence {
    /// No light, with `modes` modes (1 or 2).
    pub fn zero(modes: usize) -> Coherence {
        assert!(
            modes == 1 || modes == 2,
            "a coherence matrix has 1 or 2 modes, not {modes}"
        );
        Coherence {
            modes: modes as u8,
            xx: 0.0,
            yy: 0.0,
            xy: ZERO,
        }
    }

    /// A one-mode (eigenwave) intensity.
    pub fn scalar(intensity: f64) -> Coherence {
        Coherence {
            modes: 1,
            xx: intensity,
            yy: 0.0,
            xy: ZERO,
        }
    }

    /// Unpolarized light of intensity `intensity`: `J = (I/2) 1`.
    pub fn unpolarized(intensity: f64) -> Coherence {
        Coherence {
            modes: 2,
            xx: 0.5 * intensity,
            yy: 0.5 * intensity,
            xy: ZERO,
        }
    }

    /// Light linearly polarized at `theta` radians from x toward y:
    /// `E = √I (cos θ, sin θ)`.
    pub fn linear(intensity: f64, theta: f64) -> Coherence {
        let (s, c) = theta.sin_cos();
        Coherence {
            modes: 2,
            xx: intensity * c * c,
            yy: intensity * s * s,
            xy: Complex64::new(intensity * c * s, 0.0),
        }
    }

    /// Circularly polarized light: right-handed is `E = √(I/2) (1, −i)`
    /// (`S3 = +I`), left-handed `E = √(I/2) (1, i)` (`S3 = −I`).
    pub fn circular(intensity: f64, handedness: Handedness) -> Coherence {
        let s3 = match handedness {
            Handedness::Right => intensity,
            Handedness::Left => -intensity,
        };
        Coherence {
            modes: 2,
            xx: 0.5 * intensity,
            yy: 0.5 * intensity,
            xy: Complex64::new(0.0, 0.5 * s3),
        }
    }

    /// Fully polarized light of one Jones vector `(Ex, Ey)`: `J = E Eᴴ`.
    pub fn from_jones_vector(e: [Complex64; 2]) -> Coherence {
        Coherence {
            modes: 2,
            xx: e[0].norm_sqr(),
            yy: e[1].norm_sqr(),
            xy: e[0] * e[1].conj(),
        }
    }

    /// A one-mode wave of complex amplitude `a`: intensity `|a|²`.
    pub fn from_amplitude(a: Complex64) -> Coherence {
        Coherence::scalar(a.norm_sqr())
    }

    /// The two-mode matrix with these Stokes parameters:
    /// `Jxx = (S0 + S1)/2`, `Jyy = (S0 − S1)/2`, `Jxy = (S2 + i S3)/2`.
    pub fn from_stokes(s: Stokes) -> Coherence {
        Coherence {
            modes: 2,
            xx: 0.5 * (s.s0 + s.s1),
            yy: 0.5 * (s.s0 - s.s1),
            xy: Complex64::new(0.5 * s.s2, 0.5 * s.s3),
        }
    }

    /// A two-mode matrix from all four entries, made Hermitian: the real
    /// parts of the diagonal, and `Jxy = (m01 + conj(m10)) / 2`.
    pub fn from_matrix(m: [[Complex64; 2]; 2]) -> Coherence {
        Coherence {
            modes: 2,
            xx: m[0][0].re,
            yy: m[1][1].re,
            xy: 0.5 * (m[0][1] + m[1][0].conj()),
        }
    }

    /// Number of modes: 1 (an eigenwave's intensity) or 2.
    #[inline]
    pub fn modes(&self) -> usize {
        self.modes as usize
    }

    /// `Jxx` (the intensity itself for one mode).
    #[inline]
    pub fn jxx(&self) -> f64 {
        self.xx
    }

    /// `Jyy` (zero for one mode).
    #[inline]
    pub fn jyy(&self) -> f64 {
        self.yy
    }

    /// `Jxy = ⟨Ex Ey*⟩` (zero for one mode).
    #[inline]
    pub fn jxy(&self) -> Complex64 {
        self.xy
    }

    /// `Jyx = conj(Jxy)`.
    #[inline]
    pub fn jyx(&self) -> Complex64 {
        self.xy.conj()
    }

    /// The full matrix (`[[Jxx, Jxy], [Jyx, Jyy]]`; zeros beyond one mode).
    pub fn matrix(&self) -> [[Complex64; 2]; 2] {
        [
            [Complex64::new(self.xx, 0.0), self.xy],
            [self.xy.conj(), Complex64::new(self.yy, 0.0)],
        ]
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.xx.is_finite() && self.yy.is_finite() && self.xy.is_finite()
    }

    /// The matrix times a real factor.
    #[inline]
    pub fn scaled(&self, k: f64) -> Coherence {
        Coherence {
            modes: self.modes,
            xx: self.xx * k,
            yy: self.yy * k,
            xy: self.xy * k,
        }
    }

    /// `T J Tᴴ`: the coherence matrix after a deterministic interaction with
    /// amplitude block `t` (docs/physics.md §3). `t.cols` must equal
    /// [`Self::modes`]; the result has `t.rows` modes. The diagonal is
    /// computed as a real sum, so the result is Hermitian exactly.
    pub fn transform(&self, t: &Jones) -> Coherence {
        assert_eq!(
            t.cols,
            self.modes(),
            "a {}×{} Jones block applied to a {}-mode coherence matrix",
            t.rows,
            t.cols,
            self.modes()
        );
        assert!(
            t.rows == 1 || t.rows == 2,
            "a Jones block has 1 or 2 rows, not {}",
            t.rows
        );
        let m = &t.m;
        // Diagonal entry a: Σ_cd T_ac J_cd conj(T_ad), real.
        let diag = |a: usize| -> f64 {
            if self.modes == 1 {
                m[a][0].norm_sqr() * self.xx
            } else {
                m[a][0].norm_sqr() * self.xx
                    + m[a][1].norm_sqr() * self.yy
                    + 2.0 * (m[a][0] * self.xy * m[a][1].conj()).re
            }
        };
        let xx = diag(0);
        if t.rows == 1 {
            return Coherence::scalar(xx);
        }
        let yy = diag(1);
        let xy = if self.modes == 1 {
            m[0][0] * self.xx * m[1][0].conj()
        } else {
            m[0][0] * self.xx * m[1][0].conj()
                + m[0][1] * self.yy * m[1][1].conj()
                + m[0][0] * self.xy * m[1][1].conj()
                + m[0][1] * self.xy.conj() * m[1][0].conj()
        };
        Coherence {
            modes: 2,
            xx,
            yy,
            xy,
        }
    }

    /// The same light in a transverse basis rotated by `theta` radians (from
    /// x toward y): `R J Rᵀ` with [`Jones::rotation`]. S0, P and b/a are
    /// unchanged and the azimuth ψ decreases by `theta` (mod π). A one-mode
    /// matrix is returned unchanged (its mode does not rotate).
    pub fn rotate_basis(&self, theta: f64) -> Coherence {
        if self.modes == 1 {
            return *self;
        }
        self.transform(&Jones::rotation(theta))
    }

    /// The same light expressed in the basis `to` instead of `from` (unit
    /// vectors, 1 or 2 each; `from` must have [`Self::modes`] vectors):
    /// `J' = B J Bᵀ` with `B = ` [`Jones::change_of_basis`]`(from, to)`.
    /// Use it to carry a matrix from one interface's s/p basis into
    /// another's, both transverse to the same ray. A left-handed `to` basis
    /// (a reflection of `from`) flips the sign of S3, as it must.
    pub fn change_basis(&self, from: &[DVec3], to: &[DVec3]) -> Coherence {
        self.transform(&Jones::change_of_basis(from, to))
    }

    /// Total intensity `tr J = S0` (clipped as described in the module
    /// documentation: never negative, never NaN or ∞).
    pub fn intensity(&self) -> f64 {
        self.stokes().s0
    }

    /// The Stokes parameters (module conventions), of the nearest positive
    /// semidefinite matrix; finite for any input, and `S0 ≥ |(S1, S2, S3)|`.
    pub fn stokes(&self) -> Stokes {
        let (scale, s) = self.normalized_stokes();
        let back = |v: f64| finite(v * scale);
        let out = Stokes {
            s0: back(s.s0),
            s1: back(s.s1),
            s2: back(s.s2),
            s3: back(s.s3),
        };
        // Scaling back rounds each parameter separately (to one subnormal
        // unit, at worst): keep S0 ≥ Ip exactly.
        Stokes {
            s0: out.s0.max(out.polarized_intensity()),
            ..out
        }
    }

    /// `(Jxx, Jyy, Re Jxy, Im Jxy)` with NaN as 0 and ±∞ as ±MAX (zeros
    /// beyond the one entry of a one-mode wave).
    fn finite_entries(&self) -> (f64, f64, f64, f64) {
        if self.modes == 1 {
            (finite(self.xx), 0.0, 0.0, 0.0)
        } else {
            (
                finite(self.xx),
                finite(self.yy),
                finite(self.xy.re),
                finite(self.xy.im),
            )
        }
    }

    /// The Stokes parameters as the linear map of `J` (S0 = Jxx + Jyy, S1 =
    /// Jxx − Jyy, S2 = 2 Re Jxy, S3 = 2 Im Jxy; one mode: (I, I, 0, 0)),
    /// without [`Self::stokes`]'s clipping to a physical state: the form a
    /// sum of unbiased estimates needs, since clipping each estimate would
    /// bias the sum. Non-finite entries as in [`Self::stokes`].
    pub fn stokes_linear(&self) -> Stokes {
        let (xx, yy, re, im) = self.finite_entries();
        if self.modes == 1 {
            return Stokes {
                s0: xx,
                s1: xx,
                s2: 0.0,
                s3: 0.0,
            };
        }
        Stokes {
            s0: finite(xx + yy),
            s1: finite(xx - yy),
            s2: finite(2.0 * re),
            s3: finite(2.0 * im),
        }
    }

    /// `(scale, S / scale)`: the Stokes parameters divided by the largest
    /// entry magnitude of `J`, PSD-clipped, each of magnitude at most 4.
    /// `scale = 0` (and zero parameters) for zero or all-NaN input.
    pub(crate) fn normalized_stokes(&self) -> (f64, Stokes) {
        let none = Stokes {
            s0: 0.0,
            s1: 0.0,
            s2: 0.0,
            s3: 0.0,
        };
        let (xx, yy, re, im) = self.finite_entries();
        let scale = xx.abs().max(yy.abs()).max(re.abs()).max(im.abs());
        if scale == 0.0 {
            return (0.0, none);
        }
        let (a, b, c, d) = (xx / scale, yy / scale, re / scale, im / scale);
        let (s0, s1, s2, s3) = if self.modes == 1 {
            (a, a, 0.0, 0.0)
        } else {
            (a + b, a - b, 2.0 * c, 2.0 * d)
        };
        // Eigenvalues (S0 ± Ip)/2; clip the negative ones.
        let ip = s1.hypot(s2.hypot(s3));
        let hi = (0.5 * (s0 + ip)).max(0.0);
        let lo = (0.5 * (s0 - ip)).max(0.0);
        if hi == 0.0 {
            return (0.0, none);
        }
        let ip_clipped = hi - lo;
        let k = if ip > 0.0 { ip_clipped / ip } else { 0.0 };
        (
            scale,
            Stokes {
                s0: hi + lo,
                s1: s1 * k,
                s2: s2 * k,
                s3: s3 * k,
            },
        )
    }
}

impl Add for Coherence {
    type Output = Coherence;

    /// Incoherent superposition: the matrices add (same number of modes).
    #[inline]
    fn add(self, rhs: Coherence) -> Coherence {
        assert_eq!(
            self.modes, rhs.modes,
            "adding coherence matrices of {} and {} modes",
            self.modes, rhs.modes
        );
        Coherence {
            modes: self.modes,
            xx: self.xx + rhs.xx,
            yy: self.yy + rhs.yy,
            xy: self.xy + rhs.xy,
        }
    }
}

impl AddAssign for Coherence {
    #[inline]
    fn add_assign(&mut self, rhs: Coherence) {
        *self = *self + rhs;
    }
}

impl Mul<f64> for Coherence {
    type Output = Coherence;

    #[inline]
    fn mul(self, k: f64) -> Coherence {
        self.scaled(k)
    }
}

impl Sum for Coherence {
    /// The sum of matrices of one shape (the empty sum is the two-mode
    /// zero).
    fn sum<I: Iterator<Item = Coherence>>(mut iter: I) -> Coherence {
        match iter.next() {
            Some(first) => iter.fold(first, |a, b| a + b),
            None => Coherence::zero(2),
        }
    }
}

impl Stokes {
    /// The parameters as an array `[S0, S1, S2, S3]`.
    pub fn to_array(&self) -> [f64; 4] {
        [self.s0, self.s1, self.s2, self.s3]
    }

    /// Polarized intensity `Ip = √(S1² + S2² + S3²)` (without overflow).
    pub fn polarized_intensity(&self) -> f64 {
        finite(self.s1.hypot(self.s2.hypot(self.s3)))
    }
}
