//! Fixed-size complex linear algebra for the interface solver: complex
//! 3-vectors (fields and wave vectors of evanescent waves) and a 4×4 complex
//! LU factorization with partial pivoting (the boundary-condition system of
//! docs/physics.md §4.4).
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
///
/// Real and imaginary parts are stored apart and every complex operation is
/// written out in the order `num_complex` evaluates it (`(a + ib)(c + id) =
/// (ac − bd) + i(ad + bc)`, `1/z = z̄/|z|²`), so the results are those of
/// the textbook loop over `Complex64`. A real matrix can be factored in real
/// arithmetic instead ([`Lu4::factor_real_in_place`]): 4× fewer
/// operations, and bit for bit the real parts the complex factorization
/// gives for it (each complex product of reals reduces to the real product
/// exactly, `x − 0·0 = x`, and `1/z = z̄/|z|²` to `p / p²`).
#[derive(Clone, Copy, Debug)]
pub struct Lu4 {
    /// The matrix before factoring; after it, unit-lower L below the
    /// diagonal and U on and above it (real and imaginary parts).
    re: [[f64; 4]; 4],
    im: [[f64; 4]; 4],
    /// Inverted diagonal of U (for the back substitution).
    inv_re: [f64; 4],
    inv_im: [f64; 4],
    /// Row `i` of the permuted system is row `perm[i]` of the original.
    perm: [usize; 4],
}

/// One column step of the elimination (complex), `COL` fixed so that the
/// loops unroll. Returns false when the pivot is zero or not finite.
#[inline(always)]
fn eliminate_complex<const COL: usize>(lu: &mut Lu4) -> bool {
    // Partial pivoting: the largest remaining entry of this column (the
    // first one among equals).
    let (re, im) = (&mut lu.re, &mut lu.im);
    let mut best = COL;
    let mut best_mag = re[COL][COL] * re[COL][COL] + im[COL][COL] * im[COL][COL];
    for row in COL + 1..4 {
        let mag = re[row][COL] * re[row][COL] + im[row][COL] * im[row][COL];
        if mag > best_mag {
            best = row;
            best_mag = mag;
        }
    }
    if best_mag == 0.0 || !best_mag.is_finite() {
        return false;
    }
    if best != COL {
        re.swap(best, COL);
        im.swap(best, COL);
        lu.perm.swap(best, COL);
    }
    // 1/p = p̄/|p|².
    let (pr, pi) = (re[COL][COL], im[COL][COL]);
    let ns = pr * pr + pi * pi;
    let (vr, vi) = (pr / ns, -pi / ns);
    lu.inv_re[COL] = vr;
    lu.inv_im[COL] = vi;
    for r in COL + 1..4 {
        let (xr, xi) = (re[r][COL], im[r][COL]);
        let fr = xr * vr - xi * vi;
        let fi = xr * vi + xi * vr;
        re[r][COL] = fr;
        im[r][COL] = fi;
        for c in COL + 1..4 {
            let (ur, ui) = (re[COL][c], im[COL][c]);
            re[r][c] -= fr * ur - fi * ui;
            im[r][c] -= fr * ui + fi * ur;
        }
    }
    true
}

/// [`eliminate_complex`] for a real matrix (the real parts only).
#[inline(always)]
fn eliminate_real<const COL: usize>(lu: &mut Lu4) -> bool {
    let re = &mut lu.re;
    let mut best = COL;
    let mut best_mag = re[COL][COL] * re[COL][COL];
    for (row, r) in re.iter().enumerate().skip(COL + 1) {
        let mag = r[COL] * r[COL];
        if mag > best_mag {
            best = row;
            best_mag = mag;
        }
    }
    if best_mag == 0.0 || !best_mag.is_finite() {
        return false;
    }
    if best != COL {
        re.swap(best, COL);
        lu.perm.swap(best, COL);
    }
    let p = re[COL][COL];
    let v = p / (p * p);
    lu.inv_re[COL] = v;
    let pivot_row = re[COL];
    for r in re.iter_mut().skip(COL + 1) {
        let f = r[COL] * v;
        r[COL] = f;
        for (x, u) in r.iter_mut().zip(pivot_row).skip(COL + 1) {
            *x -= f * u;
        }
    }
    true
}

