//! The eigenwaves of a nearly isotropic biaxial medium (three principal
//! indices within [`NEAR_ISOTROPIC`] of each other, down to all equal)
//! from the wave-normal form of Fresnel's equation on the plane of `D`
//! (docs/physics.md §4.8, "Nearly isotropic media"; Born & Wolf §15.2.3).
//!
//! Booker's quartic ([`super::anisotropic`]) has two nearly double roots on
//! each side there, which f64 separates only to `√ε`, and `W(k)` is of
//! rank one to within the anisotropy, so its null vectors are noise. Here
//! instead, with `η = ε⁻¹ = η₀ I + Δη` (`η₀ = 1/n_β²`, `Δη` formed from the
//! index differences, so it keeps its relative accuracy however small it
//! is), `D` of a wave `k = t + q N` is orthogonal (bilinearly) to `k`, and
//! on the basis `s = unit(t × N)`, `w = (q û − T N)/√(k·k)` of that plane
//! (`t = T û`, `s·w = 0`, `w·w = 1`) Maxwell's equations are exactly
//!
//! ```text
//! (k·k) (η₀ + μ) = 1,   μ an eigenvalue of G = [[sᵀΔη s, sᵀΔη w], [wᵀΔη s, wᵀΔη w]],
//! ```
//!
//! `D = c₀ s + c₁ w` (its eigenvector), `E = η D`, `H = k × E`. Each of the
//! two eigenvalue branches gives one root per direction, found by Newton's
//! method from the isotropic root (`dμ/dq = cᵀ G' c / cᵀc`, `dw/dq =
//! T k / (k·k)^{3/2}`). The fast wave is the branch of the larger `μ`.
//! Where the two branches meet (an optic axis; every direction when the
//! indices are equal) `G`'s eigenvectors are known only to
//! `ε |Δη| / |μ₊ − μ₋|`; the pair is then made flux-orthogonal
//! (`B(ψ₂, ψ₁) = 0`, the cross term of the normal energy flux), which
//! keeps energy bookkeeping exact while moving the field by no more than
//! that error times the pair's small splitting.
//!
//! Each branch's root starts from its own estimate at grazing, so waves
//! near grazing (where one branch propagates and the other is already
//! evanescent) are found too.
//!
//! The backward query finds a wave again from its ray ([`k_from_ray`]):
//! there the dual, ray form on the plane of `E` ([`ray_sheets`]) is exact
//! where the ray quadratic separates its roots only to `√ε`.

use super::linalg::CVec3;
use super::medium::{outer, Medium};
use super::modes::{Dd, Eigenwave, Mode, Side, TangentFrame, Travel};
use glam::{DMat3, DVec3};
use num_complex::Complex64 as C;

/// The largest relative spread of the principal indices,
/// `(n_max − n_min)/n_min`, for which the waves come from this module.
/// Booker's quartic conserves energy to 1.5e-11 at 1e-4 (measured on
/// random cases) and loses it below; this form is exact at any spread
/// (Newton's iteration contracts by ~`|Δη| n²/q²`).
pub const NEAR_ISOTROPIC: f64 = 1e-3;

/// `η = η₀ I + Δη` of a nearly isotropic biaxial medium.
#[derive(Clone, Copy, Debug)]
pub struct PlaneForm {
    pub eta0: f64,
    pub d_eta: DMat3,
    /// `ε = ε₀ I + Δε` likewise (`ε₀ = n_β²`): the ray form's tensor.
    pub eps0: f64,
    pub d_eps: DMat3,
    /// `max |Δη_i|` (its principal values).
    pub spread: f64,
}

