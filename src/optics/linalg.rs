//! Fixed-size complex linear algebra for the interface solver: complex
//! 3-vectors (fields and wave vectors of evanescent waves) and a 4×4 complex
//! LU factorization with partial pivoting (the boundary-condition system of
//! optics.md §4).
//!
//! Everything here is stack-only: no heap allocation, so the renderer's hot
//! path (the backward query) can call it per ray.

use glam::DVec3;
use num_complex::Complex64;
use std::ops::{Add, Mul, Neg, Sub};

/// A complex 3-vector stored as real and imaginary parts, `re + i im`.
///
/// Products are the bilinear ones unless stated: [`CVec3::dot`] does not
/// conjugate, so `k.dot(k)` is `n²` for an evanescent wave vector in an
/// isotropic medium of index `n`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CVec3 {
    pub re: DVec3,
    pub im: DVec3,
}

impl CVec3 {
    pub const ZERO: CVec3 = CVec3 {
        re: DVec3::ZERO,
        im: DVec3::ZERO,
    };

    #[inline]
    pub const fn new(re: DVec3, im: DVec3) -> Self {
        CVec3 { re, im }
    }

    /// A real vector.
    #[inline]
    pub const fn real(re: DVec3) -> Self {
        CVec3 {
            re,
            im: DVec3::ZERO,
        }
    }

    /// `z · self` for a complex scalar `z`.
    #[inline]
    pub fn scale(self, z: Complex64) -> Self {
        CVec3 {
            re: self.re * z.re - self.im * z.im,
            im: self.im * z.re + self.re * z.im,
        }
    }

    /// Bilinear cross product (no conjugation).
    #[inline]
    pub fn cross(self, o: CVec3) -> Self {
        CVec3 {
            re: self.re.cross(o.re) - self.im.cross(o.im),
            im: self.re.cross(o.im) + self.im.cross(o.re),
        }
    }

    /// Cross product with a real vector.
    #[inline]
    pub fn cross_real(self, v: DVec3) -> Self {
        CVec3 {
            re: self.re.cross(v),
            im: self.im.cross(v),
        }
    }

    /// Bilinear dot product (no conjugation).
    #[inline]
    pub fn dot(self, o: CVec3) -> Complex64 {
        Complex64::new(
            self.re.dot(o.re) - self.im.dot(o.im),
            self.re.dot(o.im) + self.im.dot(o.re),
        )
    }

    /// Dot product with a real vector.
    #[inline]
    pub fn dot_real(self, v: DVec3) -> Complex64 {
        Complex64::new(self.re.dot(v), self.im.dot(v))
    }

    /// Complex conjugate.
    #[inline]
    pub fn conj(self) -> Self {
        CVec3 {
            re: self.re,
            im: -self.im,
        }
    }

    /// Hermitian squared norm `v · v*`.
    #[inline]
    pub fn norm_sqr(self) -> f64 {
        self.re.length_squared() + self.im.length_squared()
    }

    /// True when no component is NaN or infinite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }

    /// True when the imaginary part is exactly zero.
    #[inline]
    pub fn is_real(self) -> bool {
        self.im == DVec3::ZERO
    }
}

impl Add for CVec3 {
    type Output = CVec3;
    #[inline]
    fn add(self, o: CVec3) -> CVec3 {
        CVec3::new(self.re + o.re, self.im + o.im)
    }
}

impl Sub for CVec3 {
    type Output = CVec3;
    #[inline]
    fn sub(self, o: CVec3) -> CVec3 {
        CVec3::new(self.re - o.re, self.im - o.im)
    }
}

impl Neg for CVec3 {
    type Output = CVec3;
    #[inline]
    fn neg(self) -> CVec3 {
        CVec3::new(-self.re, -self.im)
    }
}

impl Mul<f64> for CVec3 {
    type Output = CVec3;
    #[inline]
    fn mul(self, s: f64) -> CVec3 {
        CVec3::new(self.re * s, self.im * s)
    }
}

/// LU factorization `P A = L U` of a complex 4×4 matrix with partial (row)
/// pivoting, for the boundary-condition system. Factor once, then solve for
/// as many right-hand sides (incident waves sharing one tangential wave
/// vector) as needed.
#[derive(Clone, Copy, Debug)]
pub struct Lu4 {
    /// Unit-lower L below the diagonal, U on and above it; the diagonal of U
    /// is stored inverted (`inv_diag`) for the back substitution.
    lu: [[Complex64; 4]; 4],
    inv_diag: [Complex64; 4],
    /// Row `i` of the permuted system is row `perm[i]` of the original.
    perm: [usize; 4],
}

