//! Eigenwaves of any non-absorbing anisotropic medium (a real symmetric
//! dielectric tensor ε: biaxial crystals, and uniaxial and isotropic media
//! as special cases) that share one tangential wave vector at an interface
//! (docs/physics.md §4.8; Booker, Phil. Trans. R. Soc. A 237, 411 (1938);
//! Born & Wolf §15.2–15.3).
//!
//! The conventions are those of [`super::modes`] (time dependence
//! `exp(i(k·r − ωt))`, `k = t + q N`, `H = k × E`, unit normal into side +).
//!
//! # The wave vectors: Booker's quartic
//!
//! A plane wave `E` with wave vector `k` solves Maxwell's equations when
//! `W(k) E = 0`, `W(k) = ε + k kᵀ − (k·k) I`, and `det W(k) = 0` is
//! (Fresnel's equation in invariant form, checked in the principal frame)
//!
//! ```text
//! det W(k) = (k·k)(kᵀ ε k) − kᵀ B k + det ε,   B = tr(ε) ε − ε².
//! ```
//!
//! With `k = t + q N` (`t·N = 0`, `T² = t·t`) it is a real quartic in `q`:
//!
//! ```text
//! ε_NN q⁴ + 2 ε_tN q³ + (ε_tt + ε_NN T² − B_NN) q²
//!        + 2 (ε_tN T² − B_tN) q + (ε_tt T² − B_tt + det ε) = 0
//! ```
//!
//! (`ε_ab = aᵀ ε b`). Its four roots are two waves leaving the interface on
//! each side and two arriving; which is which is decided by energy, as in
//! [`super::modes`]: a real root is outgoing on side σ when `σ (S·N) > 0`,
//! `S = Re(E × H*)/2` its Poynting vector; a complex root (an evanescent
//! wave) when it decays into side σ, `σ Im q > 0`. For a lossless medium
//! exactly two roots are outgoing (Berreman 1972): when rounding near
//! grazing says otherwise, the two with the largest `σ S·N` are.
//!
//! # Fields
//!
//! `E` spans the null space of `W(k)` (the largest cross product of two of
//! its rows, bilinear for a complex `k`), normalized to unit Hermitian
//! length. Where two outgoing roots meet (an optic axis, or every direction
//! in the isotropic limit) the null space is two-dimensional: the pair gets
//! `E₁ = s` projected orthogonal to the dominant row `r` of `W` and
//! `E₂ = r × E₁`, which is `s` and `p` of an isotropic medium.
//!
//! # Names: fast and slow
//!
//! A propagating wave with unit ray `ŝ` is *fast* when its ray index
//! squared `(k·ŝ)²` is nearer the smaller of the two roots of Fresnel's ray
//! equation for `ŝ` (the faster sheet of the ray surface), *slow*
//! otherwise; away from the optic axes that is also the inner (lower
//! index) sheet of the index surface. The two outgoing waves of a side are
//! listed fast first. Near an optic axis both waves of a side can share a
//! name (the ray direction then tells them apart), and evanescent waves
//! are named by their place in that order.

use super::linalg::CVec3;
use super::medium::Medium;
use super::modes::{Dd, Eigenwave, Mode, Side, TangentFrame, Travel, WaveKind};
use super::near_isotropic::{self, PlaneForm};
use glam::{DMat3, DVec3};
use num_complex::Complex64;

/// Roots closer than this (relative to `1 + |q|`) are one cluster, handled
/// by a local quadratic model (near-double roots: grazing, optic axes).
const CLUSTER: f64 = 1e-6;

/// A root farther than this from the real axis (relative) that is not in
/// a cluster is complex; closer ones are real with rounding noise.
const REAL_TOL: f64 = 1e-9;

/// Two outgoing waves of one side whose wave vectors are closer than this
/// (relative) are degenerate: their fields come from the two-dimensional
/// null space at the pair's centre. Below ~1e-8 the f64 roots (error
/// ≈ ε/separation) are less accurate than the separation itself.
const DEGENERATE: f64 = 1e-8;

/// `W(k)` is of rank ≤ 1 when its largest row cross product is below this
/// times its largest squared row (squared quantities).
const RANK1_TOL: f64 = 1e-24;

/// The dielectric tensor with the invariants the quartic needs, and the
/// optic axes.
#[derive(Clone, Copy, Debug)]
pub struct Tensor {
    pub eps: DMat3,
    /// `B = tr(ε) ε − ε²`.
    pub b: DMat3,
    pub det: f64,
    /// `1/n_α²` and `1/n_γ²` (largest and smallest principal `1/n²`).
    v_hi: f64,
    v_lo: f64,
    /// The optic axes (wave normals), both `c` for a uniaxial medium.
    axes: [DVec3; 2],
}

impl Tensor {
    /// The tensor of `medium`.
    pub fn of(medium: &Medium) -> Tensor {
        let eps = medium.epsilon();
        let tr = eps.x_axis.x + eps.y_axis.y + eps.z_axis.z;
        let inv2 = |n: f64| 1.0 / (n * n);
        let (v_hi, v_lo, axes) = match *medium {
            Medium::Isotropic { n } => (inv2(n), inv2(n), [DVec3::Z; 2]),
            // Either sign: the optic axis is the principal axis of the
            // single index.
            Medium::Uniaxial { n_o, n_e, axis } => {
                (inv2(n_o.min(n_e)), inv2(n_o.max(n_e)), [axis; 2])
            }
            Medium::Biaxial { n, .. } => {
                let lo = n.into_iter().fold(f64::INFINITY, f64::min);
                let hi = n.into_iter().fold(0.0, f64::max);
                (
                    inv2(lo),
                    inv2(hi),
                    optic_axes(medium).unwrap_or([DVec3::Z; 2]),
                )
            }
        };
        Tensor {
            eps,
            b: eps * tr - eps * eps,
            det: eps.determinant(),
            v_hi,
            v_lo,
            axes,
        }
    }