impl Lu4 {
    /// Factor `a` (row-major: `a[row][col]`). Returns `None` when a pivot is
    /// exactly zero or the factorization produced a non-finite number: the
    /// matrix is singular to working precision.
    pub fn factor(a: [[Complex64; 4]; 4]) -> Option<Lu4> {
        let mut lu = Lu4::zero();
        for (r, row) in a.iter().enumerate() {
            for (c, z) in row.iter().enumerate() {
                lu.set(r, c, z.re, z.im);
            }
        }
        lu.factor_in_place().then_some(lu)
    }

    /// The zero matrix, to be filled by [`Lu4::set`] and factored in place.
    #[inline]
    pub fn zero() -> Lu4 {
        Lu4 {
            re: [[0.0; 4]; 4],
            im: [[0.0; 4]; 4],
            inv_re: [0.0; 4],
            inv_im: [0.0; 4],
            perm: [0, 1, 2, 3],
        }
    }

    /// Set entry `(row, col)` of the matrix to `re + i im` (before
    /// factoring).
    #[inline]
    pub fn set(&mut self, row: usize, col: usize, re: f64, im: f64) {
        self.re[row][col] = re;
        self.im[row][col] = im;
    }

    /// Factor the matrix in place; false when singular to working
    /// precision (see [`Lu4::factor`]), leaving `self` unusable.
    #[inline]
    pub fn factor_in_place(&mut self) -> bool {
        eliminate_complex::<0>(self)
            && eliminate_complex::<1>(self)
            && eliminate_complex::<2>(self)
            && eliminate_complex::<3>(self)
    }

    /// Factor in place a matrix whose imaginary parts are all zero, in real
    /// arithmetic; solve it with [`Lu4::solve_real`] only.
    #[inline]
    pub fn factor_real_in_place(&mut self) -> bool {
        eliminate_real::<0>(self)
            && eliminate_real::<1>(self)
            && eliminate_real::<2>(self)
            && eliminate_real::<3>(self)
    }

    /// Solve `A x = b`.
    #[inline]
    pub fn solve(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        let (re, im) = self.solve_parts(b.map(|z| z.re), b.map(|z| z.im));
        [0, 1, 2, 3].map(|i| Complex64::new(re[i], im[i]))
    }

    /// Solve `A x = b` for `b = b_re + i b_im`; returns `(Re x, Im x)`.
    #[inline]
    pub fn solve_parts(&self, b_re: [f64; 4], b_im: [f64; 4]) -> ([f64; 4], [f64; 4]) {
        let p = self.perm;
        let mut yr = [b_re[p[0]], b_re[p[1]], b_re[p[2]], b_re[p[3]]];
        let mut yi = [b_im[p[0]], b_im[p[1]], b_im[p[2]], b_im[p[3]]];
        // Forward substitution with unit-lower L.
        for row in 1..4 {
            for c in 0..row {
                let (lr, li) = (self.re[row][c], self.im[row][c]);
                let (cr, ci) = (yr[c], yi[c]);
                yr[row] -= lr * cr - li * ci;
                yi[row] -= lr * ci + li * cr;
            }
        }
        // Back substitution with U.
        for row in (0..4).rev() {
            for c in row + 1..4 {
                let (ur, ui) = (self.re[row][c], self.im[row][c]);
                let (cr, ci) = (yr[c], yi[c]);
                yr[row] -= ur * cr - ui * ci;
                yi[row] -= ur * ci + ui * cr;
            }
            let (ar, ai) = (yr[row], yi[row]);
            let (vr, vi) = (self.inv_re[row], self.inv_im[row]);
            yr[row] = ar * vr - ai * vi;
            yi[row] = ai * vr + ar * vi;
        }
        (yr, yi)
    }

    /// Solve `A x = b` for real `b` after [`Lu4::factor_real_in_place`].
    #[inline]
    pub fn solve_real(&self, b: [f64; 4]) -> [f64; 4] {
        let p = self.perm;
        let mut y = [b[p[0]], b[p[1]], b[p[2]], b[p[3]]];
        for row in 1..4 {
            for c in 0..row {
                y[row] -= self.re[row][c] * y[c];
            }
        }
        for row in (0..4).rev() {
            for c in row + 1..4 {
                y[row] -= self.re[row][c] * y[c];
            }
            y[row] *= self.inv_re[row];
        }
        y
    }
}