impl Lu4 {
    /// Factor `a` (row-major: `a[row][col]`). Returns `None` when a pivot is
    /// exactly zero or the factorization produced a non-finite number: the
    /// matrix is singular to working precision.
    pub fn factor(a: [[Complex64; 4]; 4]) -> Option<Lu4> {
        let mut lu = a;
        let mut perm = [0usize, 1, 2, 3];
        let mut inv_diag = [Complex64::new(0.0, 0.0); 4];
        for col in 0..4 {
            // Partial pivoting: the largest remaining entry of this column.
            let mut best = col;
            let mut best_mag = lu[col][col].norm_sqr();
            for (row, r) in lu.iter().enumerate().skip(col + 1) {
                let mag = r[col].norm_sqr();
                if mag > best_mag {
                    best = row;
                    best_mag = mag;
                }
            }
            if best_mag == 0.0 || !best_mag.is_finite() {
                return None;
            }
            if best != col {
                lu.swap(best, col);
                perm.swap(best, col);
            }
            let inv = lu[col][col].inv();
            inv_diag[col] = inv;
            let pivot_row = lu[col];
            for r in lu.iter_mut().skip(col + 1) {
                let f = r[col] * inv;
                r[col] = f;
                for (x, u) in r.iter_mut().zip(pivot_row.iter()).skip(col + 1) {
                    *x -= f * u;
                }
            }
        }
        Some(Lu4 { lu, inv_diag, perm })
    }

    /// Solve `A x = b`.
    pub fn solve(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        let mut y = [
            b[self.perm[0]],
            b[self.perm[1]],
            b[self.perm[2]],
            b[self.perm[3]],
        ];
        // Forward substitution with unit-lower L.
        for row in 1..4 {
            for c in 0..row {
                let l = self.lu[row][c];
                let yc = y[c];
                y[row] -= l * yc;
            }
        }
        // Back substitution with U.
        for row in (0..4).rev() {
            for c in row + 1..4 {
                let u = self.lu[row][c];
                let yc = y[c];
                y[row] -= u * yc;
            }
            y[row] *= self.inv_diag[row];
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    #[test]
    fn lu_solves_a_system_that_needs_pivoting() {
        // Zero leading entry forces a row swap.
        let a = [
            [c(0.0, 0.0), c(1.0, 1.0), c(2.0, 0.0), c(0.0, -1.0)],
            [c(3.0, 0.0), c(0.0, 2.0), c(1.0, 0.0), c(1.0, 0.0)],
            [c(1.0, -1.0), c(0.0, 0.0), c(4.0, 1.0), c(2.0, 0.0)],
            [c(0.5, 0.0), c(1.0, 0.0), c(0.0, 3.0), c(5.0, 0.0)],
        ];
        let x = [c(1.0, 2.0), c(-1.0, 0.5), c(0.25, -3.0), c(2.0, 0.0)];
        let mut b = [c(0.0, 0.0); 4];
        for r in 0..4 {
            for k in 0..4 {
                b[r] += a[r][k] * x[k];
            }
        }
        let lu = Lu4::factor(a).expect("regular matrix");
        let y = lu.solve(b);
        for k in 0..4 {
            assert!((y[k] - x[k]).norm() < 1e-14, "{k}: {} vs {}", y[k], x[k]);
        }
    }

    #[test]
    fn lu_reports_a_singular_matrix() {
        let mut a = [[c(0.0, 0.0); 4]; 4];
        a[0][0] = c(1.0, 0.0);
        a[1][1] = c(1.0, 0.0);
        a[2][2] = c(1.0, 0.0);
        assert!(Lu4::factor(a).is_none());
    }

    #[test]
    fn bilinear_products() {
        let k = CVec3::new(DVec3::new(0.3, 0.0, 0.0), DVec3::new(0.0, 0.0, 0.5));
        // k·k = 0.09 - 0.25, no conjugation.
        assert!((k.dot(k) - c(0.09 - 0.25, 0.0)).norm() < 1e-16);
        assert!((k.norm_sqr() - 0.34).abs() < 1e-16);
        let x = CVec3::real(DVec3::X);
        let kx = k.cross(x);
        assert!((kx.im - DVec3::new(0.0, 0.5, 0.0)).length() < 1e-16);
    }
}