    /// `W(k) E = ε E + k (k·E) − (k·k) E`.
    #[inline]
    fn w_times(&self, k: CVec3, e: CVec3) -> CVec3 {
        let ee = CVec3::new(self.eps * e.re, self.eps * e.im);
        ee + k.scale(k.dot(e)) - e.scale(k.dot(k))
    }

    /// The rows of `W(k)` (symmetric, so also its columns).
    #[inline]
    fn w_rows(&self, k: CVec3) -> [CVec3; 3] {
        let kk = k.dot(k);
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        axes.map(|a| {
            let row = CVec3::real(self.eps * a) + k.scale(k.dot_real(a));
            row - CVec3::real(a).scale(kk)
        })
    }

    /// Starting points for the quartic's roots: `±√(n² − T²)` for the
    /// smallest and largest principal index `n` (each root is within the
    /// birefringence of one of them), shifted by the centre of the roots
    /// `−ε_tN/(2 ε_NN)`, off the real axis by a little (a real polynomial
    /// keeps real iterates real) and `None` where the two indices meet (the
    /// iteration needs distinct starts).
    fn starts(&self, frame: &TangentFrame) -> Option<[Complex64; 4]> {
        let (lo, hi) = (1.0 / self.v_hi, 1.0 / self.v_lo);
        if !(hi - lo > 1e-6 * hi) {
            return None;
        }
        let en = self.eps * frame.normal;
        let centre = -frame.t.dot(en) / (2.0 * frame.normal.dot(en));
        let q = |n2: f64, sign: f64, tilt: f64| {
            let d = n2 - frame.tt;
            let r = d.abs().sqrt();
            let z = if d >= 0.0 {
                Complex64::new(sign * r, tilt * r)
            } else {
                Complex64::new(tilt * r, sign * r)
            };
            z + centre
        };
        let t = 0.001;
        Some([
            q(lo, 1.0, t),
            q(hi, 1.0, -t),
            q(lo, -1.0, -t),
            q(hi, -1.0, t),
        ])
    }

    /// [`Tensor::w_rows`] for a real `k`.
    #[inline]
    fn w_rows_real(&self, k: DVec3) -> [DVec3; 3] {
        let kk = k.dot(k);
        [DVec3::X, DVec3::Y, DVec3::Z].map(|a| self.eps * a + k * k.dot(a) - a * kk)
    }

    /// The indices squared `n₁² ≤ n₂²` of the two waves with real unit
    /// wave normal `u`, from the angles `θ₁`, `θ₂` between `u` and the
    /// optic axes (Born & Wolf §15.3.3): with `v = 1/n²`,
    /// `v₁,₂ = ½ [(v_α + v_γ) + (v_α − v_γ) cos(θ₁ ∓ θ₂)]`, i.e.
    /// `v₁ − v₂ = (v_α − v_γ) sin θ₁ sin θ₂` (checked against the roots of
    /// `n⁴ uᵀεu − n² uᵀBu + det ε = 0` by the tests). Unlike that
    /// quadratic's discriminant it stays accurate on and near an optic axis,
    /// where the two indices meet.
    pub fn indices_squared(&self, u: DVec3) -> [f64; 2] {
        let (c1, c2) = (u.dot(self.axes[0]), u.dot(self.axes[1]));
        let (s1, s2) = (
            u.cross(self.axes[0]).length(),
            u.cross(self.axes[1]).length(),
        );
        let (sum, diff) = (self.v_hi + self.v_lo, self.v_hi - self.v_lo);
        let v_fast = 0.5 * (sum + diff * (c1 * c2 + s1 * s2));
        let v_slow = 0.5 * (sum + diff * (c1 * c2 - s1 * s2));
        [1.0 / v_fast, 1.0 / v_slow]
    }

    /// The ray indices squared `x₁ ≤ x₂` (`x = (k·ŝ)²`) of the two waves
    /// whose ray is along the unit `s`: the roots of
    /// `Σ sᵢ²/(εᵢ − x) = 0` (principal frame), in invariant form
    /// `x² − x (tr ε − sᵀεs) + det ε · sᵀε⁻¹s = 0` (Born & Wolf §15.2.2).
    pub fn ray_indices_squared(&self, s: DVec3) -> [f64; 2] {
        let tr = self.eps.x_axis.x + self.eps.y_axis.y + self.eps.z_axis.z;
        let b = tr - s.dot(self.eps * s);
        let c = self.det * s.dot(self.eps.inverse() * s);
        let disc = (b * b - 4.0 * c).max(0.0).sqrt();
        let big = 0.5 * (b + disc);
        [c / big, big]
    }

    /// Booker's quartic coefficients `[c₀, c₁, c₂, c₃, c₄]` (of `q⁰…q⁴`)
    /// for the frame's `t` and `N` (module docs).
    pub fn quartic(&self, frame: &TangentFrame) -> [f64; 5] {
        let (t, n, tt) = (frame.t, frame.normal, frame.tt);
        let (et, en) = (self.eps * t, self.eps * n);
        let (bt, bn) = (self.b * t, self.b * n);
        let e_nn = n.dot(en);
        let e_tn = t.dot(en);
        let e_tt = t.dot(et);
        [
            e_tt * tt - t.dot(bt) + self.det,
            2.0 * (e_tn * tt - t.dot(bn)),
            e_tt + e_nn * tt - n.dot(bn),
            2.0 * e_tn,
            e_nn,
        ]
    }
}

/// `p(z)`, `p'(z)` and `p''(z)/2` of a quartic (Horner).
#[inline]
fn horner(c: &[f64; 5], z: Complex64) -> (Complex64, Complex64, Complex64) {
    let mut p = Complex64::new(c[4], 0.0);
    let mut d = Complex64::new(0.0, 0.0);
    let mut h = Complex64::new(0.0, 0.0);
    for i in (0..4).rev() {
        h = h * z + d;
        d = d * z + p;
        p = p * z + c[i];
    }
    (p, d, h)
}