/// A real or complex scalar, for solvers written once for both.
pub trait Scalar:
    Copy
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<f64, Output = Self>
{
    const ZERO: Self;
    /// `|x|²`.
    fn norm_sqr(self) -> f64;
    /// As a complex number.
    fn complex(self) -> Complex64;
    /// `1/x`.
    fn recip(self) -> Self;
}

impl Scalar for f64 {
    const ZERO: f64 = 0.0;

    #[inline]
    fn norm_sqr(self) -> f64 {
        self * self
    }

    #[inline]
    fn complex(self) -> Complex64 {
        Complex64::new(self, 0.0)
    }

    #[inline]
    fn recip(self) -> f64 {
        1.0 / self
    }
}

impl Scalar for Complex64 {
    const ZERO: Complex64 = Complex64::new(0.0, 0.0);

    #[inline]
    fn norm_sqr(self) -> f64 {
        Complex64::norm_sqr(&self)
    }

    #[inline]
    fn complex(self) -> Complex64 {
        self
    }

    #[inline]
    fn recip(self) -> Complex64 {
        self.inv()
    }
}

/// LU factorization of a 2×2 matrix with partial pivoting.
#[derive(Clone, Copy, Debug)]
pub struct Lu2<T> {
    /// The rows were swapped.
    swap: bool,
    /// `U = [[u00, u01], [0, u11]]`, `L = [[1, 0], [l10, 1]]`; the pivots
    /// are stored inverted.
    inv_u00: T,
    u01: T,
    l10: T,
    inv_u11: T,
    /// Both pivots are non-zero and finite.
    regular: bool,
}

impl<T: Scalar> Lu2<T> {
    /// Factor `m` (`m[row][col]`). Check [`Lu2::regular`] before solving:
    /// false when a pivot is exactly zero or not finite (singular to
    /// working precision, as [`Lu4::factor`]).
    #[inline]
    pub fn factor(m: [[T; 2]; 2]) -> Lu2<T> {
        let swap = m[1][0].norm_sqr() > m[0][0].norm_sqr();
        let (r0, r1) = if swap { (m[1], m[0]) } else { (m[0], m[1]) };
        let inv_u00 = r0[0].recip();
        let l10 = r1[0] * inv_u00;
        let u11 = r1[1] - l10 * r0[1];
        let (p0, p1) = (r0[0].norm_sqr(), u11.norm_sqr());
        Lu2 {
            swap,
            inv_u00,
            u01: r0[1],
            l10,
            inv_u11: u11.recip(),
            regular: p0 != 0.0 && p0.is_finite() && p1 != 0.0 && p1.is_finite(),
        }
    }

    /// Both pivots are non-zero and finite.
    #[inline]
    pub fn regular(&self) -> bool {
        self.regular
    }

    /// Solve `M x = b`.
    #[inline]
    pub fn solve(&self, b: [T; 2]) -> [T; 2] {
        let (b0, b1) = if self.swap {
            (b[1], b[0])
        } else {
            (b[0], b[1])
        };
        let x1 = (b1 - self.l10 * b0) * self.inv_u11;
        let x0 = (b0 - self.u01 * x1) * self.inv_u00;
        [x0, x1]
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
    fn real_factorization_reproduces_the_complex_one_bit_for_bit() {
        let a = [
            [0.0, 1.5, 2.0, -1.0],
            [3.0, 0.25, 1.0, 1.0],
            [1.0, -7.0, 4.0, 2.0],
            [0.5, 1.0, 1.0 / 3.0, 5.0],
        ];
        let b = [1.0, -0.3, 0.7, 2.0];
        let complex = Lu4::factor(a.map(|r| r.map(|x| c(x, 0.0)))).unwrap();
        let mut real = Lu4::zero();
        for (i, row) in a.iter().enumerate() {
            for (j, &x) in row.iter().enumerate() {
                real.set(i, j, x, 0.0);
            }
        }
        assert!(real.factor_real_in_place());
        let x = real.solve_real(b);
        let z = complex.solve(b.map(|x| c(x, 0.0)));
        for k in 0..4 {
            assert_eq!(x[k], z[k].re);
            assert_eq!(z[k].im, 0.0);
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