impl PlaneForm {
    /// The form of `medium` when it is biaxial and nearly isotropic.
    pub fn of(medium: &Medium) -> Option<PlaneForm> {
        let Medium::Biaxial { n, x, z } = *medium else {
            return None;
        };
        let mut s = n;
        s.sort_by(f64::total_cmp);
        if !((s[2] - s[0]) <= NEAR_ISOTROPIC * s[0]) {
            return None;
        }
        let nb = s[1];
        let axes = [x, z.cross(x), z];
        let mut d_eta = DMat3::ZERO;
        let mut d_eps = DMat3::ZERO;
        let mut spread = 0.0f64;
        for i in 0..3 {
            // 1/n_i² − 1/n_β² and n_i² − n_β², from the difference of the
            // indices (exact in f64 for close indices).
            let di = (nb - n[i]) * (nb + n[i]) / (n[i] * n[i] * nb * nb);
            d_eta += outer(axes[i], axes[i]) * di;
            d_eps += outer(axes[i], axes[i]) * ((n[i] - nb) * (n[i] + nb));
            spread = spread.max(di.abs());
        }
        Some(PlaneForm {
            eta0: 1.0 / (nb * nb),
            d_eta,
            eps0: nb * nb,
            d_eps,
            spread,
        })
    }

    fn d_eta_c(&self, v: CVec3) -> CVec3 {
        CVec3::new(self.d_eta * v.re, self.d_eta * v.im)
    }
}

/// `G`, `w`, `k` and `k·k` at a root candidate `q`.
struct Point {
    k: CVec3,
    kk: C,
    w: CVec3,
    g: [C; 3],
}

fn point(pf: &PlaneForm, frame: &TangentFrame, q: C) -> Point {
    let (n, u, s) = (frame.normal, frame.u, frame.s);
    let big_t = frame.tt.sqrt();
    let k = CVec3::new(frame.t + n * q.re, n * q.im);
    let kk = q * q + frame.tt;
    let w = CVec3::new(u * q.re - n * big_t, u * q.im).scale(kk.sqrt().inv());
    let ds = pf.d_eta * s;
    let dw = pf.d_eta_c(w);
    Point {
        k,
        kk,
        w,
        g: [C::new(s.dot(ds), 0.0), w.dot_real(ds), w.dot(dw)],
    }
}

/// The eigenvalues of the symmetric `[[a, b], [b, d]]`: `m ± √((a−d)²/4 + b²)`.
fn eigenvalues(g: &[C; 3]) -> [C; 2] {
    let m = (g[0] + g[2]) * 0.5;
    let h = (g[0] - g[2]) * 0.5;
    let r = (h * h + g[1] * g[1]).sqrt();
    [m + r, m - r]
}

/// An eigenvector of `g` for eigenvalue `mu` (the larger of the two
/// formulas), or `None` when both vanish (`g = μ I`).
fn eigenvector(g: &[C; 3], mu: C) -> Option<[C; 2]> {
    let v1 = [g[1], mu - g[0]];
    let v2 = [mu - g[2], g[1]];
    let n = |v: &[C; 2]| v[0].norm_sqr() + v[1].norm_sqr();
    let v = if n(&v1) >= n(&v2) { v1 } else { v2 };
    let l = n(&v).sqrt();
    (l > 0.0 && l.is_finite()).then(|| [v[0] / l, v[1] / l])
}

/// One root of branch `mu0` (the eigenvalue it starts nearest) in direction
/// `sigma` (`+1`: `Re q > 0` when propagating, `Im q > 0` when evanescent).
struct Found {
    q: C,
    mu: C,
    c: Option<[C; 2]>,
    p: Point,
}