/// Newton steps on a root (kept only while they reduce `|p|`).
fn polish(c: &[f64; 5], mut z: Complex64, real: bool) -> Complex64 {
    if real {
        z.im = 0.0;
    }
    // Moduli as √(re² + im²), not `norm()`'s overflow-safe `hypot` (a
    // seventh of a biaxial render's time): these values are O(1e-16…10).
    let mut pz = horner(c, z).0.norm_sqr().sqrt();
    for _ in 0..4 {
        let (p, d, _) = horner(c, z);
        if d.norm_sqr() == 0.0 {
            break;
        }
        let mut next = z - p / d;
        if real {
            next.im = 0.0;
        }
        let pn = horner(c, next).0.norm_sqr().sqrt();
        if !(pn < pz) {
            break;
        }
        z = next;
        pz = pn;
        if pz == 0.0 {
            break;
        }
    }
    z
}

/// The four complex roots of the quartic (Aberth–Ehrlich simultaneous
/// iteration), unpolished.
fn aberth(c: &[f64; 5], start: Option<[Complex64; 4]>) -> [Complex64; 4] {
    let a: [f64; 4] = [c[0] / c[4], c[1] / c[4], c[2] / c[4], c[3] / c[4]];
    let mut z = start.unwrap_or_else(|| {
        let centre = -a[3] / 4.0;
        // A radius of the order of the roots' moduli (Fujiwara's bound).
        let r = (0..4)
            .map(|i| a[i].abs().powf(1.0 / (4 - i) as f64))
            .fold(0.0, f64::max)
            .max(1e-3);
        [0, 1, 2, 3].map(|j| {
            Complex64::from_polar(r, 0.4 + std::f64::consts::FRAC_PI_2 * j as f64) + centre
        })
    });
    let mut last = f64::INFINITY;
    for _ in 0..200 {
        let mut moved = 0.0f64;
        for j in 0..4 {
            let (p, d, _) = horner(c, z[j]);
            if p.norm_sqr() == 0.0 {
                continue;
            }
            let ratio = p / d;
            let mut sum = Complex64::new(0.0, 0.0);
            for (k, zk) in z.iter().enumerate() {
                if k != j {
                    sum += (z[j] - zk).inv();
                }
            }
            let step = ratio / (Complex64::new(1.0, 0.0) - ratio * sum);
            if step.is_finite() {
                z[j] -= step;
                moved = moved.max(step.norm_sqr().sqrt() / (1.0 + z[j].norm_sqr().sqrt()));
            }
        }
        // Converged, or at the rounding floor: near a cluster of roots
        // rounding moves them by ε|p|/|p'| ≫ 1e-15 each step, and the
        // steps stop shrinking (the roots are polished afterwards).
        if moved < 1e-15 || (moved < 1e-9 && moved >= 0.5 * last) {
            break;
        }
        last = moved;
    }
    z
}

/// The roots of Booker's quartic, real ones with zero imaginary part and
/// complex ones in conjugate pairs, each polished. `singular` tells whether
/// a point `q` of the line is a singular point of the wave-vector surface
/// (`∇ det W = 0`: an optic axis, or the isotropic limit), where a cluster
/// of two roots is a pair of real roots that travel the same way.
fn roots(
    c: &[f64; 5],
    start: Option<[Complex64; 4]>,
    singular: impl Fn(f64) -> bool,
) -> [Complex64; 4] {
    let mut z = aberth(c, start);
    z.sort_by(|a, b| a.re.total_cmp(&b.re));
    let near = |a: Complex64, b: Complex64| (a - b).norm() <= CLUSTER * (1.0 + a.norm());
    let mut out = z;
    let mut done = [false; 4];
    for i in 0..4 {
        if done[i] {
            continue;
        }
        // A cluster partner: the nearest other unhandled root, if near.
        let partner = (i + 1..4)
            .filter(|&j| !done[j] && near(z[i], z[j]))
            .min_by(|&a, &b| (z[a] - z[i]).norm().total_cmp(&(z[b] - z[i]).norm()));
        let small_im = |w: Complex64| w.im.abs() <= CLUSTER * (1.0 + w.norm());
        match partner {
            Some(j) if small_im(z[i]) && small_im(z[j]) => {
                // Local model p(a + h) ≈ p + p' h + p''/2 h² about the
                // cluster's centre on the real axis.
                let a = 0.5 * (z[i].re + z[j].re);
                let (p, d, h2) = horner(c, Complex64::new(a, 0.0));
                let (p, d, h2) = (p.re, d.re, h2.re);
                let disc = d * d - 4.0 * h2 * p;
                let pair = if disc >= 0.0 || singular(a) {
                    let s = disc.max(0.0).sqrt();
                    let (h_lo, h_hi) = if h2 != 0.0 {
                        let big = -(d + d.signum() * s) / (2.0 * h2);
                        let small = if big != 0.0 { p / (h2 * big) } else { 0.0 };
                        (big.min(small), big.max(small))
                    } else {
                        (0.0, 0.0)
                    };
                    [
                        polish(c, Complex64::new(a + h_lo, 0.0), true),
                        polish(c, Complex64::new(a + h_hi, 0.0), true),
                    ]
                } else {
                    let w = polish(
                        c,
                        Complex64::new(a - d / (2.0 * h2), (-disc).sqrt() / (2.0 * h2.abs())),
                        false,
                    );
                    let w = Complex64::new(w.re, w.im.abs());
                    [w, w.conj()]
                };
                out[i] = pair[0];
                out[j] = pair[1];
                done[i] = true;
                done[j] = true;
            }
            _ => {
                if z[i].im.abs() <= REAL_TOL * (1.0 + z[i].norm()) {
                    out[i] = polish(c, z[i], true);
                    done[i] = true;
                } else {
                    // A complex root: polish it, its conjugate is the
                    // partner nearest to the conjugate.
                    let w = polish(c, z[i], false);
                    out[i] = w;
                    done[i] = true;
                    let mirror = z[i].conj();
                    if let Some(j) = (0..4)
                        .filter(|&j| !done[j])
                        .min_by(|&a, &b| (z[a] - mirror).norm().total_cmp(&(z[b] - mirror).norm()))
                    {
                        out[j] = w.conj();
                        done[j] = true;
                    }
                }
            }
        }
    }
    out
}

