//! Closed-form Fresnel coefficients for an interface between two isotropic
//! media (docs/physics.md §4.2; Born & Wolf §1.5.2, eqs. (20)–(21)): the fast path
//! for glass, diamond and air, and the first check of the 4×4 solver.
//!
//! # Field vectors the coefficients refer to
//!
//! With the conventions of [`super::modes`]: `s = unit(t × N)` is the same
//! real vector for the incident, reflected and transmitted waves, and each
//! wave has its own `p = k × s / n` (so `(s, p, k̂)` is right-handed for every
//! wave). With those vectors the tangential boundary conditions give exactly
//! the textbook forms below, whichever side the light comes from
//! (`Q = n cos θ = |q|`, complex `Q₂ = i sqrt(T² − n₂²)` under total internal
//! reflection, the root that decays away from the interface):
//!
//! ```text
//! rs = (Q₁ − Q₂)/(Q₁ + Q₂)                ts = 2 Q₁/(Q₁ + Q₂)
//! rp = (n₂² Q₁ − n₁² Q₂)/(n₂² Q₁ + n₁² Q₂)  tp = 2 n₁ n₂ Q₁/(n₂² Q₁ + n₁² Q₂)
//! ```
//!
//! (`rp = (n₂ cos θ₁ − n₁ cos θ₂)/(n₂ cos θ₁ + n₁ cos θ₂)` multiplied through
//! by `n₁ n₂`.) At normal incidence `p_reflected = −p_incident`, so
//! `rp = −rs` there describes the same physical reflection as `rs`.
//!
//! Energy-normalized amplitudes `ã = a sqrt(|F_out| / |F_in|)` with
//! `F = Q/2` for either mode: reflected `ã = r`, transmitted
//! `ã = t sqrt(Re Q₂ / Q₁)`; `|rs|² + |ts̃|² = 1` and the same for p.

use super::modes::n2_minus_tt;
use num_complex::Complex64;

/// Fresnel amplitude coefficients from medium 1 (incident) into medium 2 at
/// one tangential wave-vector length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fresnel {
    /// `Q₁ = n₁ cos θ₁ = sqrt(n₁² − T²) ≥ 0`.
    pub q1: f64,
    /// `Q₂ = n₂ cos θ₂`: `sqrt(n₂² − T²)`, or `i sqrt(T² − n₂²)` under TIR.
    pub q2: Complex64,
    pub rs: Complex64,
    pub rp: Complex64,
    pub ts: Complex64,
    pub tp: Complex64,
    /// Energy-normalized transmission amplitudes (0 when the transmitted
    /// wave is evanescent).
    pub ts_energy: Complex64,
    pub tp_energy: Complex64,
}

impl Fresnel {
    /// True under total internal reflection (the transmitted wave is
    /// evanescent).
    #[inline]
    pub fn total_internal_reflection(&self) -> bool {
        self.q2.im != 0.0
    }

    /// Reflectances `(Rs, Rp)`.
    #[inline]
    pub fn reflectance(&self) -> (f64, f64) {
        (self.rs.norm_sqr(), self.rp.norm_sqr())
    }

    /// Transmittances `(Ts, Tp)` (fractions of the incident normal flux).
    #[inline]
    pub fn transmittance(&self) -> (f64, f64) {
        (self.ts_energy.norm_sqr(), self.tp_energy.norm_sqr())
    }
}

/// Fresnel coefficients from index `n1` into `n2` for a wave whose tangential
/// wave vector has squared length `tt = T² = (n₁ sin θ₁)²`. Requires
/// `tt ≤ n1²` (a propagating incident wave); larger `tt` is clamped to
/// grazing incidence.
#[inline]
pub fn fresnel(n1: f64, n2: f64, tt: f64) -> Fresnel {
    let q1 = n2_minus_tt(n1, tt).max(0.0).sqrt();
    fresnel_from_normals(n1, n2, q1, normal_component(n2_minus_tt(n2, tt)))
}

/// `Q = n cos θ` from `d = n² − T²`: `sqrt(d)` for a propagating wave,
/// `i sqrt(−d)` for the evanescent one (the root that decays away from the
/// interface).
#[inline]
pub fn normal_component(d: f64) -> Complex64 {
    if d >= 0.0 {
        Complex64::new(d.sqrt(), 0.0)
    } else {
        Complex64::new(0.0, (-d).sqrt())
    }
}

/// The closed forms (module docs) for given `Q₁` and `Q₂`.
#[inline]
pub fn fresnel_from_normals(n1: f64, n2: f64, q1: f64, q2: Complex64) -> Fresnel {
    let n1s = n1 * n1;
    let n2s = n2 * n2;
    let den_s = q2 + q1;
    let den_p = q2 * n1s + q1 * n2s;
    let (rs, ts, rp, tp) = if den_s == Complex64::new(0.0, 0.0) {
        // Q₁ = Q₂ = 0 forces n₁ = n₂ (both at grazing): no interface.
        let one = Complex64::new(1.0, 0.0);
        let zero = Complex64::new(0.0, 0.0);
        (zero, one, zero, one)
    } else {
        let inv_s = den_s.inv();
        let inv_p = den_p.inv();
        (
            (-q2 + q1) * inv_s,
            inv_s * (2.0 * q1),
            (-q2 * n1s + q1 * n2s) * inv_p,
            inv_p * (2.0 * n1 * n2 * q1),
        )
    };
    // ã = t sqrt(|F₂|/|F₁|), F = Re Q / 2. A grazing incident wave (Q₁ = 0)
    // carries no flux: its energy stays with the waves that are grazing too
    // (the limit Q₁ → 0, where Rs, Rp → 1).
    let ratio = if q1 > 0.0 {
        (q2.re / q1).sqrt()
    } else if q2.re == 0.0 && q2.im == 0.0 {
        1.0
    } else {
        0.0
    };
    Fresnel {
        q1,
        q2,
        rs,
        rp,
        ts,
        tp,
        ts_energy: ts * ratio,
        tp_energy: tp * ratio,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_air_glass() {
        // R = ((n−1)/(n+1))² = 0.04 for n = 1.5.
        let f = fresnel(1.0, 1.5, 0.0);
        assert!((f.rs.re + 0.2).abs() < 1e-15);
        assert!((f.rp.re - 0.2).abs() < 1e-15);
        let (ts, tp) = f.transmittance();
        assert!((ts - 0.96).abs() < 1e-15 && (tp - 0.96).abs() < 1e-15);
    }
}