fn root(pf: &PlaneForm, frame: &TangentFrame, q0: C, branch: usize) -> Option<Found> {
    let big_t = frame.tt.sqrt();
    let r_t = Dd::dot(frame.t, frame.t)
        .mul_dd(Dd {
            hi: pf.eta0,
            lo: 0.0,
        })
        .add_f64(-1.0)
        .value();
    let tn = frame.t.dot(frame.normal);
    let mut q = q0;
    let mut p = point(pf, frame, q);
    let mut mu = eigenvalues(&p.g)[branch];
    let mut last = f64::INFINITY;
    for _ in 0..60 {
        // Follow the branch: the eigenvalue nearest the last one.
        let [m1, m2] = eigenvalues(&p.g);
        mu = if (m1 - mu).norm() <= (m2 - mu).norm() {
            m1
        } else {
            m2
        };
        // g = (k·k)(η₀ + μ) − 1 with its cancelling part t·t η₀ − 1 in
        // double-double (near grazing g' ∝ q is small and f64 rounding of
        // n² would move q by ε n²/q).
        let g = (q * q + q * (2.0 * tn)) * pf.eta0 + r_t + p.kk * mu;
        // dμ/dq by Hellmann–Feynman on the bilinear form; G' from w'.
        let dmu = match eigenvector(&p.g, mu) {
            Some(c) if big_t > 0.0 => {
                let dw = p.k.scale(p.kk.powf(-1.5) * big_t);
                let ds_dw = dw.dot_real(pf.d_eta * frame.s);
                let dw_dw = p.w.dot(pf.d_eta_c(dw)) * 2.0;
                let cc = c[0] * c[0] + c[1] * c[1];
                if cc.norm() > 1e-3 {
                    (c[0] * c[1] * ds_dw * 2.0 + c[1] * c[1] * dw_dw) / cc
                } else {
                    C::new(0.0, 0.0)
                }
            }
            _ => C::new(0.0, 0.0),
        };
        let dg = q * (mu + pf.eta0) * 2.0 + p.kk * dmu;
        if !(dg.norm() > 0.0) {
            return None;
        }
        let step = g / dg;
        if !step.is_finite() {
            return None;
        }
        // Converged: a step at rounding level, or one that no longer
        // shrinks once small (rounding noise in g).
        let size = step.norm() / (1.0 + q.norm());
        let done = size <= 16.0 * f64::EPSILON || (size >= last && size <= 1e-10);
        last = size;
        if !done {
            q -= step;
            if q0.im == 0.0 {
                q.im = 0.0;
            }
            p = point(pf, frame, q);
        }
        if done {
            let [m1, m2] = eigenvalues(&p.g);
            mu = if (m1 - mu).norm() <= (m2 - mu).norm() {
                m1
            } else {
                m2
            };
            let c = eigenvector(&p.g, mu);
            return Some(Found { q, mu, c, p });
        }
    }
    None
}

/// The wave of a found root with plane coordinates `c` of `D`.
fn wave(pf: &PlaneForm, frame: &TangentFrame, f: &Found, c: [C; 2]) -> (CVec3, CVec3) {
    let d = CVec3::real(frame.s).scale(c[0]) + f.p.w.scale(c[1]);
    let e = d * pf.eta0 + pf.d_eta_c(d);
    let e = e * (1.0 / e.norm_sqr().sqrt());
    (e, f.p.k.cross(e))
}

/// `B(a, b) = ¼ [(E_a × H_b*) + (E_b* × H_a)]·N`: the Hermitian form whose
/// diagonal is the normal flux `Re(E × H*)·N / 2`.
fn cross_flux(a: (CVec3, CVec3), b: (CVec3, CVec3), n: DVec3) -> C {
    (a.0.cross(b.1.conj()) + b.0.conj().cross(a.1)).dot_real(n) * 0.25
}

/// The root of branch `j` in direction `sigma`: started from the branch's
/// own isotropic estimate `ρ_j = (1 − T² (η₀ + μ_j)) / (η₀ + μ_j)` (`μ_j`
/// at grazing, `q = 0`), on the real axis when `ρ_j > 0` and on the
/// imaginary one otherwise, then the other if that fails (within
/// `~|Δη|` of grazing the estimate can pick the wrong one).
fn branch_root(pf: &PlaneForm, frame: &TangentFrame, j: usize, sigma: f64) -> Option<Found> {
    // μ_j at grazing (at normal incidence, where k·k would vanish there,
    // at any q: w is then û for every q).
    let q_ref = if frame.tt > 1e-200 { 0.0 } else { 1.0 };
    let p0 = point(pf, frame, C::new(q_ref, 0.0));
    let mu = eigenvalues(&p0.g)[j].re;
    let eta = pf.eta0 + mu;
    let rho = (1.0 - frame.tt * eta) / eta;
    let real = C::new(sigma * rho.abs().sqrt(), 0.0);
    let imag = C::new(0.0, sigma * rho.abs().sqrt());
    let tries = if rho > 0.0 {
        [real, imag]
    } else {
        [imag, real]
    };
    tries.into_iter().find_map(|q0| {
        let f = root(pf, frame, q0, j)?;
        // Real roots travel along σ, complex ones decay into σ.
        let ok = if f.q.im == 0.0 {
            sigma * f.q.re > 0.0
        } else {
            sigma * f.q.im > 0.0
        };
        ok.then_some(f)
    })
}