/// A unit null vector of the rank-2 symmetric `W` (rows `r`), or `None`
/// when `W` is of rank ≤ 1.
fn null_vector(r: &[CVec3; 3]) -> Option<CVec3> {
    let crosses = [r[0].cross(r[1]), r[0].cross(r[2]), r[1].cross(r[2])];
    let (best, l2) =
        crosses
            .iter()
            .map(|c| (*c, c.norm_sqr()))
            .fold(
                (CVec3::ZERO, -1.0),
                |acc, x| if x.1 > acc.1 { x } else { acc },
            );
    let row2 = r.iter().map(|v| v.norm_sqr()).fold(0.0, f64::max);
    if !(l2 > RANK1_TOL * row2 * row2 && l2.is_finite()) {
        return None;
    }
    // The cross product's rounding error (≈ ε σ₁/σ₂ for singular values
    // σ₁ ≥ σ₂ of W) lies mostly along the dominant row, where it costs a
    // residual σ₁ times as large; the null vector is orthogonal to every
    // row, so remove that component (near an optic axis σ₂ ≪ σ₁: measured,
    // residuals drop from 1e-11 to rounding).
    let e = best * (1.0 / l2.sqrt());
    let d = dominant_row(r);
    let dd = d.dot(d);
    let e = if dd.norm() > 0.0 {
        e - d.scale(d.dot(e) / dd)
    } else {
        e
    };
    Some(e * (1.0 / e.norm_sqr().sqrt()))
}

/// [`null_vector`] of a real `W` (rows `r`), operation for operation: the
/// same values as the complex form with zero imaginary parts (a bilinear
/// quotient `x/y` of complex numbers is `(x y)/(y y)` there, kept so).
fn null_vector_real(r: &[DVec3; 3]) -> Option<DVec3> {
    let crosses = [r[0].cross(r[1]), r[0].cross(r[2]), r[1].cross(r[2])];
    let (best, l2) =
        crosses
            .iter()
            .map(|c| (*c, c.length_squared()))
            .fold(
                (DVec3::ZERO, -1.0),
                |acc, x| if x.1 > acc.1 { x } else { acc },
            );
    let row2 = r.iter().map(|v| v.length_squared()).fold(0.0, f64::max);
    if !(l2 > RANK1_TOL * row2 * row2 && l2.is_finite()) {
        return None;
    }
    let e = best * (1.0 / l2.sqrt());
    let d = *r
        .iter()
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
        .unwrap_or(&r[0]);
    let dd = d.dot(d);
    let e = if dd.abs() > 0.0 {
        e - d * ((d.dot(e) * dd) / (dd * dd))
    } else {
        e
    };
    Some(e * (1.0 / e.length_squared().sqrt()))
}

/// The dominant row of `W` (largest Hermitian norm).
fn dominant_row(r: &[CVec3; 3]) -> CVec3 {
    *r.iter()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
        .unwrap_or(&r[0])
}

/// The two unit fields of a degenerate pair: `E₁ = s − r (r·s)/(r·r)`,
/// `E₂ = r × E₁` (module docs).
fn degenerate_pair(r: CVec3, s: DVec3) -> [CVec3; 2] {
    let rr = r.dot(r);
    let e1 = if rr.norm() > 0.0 {
        CVec3::real(s) - r.scale(r.dot_real(s) / rr)
    } else {
        CVec3::real(s)
    };
    let e1 = e1 * (1.0 / e1.norm_sqr().sqrt());
    let e2 = r.cross(e1);
    let l2 = e2.norm_sqr();
    let e2 = if l2 > 0.0 && l2.is_finite() {
        e2 * (1.0 / l2.sqrt())
    } else {
        CVec3::real(s.cross(DVec3::Z).normalize_or_zero())
    };
    [e1, e2]
}

/// Two real unit fields spanning the plane of `e1`, `e2`, rotated in it so
/// that the waves they make with the common wave vector `k` carry no cross
/// flux through the interface: the eigenvectors of the symmetric form
/// `F(a, b) = (a·b)(k·N) − ½ [(a·k)(b·N) + (b·k)(a·N)]` (`Re(E_a × H_b*)·N`
/// symmetrized, `H = k × E`) on that plane. Why: a degenerate pair's fields
/// are any basis of the null plane of `W(k)`, and the energy balance
/// `Σ |a_j|² F_j` holds only when the cross fluxes vanish (measured:
/// 7e-5 of energy with the plain basis on an optic axis). For `s` and `p`
/// of an isotropic wave the form is already diagonal.
fn flux_orthogonal(e1: DVec3, e2: DVec3, k: DVec3, n: DVec3) -> [DVec3; 2] {
    let b1 = e1.normalize_or_zero();
    let b2 = (e2 - b1 * b1.dot(e2)).normalize_or_zero();
    if b1 == DVec3::ZERO || b2 == DVec3::ZERO {
        return [e1, e2];
    }
    let kn = k.dot(n);
    let f = |a: DVec3, b: DVec3| a.dot(b) * kn - 0.5 * (a.dot(k) * b.dot(n) + b.dot(k) * a.dot(n));
    let (m11, m22, m12) = (f(b1, b1), f(b2, b2), f(b1, b2));
    let theta = 0.5 * (2.0 * m12).atan2(m11 - m22);
    let (c, s) = (theta.cos(), theta.sin());
    [b1 * c + b2 * s, b2 * c - b1 * s]
}

