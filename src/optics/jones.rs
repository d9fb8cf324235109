//! Jones blocks: complex amplitude matrices between wave modes.
//!
//! A wave in an isotropic medium has two modes (two transverse basis
//! vectors); an eigenwave in a uniaxial crystal (o or e) has one. A Jones
//! block maps the `cols` modal amplitudes of an incoming wave to the `rows`
//! modal amplitudes of an outgoing wave, so its shape is 1×1, 1×2, 2×1 or
//! 2×2. Unused entries of `m` are zero.

use glam::DVec3;
use num_complex::Complex64;
use std::ops::Mul;

const ZERO: Complex64 = Complex64::new(0.0, 0.0);
const ONE: Complex64 = Complex64::new(1.0, 0.0);

/// A complex matrix of shape `rows × cols`, each 1 or 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jones {
    pub rows: usize,
    pub cols: usize,
    pub m: [[Complex64; 2]; 2],
}

fn check_shape(rows: usize, cols: usize) {
    assert!(
        (1..=2).contains(&rows) && (1..=2).contains(&cols),
        "a Jones block is 1×1, 1×2, 2×1 or 2×2, not {rows}×{cols}"
    );
}

impl Jones {
    /// The zero block of shape `rows × cols`.
    pub fn zero(rows: usize, cols: usize) -> Jones {
        check_shape(rows, cols);
        Jones {
            rows,
            cols,
            m: [[ZERO; 2]; 2],
        }
    }

    /// The `n × n` identity.
    pub fn identity(n: usize) -> Jones {
        let mut j = Jones::zero(n, n);
        for i in 0..n {
            j.m[i][i] = ONE;
        }
        j
    }

    /// A block of shape `rows × cols` from a full 2×2 array; entries outside
    /// the shape are set to zero.
    pub fn from_entries(rows: usize, cols: usize, m: [[Complex64; 2]; 2]) -> Jones {
        let mut j = Jones::zero(rows, cols);
        for (out, row) in j.m.iter_mut().zip(m).take(rows) {
            out[..cols].copy_from_slice(&row[..cols]);
        }
        j
    }

    /// The 2×2 diagonal block `diag(a, b)` (e.g. Fresnel `rs`, `rp`).
    pub fn diagonal(a: Complex64, b: Complex64) -> Jones {
        Jones {
            rows: 2,
            cols: 2,
            m: [[a, ZERO], [ZERO, b]],
        }
    }

    /// The 1×1 block `a` (eigenwave to eigenwave).
    pub fn scalar(a: Complex64) -> Jones {
        Jones::from_entries(1, 1, [[a, ZERO], [ZERO, ZERO]])
    }

    /// The 1×2 block `[a b]` (two modes into one eigenwave).
    pub fn row(a: Complex64, b: Complex64) -> Jones {
        Jones::from_entries(1, 2, [[a, b], [ZERO, ZERO]])
    }

    /// The 2×1 block `[a; b]` (one eigenwave into two modes).
    pub fn column(a: Complex64, b: Complex64) -> Jones {
        Jones::from_entries(2, 1, [[a, ZERO], [b, ZERO]])
    }

    /// The real 2×2 change of transverse basis to axes rotated by `theta`
    /// (radians, from x toward y): components in the new basis are
    /// `R · components in the old`, `R = [[cos θ, sin θ], [−sin θ, cos θ]]`.
    pub fn rotation(theta: f64) -> Jones {
        let (s, c) = theta.sin_cos();
        let r = |v: f64| Complex64::new(v, 0.0);
        Jones {
            rows: 2,
            cols: 2,
            m: [[r(c), r(s)], [r(-s), r(c)]],
        }
    }

    /// The real change of basis from the unit vectors `from` to the unit
    /// vectors `to` (1 or 2 of each): entry `(r, c) = to[r] · from[c]`, the
    /// component along `to[r]` of a unit field along `from[c]`. When both
    /// bases span the same plane (transverse to one direction) this is a
    /// rotation or a reflection; otherwise it projects.
    pub fn change_of_basis(from: &[DVec3], to: &[DVec3]) -> Jones {
        let mut j = Jones::zero(to.len(), from.len());
        for (r, t) in to.iter().enumerate() {
            for (c, f) in from.iter().enumerate() {
                j.m[r][c] = Complex64::new(t.dot(*f), 0.0);
            }
        }
        j
    }