/// The outgoing and incoming waves (each pair fast first) of a nearly
/// isotropic medium on `side`, or `None` when an iteration fails (the
/// caller then uses the quartic). Fast is the branch of the larger `μ`
/// (smaller index): with one wave of the pair evanescent, the fast one.
pub fn waves(
    pf: &PlaneForm,
    frame: &TangentFrame,
    side: Side,
) -> Option<([Eigenwave; 2], [Eigenwave; 2])> {
    let n = frame.normal;
    let pair = |sigma: f64| -> Option<[Eigenwave; 2]> {
        let mut found = [
            branch_root(pf, frame, 0, sigma)?,
            branch_root(pf, frame, 1, sigma)?,
        ];
        let evanescent = found.each_ref().map(|f| f.q.im != 0.0);
        if evanescent == [false, false] && found[1].mu.re > found[0].mu.re {
            found.swap(0, 1);
        }
        // Plane coordinates of D: the eigenvectors, or where the branches
        // meet (no eigenvector) s and w.
        let cs = match (found[0].c, found[1].c) {
            (Some(a), Some(b)) => [a, b],
            _ => [
                [C::new(1.0, 0.0), C::new(0.0, 0.0)],
                [C::new(0.0, 0.0), C::new(1.0, 0.0)],
            ],
        };
        let mut f0 = wave(pf, frame, &found[0], cs[0]);
        let mut f1 = wave(pf, frame, &found[1], cs[1]);
        if evanescent == [false, false] {
            // Flux-orthogonal pair: remove from the wave with the smaller
            // flux its cross term with the other.
            let (b00, b11) = (cross_flux(f0, f0, n).re, cross_flux(f1, f1, n).re);
            let swap = b11.abs() > b00.abs();
            let (a, b) = if swap { (f1, f0) } else { (f0, f1) };
            let coef = cross_flux(b, a, n) / cross_flux(a, a, n).re;
            let k_b = if swap { found[0].p.k } else { found[1].p.k };
            let e = b.0 - a.0.scale(coef);
            let e = e * (1.0 / e.norm_sqr().sqrt());
            let b = (e, k_b.cross(e));
            if swap {
                f0 = b;
            } else {
                f1 = b;
            }
        }
        let travel = if sigma == side.sign() {
            Travel::Outgoing
        } else {
            Travel::Incoming
        };
        let make = |f: &Found, (e, h): (CVec3, CVec3), mode: Mode| {
            let evanescent = f.q.im != 0.0;
            let p = e.cross(h.conj()).re;
            let l = p.length();
            let ray = if l > 0.0 && l.is_finite() {
                p / l
            } else {
                DVec3::ZERO
            };
            Eigenwave {
                side,
                mode,
                travel,
                k: f.p.k,
                q: f.q,
                ray,
                e,
                h,
                flux: if evanescent { 0.0 } else { 0.5 * p.dot(n) },
                evanescent,
            }
        };
        let w = [
            make(&found[0], f0, Mode::Fast),
            make(&found[1], f1, Mode::Slow),
        ];
        let finite = w
            .iter()
            .all(|w| w.e.is_finite() && w.h.is_finite() && w.flux.is_finite() && w.q.is_finite());
        // A propagating wave leaves the side its energy flows into.
        let flows = w.iter().all(|w| w.evanescent || sigma * w.flux > 0.0);
        (finite && flows).then_some(w)
    };
    let sigma = side.sign();
    Some((pair(sigma)?, pair(-sigma)?))
}