/// One root with its field, before it is named.
#[derive(Clone, Copy, Debug)]
struct Root {
    q: Complex64,
    k: CVec3,
    e: CVec3,
    evanescent: bool,
}

impl Root {
    /// `Re(E × H*)·N / 2` with `H = k × E`.
    fn flux(&self, n: DVec3) -> f64 {
        let h = self.k.cross(self.e);
        0.5 * self.e.cross(h.conj()).re.dot(n)
    }

    /// How strongly this root leaves into side σ: `σ Im q` scaled far above
    /// any flux for an evanescent root, `σ F / |k|` for a propagating one.
    fn out_score(&self, sigma: f64, n: DVec3) -> f64 {
        if self.evanescent {
            sigma * self.q.im.signum() * 1e30
        } else {
            sigma * self.flux(n) / (1.0 + self.k.re.length())
        }
    }
}

/// The four eigenwaves of an anisotropic medium on `side` for the frame's
/// tangential component: `outgoing` (fast first, module docs) and
/// `incoming` (the two roots arriving at the interface, fast first;
/// evanescent ones among them do not exist as incident waves).
#[derive(Clone, Copy, Debug)]
pub struct Waves {
    pub outgoing: [Eigenwave; 2],
    pub incoming: [Eigenwave; 2],
}

/// [`Waves`] of `medium` (any medium; the general path) on `side`.
pub fn waves(medium: &Medium, frame: &TangentFrame, side: Side) -> Waves {
    // Nearly isotropic media: the exact plane form (its module docs).
    if let Some(pf) = PlaneForm::of(medium) {
        if let Some((outgoing, incoming)) = near_isotropic::waves(&pf, frame, side) {
            return Waves { outgoing, incoming };
        }
    }
    let tensor = Tensor::of(medium);
    let c = tensor.quartic(frame);
    let n = frame.normal;
    // ∇ det W(k) = 2 (kᵀεk) k + 2 (k·k) ε k − 2 B k, small against its
    // scale only at singular points of the surface.
    let singular = |q: f64| {
        let k = frame.t + n * q;
        let ek = tensor.eps * k;
        let g = k * k.dot(ek) + ek * k.length_squared() - tensor.b * k;
        let scale = (k.length_squared() + tensor.eps.x_axis.length()).powi(2) * k.length().max(1.0);
        g.length() <= 1e-3 * scale
    };
    let qs = roots(&c, tensor.starts(frame), singular);
    let mut rs: [Root; 4] = qs.map(|q| {
        let (q, k, e) = refine(&tensor, frame, q);
        Root {
            q,
            k,
            e,
            evanescent: q.im != 0.0,
        }
    });
    // Energy rule: the two roots with the largest σ S·N leave side σ.
    let sigma = side.sign();
    let mut order = [0usize, 1, 2, 3];
    let scores = rs.map(|r| r.out_score(sigma, n));
    order.sort_by(|&a, &b| scores[b].total_cmp(&scores[a]));
    let (out_idx, in_idx) = ([order[0], order[1]], [order[2], order[3]]);
    // Degenerate pairs share the two-dimensional null space at their centre.
    for pair in [out_idx, in_idx] {
        let (a, b) = (rs[pair[0]], rs[pair[1]]);
        let close = (a.k - b.k).norm_sqr() <= (DEGENERATE * (1.0 + a.k.norm_sqr().sqrt())).powi(2);
        if close && !a.evanescent && !b.evanescent {
            let centre = (a.k + b.k) * 0.5;
            let [e1, e2] = degenerate_pair(dominant_row(&tensor.w_rows(centre)), frame.s);
            let [e1, e2] = flux_orthogonal(e1.re, e2.re, centre.re, n);
            rs[pair[0]].e = CVec3::real(e1);
            rs[pair[1]].e = CVec3::real(e2);
        }
    }
    let make = |i: usize, travel: Travel| {
        let r = rs[i];
        let h = r.k.cross(r.e);
        let p = r.e.cross(h.conj()).re;
        let l = p.length();
        let ray = if l > 0.0 && l.is_finite() {
            p / l
        } else {
            DVec3::ZERO
        };
        let mode = if !r.evanescent && l > 0.0 && is_fast(&tensor, r.k.re, p / l) {
            Mode::Fast
        } else {
            Mode::Slow
        };
        Eigenwave {
            side,
            mode,
            travel,
            k: r.k,
            q: r.q,
            ray,
            e: r.e,
            h,
            flux: if r.evanescent { 0.0 } else { 0.5 * p.dot(n) },
            evanescent: r.evanescent,
        }
    };
    let named = |idx: [usize; 2], travel: Travel| {
        let mut w = idx.map(|i| make(i, travel));
        // An evanescent wave takes the name its propagating partner does
        // not have; two evanescent waves are named by their place.
        match (w[0].evanescent, w[1].evanescent) {
            (true, true) => {
                w[0].mode = Mode::Fast;
                w[1].mode = Mode::Slow;
            }
            (true, false) => w[0].mode = other(w[1].mode),
            (false, true) => w[1].mode = other(w[0].mode),
            (false, false) => {}
        }
        // Fast first.
        if w[0].mode == Mode::Slow && w[1].mode == Mode::Fast {
            w.swap(0, 1);
        }
        w
    };
    Waves {
        outgoing: named(out_idx, Travel::Outgoing),
        incoming: named(in_idx, Travel::Incoming),
    }
}

/// The other name of a biaxial wave.
fn other(mode: Mode) -> Mode {
    if mode == Mode::Fast {
        Mode::Slow
    } else {
        Mode::Fast
    }
}