    /// Entry `(r, c)`.
    #[inline]
    pub fn get(&self, r: usize, c: usize) -> Complex64 {
        self.m[r][c]
    }

    /// The matrix product `self · rhs` (`self.cols` must equal `rhs.rows`).
    #[inline]
    pub fn product(&self, rhs: &Jones) -> Jones {
        assert_eq!(
            self.cols, rhs.rows,
            "Jones product of a {}×{} and a {}×{} block",
            self.rows, self.cols, rhs.rows, rhs.cols
        );
        // Unrolled (the hot path of the physical model): each used entry
        // is the sum over k < self.cols from a zero start, in the order a
        // loop would take; unused entries stay zero.
        let (a, b) = (&self.m, &rhs.m);
        let two = self.cols == 2;
        let mut out = Jones::zero(self.rows, rhs.cols);
        for (r, (row, a_r)) in out.m.iter_mut().zip(a).enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                if r < self.rows && c < rhs.cols {
                    *v = ZERO + a_r[0] * b[0][c];
                    if two {
                        *v += a_r[1] * b[1][c];
                    }
                }
            }
        }
        out
    }

    /// The conjugate transpose `Tᴴ`.
    pub fn adjoint(&self) -> Jones {
        let mut out = Jones::zero(self.cols, self.rows);
        for r in 0..self.rows {
            for c in 0..self.cols {
                out.m[c][r] = self.m[r][c].conj();
            }
        }
        out
    }

    /// The block times a complex factor.
    pub fn scaled(&self, k: Complex64) -> Jones {
        let mut out = *self;
        for row in out.m.iter_mut() {
            for v in row.iter_mut() {
                *v *= k;
            }
        }
        out
    }

    /// The block applied to a vector of `cols` modal amplitudes (entries
    /// beyond `cols` are ignored; the result has zeros beyond `rows`).
    pub fn apply(&self, v: [Complex64; 2]) -> [Complex64; 2] {
        let mut out = [ZERO; 2];
        for (r, o) in out.iter_mut().enumerate().take(self.rows) {
            *o = (0..self.cols).map(|c| self.m[r][c] * v[c]).sum();
        }
        out
    }

    /// The squared Frobenius norm `Σ |T_rc|²` (twice the transmitted
    /// intensity of unit unpolarized light through a 2×2 block).
    pub fn norm_sqr(&self) -> f64 {
        self.m.iter().flatten().map(|v| v.norm_sqr()).sum()
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.m.iter().flatten().all(|v| v.is_finite())
    }
}

impl Mul for Jones {
    type Output = Jones;

    /// The matrix product (see [`Jones::product`]).
    fn mul(self, rhs: Jones) -> Jones {
        self.product(&rhs)
    }
}

impl Jones {
    /// An ideal linear polarizer whose transmission axis is at `theta`
    /// radians from basis x toward y: the projector `a aᵀ`, `a = (cos θ,
    /// sin θ)` (Born & Wolf §1.4; a Malus-law element).
    pub fn linear_polarizer(theta: f64) -> Jones {
        let (s, c) = theta.sin_cos();
        let r = |v: f64| Complex64::new(v, 0.0);
        Jones {
            rows: 2,
            cols: 2,
            m: [[r(c * c), r(c * s)], [r(c * s), r(s * s)]],
        }
    }

    /// An ideal retarder (waveplate) with its fast axis at `theta` radians
    /// from basis x toward y and retardance `delta` radians: the slow
    /// component lags by `delta`. With fields `exp(i(k·r − ωt))` a wave
    /// that lags has the larger phase, so in the (fast, slow) basis the
    /// plate is `diag(1, exp(iδ))`, and here `Rᵀ diag(1, e^{iδ}) R` with
    /// `R` = [`Jones::rotation`]`(θ)` (docs/physics.md §9.5).
    pub fn retarder(theta: f64, delta: f64) -> Jones {
        let r = Jones::rotation(theta);
        let d = Jones::diagonal(ONE, Complex64::from_polar(1.0, delta));
        let mut rt = r;
        rt.m[0][1] = r.m[1][0];
        rt.m[1][0] = r.m[0][1];
        rt.product(&d.product(&r))
    }
}