/// The unit field `E` of the real wave vector `k` in a nearly isotropic
/// medium (the eigenvector of `G` whose index is nearest `|k|`), and
/// whether it is unique (`false` where the branches meet).
pub fn real_field(pf: &PlaneForm, k: DVec3) -> (DVec3, bool) {
    let kh = k.normalize();
    let s = kh.any_orthonormal_vector();
    let w = kh.cross(s);
    let (ds, dw) = (pf.d_eta * s, pf.d_eta * w);
    let g = [s.dot(ds), s.dot(dw), w.dot(dw)].map(|x| C::new(x, 0.0));
    let [m1, m2] = eigenvalues(&g);
    let kk = k.length_squared();
    let miss = |m: C| (kk * (pf.eta0 + m.re) - 1.0).abs();
    let mu = if miss(m1) <= miss(m2) { m1 } else { m2 };
    if m1 == m2 {
        return (s, false);
    }
    match eigenvector(&g, mu) {
        Some(c) => {
            let d = s * c[0].re + w * c[1].re;
            ((d * pf.eta0 + pf.d_eta * d).normalize(), true)
        }
        None => (s, false),
    }
}

/// The ray form on the plane of `E` (docs/physics.md §4.8, "Nearly
/// isotropic media"; Born & Wolf §15.2.2): for a unit ray `ŝ`, `E ⊥ ŝ` and
/// `E = (D − (ŝ·D) ŝ)/n_r²`, so on a basis `a`, `b` of the plane normal to
/// `ŝ`, `E = c₀ a + c₁ b` is an eigenvector of `Gᵣ = [[aᵀΔε a, aᵀΔε b],
/// [bᵀΔε a, bᵀΔε b]]` with `n_r² = ε₀ + ν`, `ν` its eigenvalue. Returns
/// `(n_r², E)` of the fast (smaller `n_r`) then the slow sheet; `E` is
/// `None` where the sheets meet (a ray axis: any `E` of the plane).
fn ray_sheets(pf: &PlaneForm, s: DVec3) -> [(f64, Option<DVec3>); 2] {
    let a = s.any_orthonormal_vector();
    let b = s.cross(a);
    let (da, db) = (pf.d_eps * a, pf.d_eps * b);
    let g = [a.dot(da), a.dot(db), b.dot(db)].map(|x| C::new(x, 0.0));
    let [hi, lo] = eigenvalues(&g);
    [lo, hi].map(|nu| {
        let e = (hi != lo)
            .then(|| eigenvector(&g, nu))
            .flatten()
            .map(|c| a * c[0].re + b * c[1].re);
        (pf.eps0 + nu.re, e)
    })
}

/// The ray indices squared `[fast, slow]` along the unit ray `s` of a
/// nearly isotropic medium, from the ray form ([`ray_sheets`]): exact at
/// any spread, where the ray form of Fresnel's equation as a quadratic
/// separates its nearly double root only to `√ε`.
pub fn ray_indices_squared(pf: &PlaneForm, s: DVec3) -> [f64; 2] {
    ray_sheets(pf, s).map(|(x, _)| x)
}

/// The wave vector of the wave of sheet `sheet` (0 fast, 1 slow) whose ray
/// is along the unit `s`: `E` from the ray form ([`ray_sheets`]), `D = εE`,
/// `H ∥ ŝ × E`, `k ∥ D × H` with `k·ŝ = n_r`.
pub fn k_from_ray(pf: &PlaneForm, sheet: usize, s: DVec3) -> DVec3 {
    let (x, e) = ray_sheets(pf, s)[sheet];
    let Some(e) = e else {
        // A ray axis: the pair's wave normals meet ŝ only in the limit;
        // the isotropic wave is the continuous choice.
        return s * x.sqrt();
    };
    // D × (ŝ × E) = ŝ (D·E) − E (D·ŝ), with D·ŝ = (ΔεE)·ŝ (E ⊥ ŝ) taken
    // from Δε so the small tilt of k from ŝ keeps its relative accuracy.
    let de = pf.d_eps * e;
    let d_dot_e = pf.eps0 * e.length_squared() + de.dot(e);
    let dir = s * d_dot_e - e * de.dot(s);
    let k_hat = dir.normalize();
    k_hat * (x.sqrt() / k_hat.dot(s))
}