/// A root of the quartic refined on its own sheet, with its field: Newton
/// steps on the Rayleigh functional `f(q) = Eᵀ W(q) E / (Eᵀ E)` (bilinear),
/// `E` the null vector at the current `q`, with
/// `f'(q) = (2 (k·E)(N·E) − 2 (k·N)(E·E)) / (Eᵀ E)` (`−4 F` for a unit real
/// field: the flux). Why: the quartic's coefficients cancel (`c₀` is a
/// difference of terms of order `n⁶`), so near another root a root of the
/// rounded quartic is off by `ε n⁶ / |p'(q)|` (measured: 3e-11, and 3e-9
/// of energy, 4e-4 from the other root); `f` is evaluated from entries of
/// order `n²` and its slope does not vanish where the other sheet's root is
/// near. Steps larger than `CLUSTER` (relative) are refused: this only
/// polishes.
fn refine(tensor: &Tensor, frame: &TangentFrame, q0: Complex64) -> (Complex64, CVec3, CVec3) {
    let n = frame.normal;
    let k_of = |q: Complex64| CVec3::new(frame.t + n * q.re, n * q.im);
    let field_at = |k: CVec3| {
        // A real k (a propagating root): the same arithmetic on real rows,
        // a quarter of the operations.
        if k.is_real() {
            if let Some(e) = null_vector_real(&tensor.w_rows_real(k.re)) {
                return (CVec3::real(e), true);
            }
        }
        let rows = tensor.w_rows(k);
        null_vector(&rows).map_or_else(
            || (degenerate_pair(dominant_row(&rows), frame.s)[0], false),
            |e| (e, true),
        )
    };
    let mut q = q0;
    let mut k = k_of(q);
    let (mut e, mut unique) = field_at(k);
    for _ in 0..4 {
        if !unique {
            break;
        }
        let ee = e.dot(e);
        let num = if q.im == 0.0 {
            // Real roots: f(q) in double-double (near grazing f' = −4F is
            // small, and ε n² of rounding in f would move q by ε n²/F).
            Complex64::new(rayleigh_dd(tensor, frame, q.re, e.re), 0.0)
        } else {
            e.dot(tensor.w_times(k, e))
        };
        let kn = k.dot_real(n);
        let den = (k.dot(e) * e.dot_real(n) - kn * ee) * 2.0;
        if den.norm_sqr() == 0.0 {
            break;
        }
        let mut step = num / den;
        if q.im == 0.0 {
            step.im = 0.0;
        }
        if !(step.norm_sqr().sqrt() <= CLUSTER * (1.0 + q.norm_sqr().sqrt())) {
            break;
        }
        // Converged: a step below half an ulp leaves q (and so k and E)
        // as they are, and every further step would be the same.
        let next = q - step;
        if next == q {
            break;
        }
        q = next;
        k = k_of(q);
        (e, unique) = field_at(k);
        // Newton converges quadratically: after a step of this size the
        // next one is below rounding (a confirming step moved q in 7 % of
        // roots, by an ulp or two).
        if step.norm_sqr().sqrt() <= CONFIRMED * (1.0 + q.norm_sqr().sqrt()) {
            break;
        }
    }
    (q, k, e)
}

/// A relative Newton step in [`refine`] after which the root needs no
/// confirming step.
const CONFIRMED: f64 = 1e-12;

/// `Eᵀ W(t + q N) E` for a real `q` and field, in double-double from the
/// f64 inputs (`ε`, `t`, `N`, `q`, `E`): every wave of one medium and one
/// `t` is then an eigenmode of the same (f64) tensor, to ~ε² n².
fn rayleigh_dd(tensor: &Tensor, frame: &TangentFrame, q: f64, e: DVec3) -> f64 {
    let (t, n) = (frame.t.to_array(), frame.normal.to_array());
    let e = e.to_array();
    let k: [Dd; 3] = [0, 1, 2].map(|i| Dd::prod(q, n[i]).add_f64(t[i]));
    let de = |x: f64| Dd { hi: x, lo: 0.0 };
    let dot_ke = k[0]
        .mul_dd(de(e[0]))
        .add(k[1].mul_dd(de(e[1])))
        .add(k[2].mul_dd(de(e[2])));
    let kk = k[0]
        .mul_dd(k[0])
        .add(k[1].mul_dd(k[1]))
        .add(k[2].mul_dd(k[2]));
    let eps = tensor.eps.to_cols_array_2d();
    let mut sum = Dd { hi: 0.0, lo: 0.0 };
    for i in 0..3 {
        // (W E)_i = Σ_j ε_ij E_j + k_i (k·E) − (k·k) E_i
        let mut wi = Dd::prod(eps[0][i], e[0])
            .add(Dd::prod(eps[1][i], e[1]))
            .add(Dd::prod(eps[2][i], e[2]));
        wi = wi.add(k[i].mul_dd(dot_ke)).sub(kk.mul_dd(de(e[i])));
        sum = sum.add(wi.mul_dd(de(e[i])));
    }
    sum.value()
}

/// True when the wave of real wave vector `k` and unit ray `s` lies on the
/// fast sheet of the ray surface: its ray index squared `(k·s)²` nearer the
/// smaller root of [`Tensor::ray_indices_squared`]. Named by the ray
/// surface, not the index surface: near an optic axis the outer index
/// sheet has a dimple where two of its wave vectors share one ray
/// direction (on different ray sheets), and the backward query finds a
/// wave from its ray and name ([`k_from_ray`]), which is one-to-one only
/// on the ray surface.
fn is_fast(tensor: &Tensor, k: DVec3, s: DVec3) -> bool {
    let x = k.dot(s).powi(2);
    let [x1, x2] = tensor.ray_indices_squared(s);
    (x - x1).abs() <= (x - x2).abs()
}

/// The sheet (0 fast, 1 slow) of a wave kind of an anisotropic medium.
fn sheet_index(kind: WaveKind) -> usize {
    match kind {
        WaveKind::Slow => 1,
        _ => 0,
    }
}

/// The wave vector of the `kind` wave (fast or slow) with wave normal along
/// `dir`: `n d̂` with `n²` the index of that sheet.
pub fn k_from_wave_normal(medium: &Medium, kind: WaveKind, dir: DVec3) -> DVec3 {
    let d = dir.normalize();
    let n2 = Tensor::of(medium).indices_squared(d)[sheet_index(kind)];
    d * n2.sqrt()
}

/// The unit field `E` of the real wave vector `k` (on either sheet), and
/// whether it is unique (`false` on an optic axis).
fn real_field(tensor: &Tensor, k: DVec3) -> (DVec3, bool) {
    let rows = tensor.w_rows(CVec3::real(k));
    match null_vector(&rows) {
        Some(e) => (e.re.normalize_or_zero(), true),
        None => {
            let s = k.any_orthonormal_vector();
            (degenerate_pair(dominant_row(&rows), s)[0].re, false)
        }
    }
}

/// The unit ray (energy) direction of the real wave vector `k`:
/// `S ∝ E × (k × E) = (E·E) k − (E·k) E`. On an optic axis, where the
/// rays of the degenerate pair fill a cone, this is `k̂`.
pub fn ray_direction(medium: &Medium, k: DVec3) -> DVec3 {
    let (e, unique) = match PlaneForm::of(medium) {
        Some(pf) => near_isotropic::real_field(&pf, k),
        None => real_field(&Tensor::of(medium), k),
    };
    if !unique {
        return k.normalize();
    }
    (k * e.length_squared() - e * e.dot(k)).normalize()
}

/// The wave vector of the `kind` wave whose ray (energy) direction is along
/// `ray`: the ray index `n_r² = x` solves `Σ ŝᵢ²/(εᵢ − x) = 0` in the
/// principal frame, `D` spans the null space of `ε⁻¹ − (I − ŝŝᵀ)/x`
/// (Born & Wolf §15.2.2, the ray form of Fresnel's equation), and `k`
/// is along `D × (E × ŝ)` with `k·ŝ = n_r`. Nearly isotropic media take the
/// exact ray form on the plane of `E` ([`near_isotropic::k_from_ray`]).
pub fn k_from_ray(medium: &Medium, kind: WaveKind, ray: DVec3) -> DVec3 {
    let s = ray.normalize();
    if let Some(pf) = PlaneForm::of(medium) {
        return near_isotropic::k_from_ray(&pf, sheet_index(kind), s);
    }
    let tensor = Tensor::of(medium);
    let inv = tensor.eps.inverse();
    let x = tensor.ray_indices_squared(s)[sheet_index(kind)];
    // Null space of ε⁻¹ − (I − ŝŝᵀ)/x (real symmetric).
    let m = inv - (DMat3::IDENTITY - super::medium::outer(s, s)) * (1.0 / x);
    let rows = [m.row(0), m.row(1), m.row(2)].map(CVec3::real);
    let d = match null_vector(&rows) {
        Some(d) => d.re,
        // A ray axis: any D of the plane; the plane of the dominant row.
        None => degenerate_pair(dominant_row(&rows), s.any_orthonormal_vector())[0].re,
    };
    let e = inv * d;
    let dir = d.cross(e.cross(s));
    let l = dir.length();
    let k_hat = if l > 0.0 && l.is_finite() {
        let v = dir / l;
        if v.dot(s) < 0.0 {
            -v
        } else {
            v
        }
    } else {
        s
    };
    k_hat * (x.sqrt() / k_hat.dot(s))
}

/// The half-angle `V` between each optic axis (wave normals of equal
/// index) and the principal axis of the largest index, in radians, for
/// principal indices `n` in any order: the optic axes are the normals of
/// the indicatrix's circular sections, `sin² V = (1/n_α² − 1/n_β²) /
/// (1/n_α² − 1/n_γ²)` (Born & Wolf §15.3.3). `None` when all three are
/// equal (isotropic: every direction is an optic axis).
pub fn half_optic_angle(n: [f64; 3]) -> Option<f64> {
    let mut s = n;
    s.sort_by(f64::total_cmp);
    let [a, b, g] = s.map(|x| 1.0 / (x * x));
    if a == g {
        return None;
    }
    Some(((a - b) / (a - g)).clamp(0.0, 1.0).sqrt().asin())
}

/// The unit optic axes (wave normals) of a biaxial medium in the interface
/// frame: in the plane of the smallest and largest principal indices, at
/// `±V` from the axis of the largest ([`half_optic_angle`]). `None` for an
/// isotropic or uniaxial medium's [`Medium::Biaxial`] form with all three
/// indices equal, and for other media.
pub fn optic_axes(medium: &Medium) -> Option<[DVec3; 2]> {
    let Medium::Biaxial { n, x, z } = *medium else {
        return None;
    };
    let v = half_optic_angle(n)?;
    let axes = [x, z.cross(x), z];
    let lo = (0..3).min_by(|&a, &b| n[a].total_cmp(&n[b]))?;
    let hi = (0..3).rev().max_by(|&a, &b| n[a].total_cmp(&n[b]))?;
    let (a_lo, a_hi) = (axes[lo], axes[hi]);
    Some([
        a_hi * v.cos() + a_lo * v.sin(),
        a_hi * v.cos() - a_lo * v.sin(),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [−1, 1) from a 64-bit LCG (Knuth's MMIX
    /// constants): reproducible cases without a dependency.
    fn lcg(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// Case `i` of a random biaxial solve: topaz-like indices (even `i`) or
    /// any in [1.3, 1.9], random crystal axes, normal and tangential
    /// component (up to `t_scale` per coordinate).
    fn random_solve(r: &mut impl FnMut() -> f64, i: usize, t_scale: f64) -> (Tensor, TangentFrame) {
        let n = if i % 2 == 0 {
            [1.6093, 1.6116, 1.6194]
        } else {
            [0, 1, 2].map(|_| 1.3 + 0.6 * (r() + 1.0))
        };
        let m = Medium::biaxial(n, DVec3::new(r(), r(), r()), DVec3::new(r(), r(), r())).unwrap();
        let normal = DVec3::new(r(), r(), r()).normalize();
        let frame = TangentFrame::new(normal, DVec3::new(r(), r(), r()) * t_scale);
        (Tensor::of(&m), frame)
    }

    #[test]
    fn bookers_quartic_is_the_determinant_of_w() {
        // det W(t + qN) as a 3×3 determinant at several q, against the
        // quartic's coefficients.
        let m = Medium::biaxial([1.5, 1.7, 2.1], DVec3::new(0.3, 0.4, 0.8), DVec3::X).unwrap();
        let tensor = Tensor::of(&m);
        let normal = DVec3::new(0.2, -0.3, 0.9).normalize();
        let frame = TangentFrame::new(normal, DVec3::new(0.6, 0.5, 0.1));
        let c = tensor.quartic(&frame);
        for q in [-2.0, -0.7, 0.0, 0.4, 1.3] {
            let k = frame.t + normal * q;
            let w = tensor.eps + super::super::medium::outer(k, k)
                - DMat3::IDENTITY * k.length_squared();
            let p: f64 = (0..5).map(|i| c[i] * q.powi(i as i32)).sum();
            assert!((w.determinant() - p).abs() < 1e-12 * (1.0 + p.abs()), "{q}");
        }
    }

    #[test]
    fn the_real_null_vector_is_the_complex_one_bit_for_bit() {
        // W(k) of real wave vectors near and on the wave surfaces of a
        // topaz-like medium (rank 2) and of an isotropic one on its sphere
        // (rank 1: no unique null vector, `None` from both forms).
        let topaz = Medium::biaxial(
            [1.6093, 1.6116, 1.6194],
            DVec3::new(0.3, 0.5, 0.8),
            DVec3::X,
        )
        .unwrap();
        let glass = Medium::Isotropic { n: 1.5 };
        let mut r = lcg(7);
        let (mut some, mut none) = (0, 0);
        for i in 0..4000 {
            let u = DVec3::new(r(), r(), r()).normalize();
            let (medium, n) = if i % 4 == 3 {
                (glass, 1.5)
            } else {
                let tensor = Tensor::of(&topaz);
                (topaz, tensor.indices_squared(u)[i % 2].sqrt())
            };
            let tensor = Tensor::of(&medium);
            let k = if i % 4 == 3 {
                u * n
            } else {
                u * n * (1.0 + 1e-9 * r())
            };
            let real = null_vector_real(&tensor.w_rows_real(k));
            let complex = null_vector(&tensor.w_rows(CVec3::real(k)));
            match (real, complex) {
                (Some(a), Some(b)) => {
                    assert_eq!(a.to_array(), b.re.to_array(), "{k}");
                    assert_eq!(b.im.length_squared(), 0.0);
                    some += 1;
                }
                (None, None) => none += 1,
                other => panic!("{k}: {other:?}"),
            }
        }
        assert!(some > 2000 && none > 500, "{some} {none}");
    }

    #[test]
    fn roots_from_the_index_starts_are_the_roots_from_the_circle() {
        // The quartic's roots found from the extreme indices' starts
        // (`Tensor::starts`) and from Aberth's usual circle, each refined on
        // W(k): the same four roots, propagating and evanescent, for
        // topaz-like and strongly biaxial media at every incidence.
        let mut r = lcg(99);
        let (mut worst, mut complex) = (0.0f64, 0);
        for i in 0..20_000 {
            let (tensor, frame) = random_solve(&mut r, i, 2.0);
            let c = tensor.quartic(&frame);
            let key = |z: &Complex64| ((z.re * 1e6).round() as i64, (z.im * 1e6).round() as i64);
            let solve = |start| roots(&c, start, |_| false).map(|q| refine(&tensor, &frame, q).0);
            let (mut a, mut b) = (solve(None), solve(tensor.starts(&frame)));
            a.sort_by_key(key);
            b.sort_by_key(key);
            for (x, y) in a.iter().zip(&b) {
                worst = worst.max((x - y).norm() / (1.0 + x.norm()));
                complex += usize::from(x.im != 0.0);
            }
        }
        assert!(complex > 10_000, "{complex}");
        assert!(worst < 1e-12, "{worst}");
    }

    #[test]
    fn refined_real_roots_are_fixed_points_of_the_double_double_step() {
        // `refine` may stop after a small step without a confirming one;
        // the root it returns must be where a further Newton step on the
        // double-double Rayleigh quotient (with the field at that root)
        // moves it by rounding only, for every propagating root of random
        // topaz-like and strongly biaxial media.
        let mut r = lcg(5);
        let (mut worst, mut count) = (0.0f64, 0);
        for i in 0..20_000 {
            let (tensor, frame) = random_solve(&mut r, i, 1.2);
            let normal = frame.normal;
            let c = tensor.quartic(&frame);
            for q0 in roots(&c, tensor.starts(&frame), |_| false) {
                let (q, k, e) = refine(&tensor, &frame, q0);
                if q.im != 0.0 || !e.is_real() {
                    continue;
                }
                let f = rayleigh_dd(&tensor, &frame, q.re, e.re);
                let slope =
                    2.0 * (k.re.dot(e.re) * e.re.dot(normal) - k.re.dot(normal) * e.re.dot(e.re));
                // Away from grazing, where the slope (−4 × the flux) is
                // not small: there a step's rounding is ε n²/|f'|.
                if slope.abs() < 0.1 {
                    continue;
                }
                worst = worst.max((f / slope).abs() / (f64::EPSILON * (1.0 + q.re.abs())));
                count += 1;
            }
        }
        assert!(count > 20_000, "{count}");
        assert!(worst <= 4.0, "a further step of {worst} ulps");
    }
}
