//! Isotropic interfaces against the check values of docs/physics.md §8.2 and the
//! textbook (Born & Wolf §1.5): every expected number is computed here from
//! its own formula or quoted from the reference, never taken from the code
//! under test.
//!
//! Conventions (spar's, see `spar::optics::modes`): fields vary as
//! exp(i(k·r − ωt)); `s = unit(t × N)` is shared by all waves; each wave has
//! `p = k̂ × s`. With them the reflection coefficients are Born & Wolf's
//! r⊥ (= rs) and r∥ (= rp), eq. 1.5 (21), and under total internal
//! reflection their phases are B&W 1.5 (60), whose time factor is also
//! exp(−iωt).

use crate::support::optics::*;
use glam::DVec3;
use num_complex::Complex64;
use spar::optics::linalg::CVec3;
use spar::optics::{Interface, Medium, Mode, Scattering, Side};

fn iso(n1: f64, n2: f64) -> Interface {
    Interface::new(
        DVec3::Z,
        Medium::Isotropic { n: n1 },
        Medium::Isotropic { n: n2 },
    )
    .unwrap()
}

/// Solve at polar angle `theta` in the x–z plane, incident from side +.
fn at(iface: &Interface, n1: f64, theta: f64, mode: Mode, solver: bool) -> Scattering {
    let t = t_at(n1, theta);
    if solver {
        iface.solve_4x4(Side::Plus, mode, t).unwrap()
    } else {
        iface.solve(Side::Plus, mode, t).unwrap()
    }
}

fn r(sc: &Scattering) -> Complex64 {
    sc.find(Side::Plus, sc.incident.mode).unwrap().amplitude
}

/// Physical reflected field (3-vector) for an incident field with
/// components `(cs, cp)` along the incident wave's `s` and `p`.
fn reflected_field(iface: &Interface, n1: f64, theta: f64, cs: Complex64, cp: Complex64) -> CVec3 {
    let s = at(iface, n1, theta, Mode::S, true);
    let p = at(iface, n1, theta, Mode::P, true);
    s.field_on(Side::Plus).scale(cs) + p.field_on(Side::Plus).scale(cp)
}

/// Minor/major axis ratio b/a of the polarization ellipse of a transverse
/// complex field: |E·E| = a² − b² (bilinear) and E·E* = a² + b².
fn ellipticity(e: CVec3) -> f64 {
    let tot = e.norm_sqr();
    let lin = e.dot(e).norm();
    ((tot - lin) / (tot + lin)).max(0.0).sqrt()
}

#[test]
fn glass_at_45_degrees() {
    // docs/physics.md §8.2: n = 1.5 from air at 45°: Rs = 0.092013, Rp = 0.008466.
    let g = iso(1.0, 1.5);
    let th = 45f64.to_radians();
    for solver in [false, true] {
        let rs = r(&at(&g, 1.0, th, Mode::S, solver)).norm_sqr();
        let rp = r(&at(&g, 1.0, th, Mode::P, solver)).norm_sqr();
        assert!(close(rs, 0.092013, 5e-7), "Rs = {rs}");
        assert!(close(rp, 0.008466, 5e-7), "Rp = {rp}");
        // Abelès: at 45° incidence Rp = Rs² exactly, whatever the indices.
        assert!(close(rp, rs * rs, 1e-15), "Rp = {rp}, Rs² = {}", rs * rs);
        for mode in [Mode::S, Mode::P] {
            let sc = at(&g, 1.0, th, mode, solver);
            assert!(close(sc.energy_sum(), 1.0, 1e-15));
        }
    }
}

#[test]
fn brewster_angle_of_n_bk7() {
    // docs/physics.md §8.2: θ_B = atan(1.5168) = 56.60° from air; there Rp = 0 and
    // the reflected part of unpolarized light is fully polarized.
    let n = 1.5168;
    let g = iso(1.0, n);
    // rp is real and changes sign at θ_B: bisect on the 4×4 solver.
    let (mut lo, mut hi) = (50f64.to_radians(), 60f64.to_radians());
    let sign = |th: f64| r(&at(&g, 1.0, th, Mode::P, true)).re.signum();
    let s_lo = sign(lo);
    assert_ne!(s_lo, sign(hi));
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if sign(mid) == s_lo {
            lo = mid
        } else {
            hi = mid
        }
    }
    let theta_b = 0.5 * (lo + hi);
    assert!(
        (theta_b - n.atan()).abs() < 1e-12,
        "{theta_b} vs {}",
        n.atan()
    );
    assert_eq!(format!("{:.2}", theta_b.to_degrees()), "56.60");

    let th = n.atan();
    let rs = r(&at(&g, 1.0, th, Mode::S, true));
    let rp = r(&at(&g, 1.0, th, Mode::P, true));
    assert!(rp.norm_sqr() < 1e-28, "Rp = {}", rp.norm_sqr());
    // Unpolarized in: J = I/2 in (s, p); out: J = diag(|rs|², |rp|²)/2.
    let (jss, jpp) = (0.5 * rs.norm_sqr(), 0.5 * rp.norm_sqr());
    let tr = jss + jpp;
    let p = (1.0 - 4.0 * jss * jpp / (tr * tr)).max(0.0).sqrt();
    assert!(close(p, 1.0, 1e-12), "P = {p}");
}

#[test]
fn critical_angle_of_n_bk7() {
    // docs/physics.md §8.2: asin(1/1.5168) = 41.25° from N-BK7 into air.
    let n = 1.5168;
    let g = iso(n, 1.0);
    let theta_c = (1.0 / n).asin();
    assert_eq!(format!("{:.2}", theta_c.to_degrees()), "41.25");
    for mode in [Mode::S, Mode::P] {
        let below = at(&g, n, theta_c - 1e-9, mode, true);
        let above = at(&g, n, theta_c + 1e-9, mode, true);
        assert!(below.transmitted().iter().all(|o| !o.wave.evanescent));
        assert!(below.energy_sum() > 0.0 && (below.energy_sum() - 1.0).abs() < 1e-12);
        assert!(above
            .transmitted()
            .iter()
            .all(|o| o.wave.evanescent && o.energy == 0.0));
        // Total internal reflection: |r| = 1.
        assert!(
            close(r(&above).norm(), 1.0, 1e-15),
            "|r| = {}",
            r(&above).norm()
        );
    }
    // Where the code switches to evanescent: bisect on the flag.
    let (mut lo, mut hi) = (40f64.to_radians(), 42f64.to_radians());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if at(&g, n, mid, Mode::S, true).outgoing[2].wave.evanescent {
            hi = mid
        } else {
            lo = mid
        }
    }
    assert!((lo - theta_c).abs() < 1e-15 * 4.0, "{lo} vs {theta_c}");
}

/// Phases of rs and rp under total internal reflection, B&W 1.5 (60) with
/// n = n₂/n₁: tan(δs/2) = −√(sin²θ − n²)/cos θ, tan(δp/2) =
/// −√(sin²θ − n²)/(n² cos θ); and their difference (B&W 1.5 (61)):
/// tan(δ/2) = cos θ √(sin²θ − n²)/sin²θ for δ = δs − δp.
#[test]
fn total_internal_reflection_phases_across_angles() {
    for n1 in [1.5, 1.51, 2.417] {
        let g = iso(n1, 1.0);
        let n = 1.0 / n1;
        let theta_c = n.asin();
        for i in 0..=400 {
            let th =
                theta_c + 1e-6 + (89.9f64.to_radians() - theta_c - 1e-6) * f64::from(i) / 400.0;
            // From the same T = n₁ sin θ the solve receives, factored so
            // that sin²θ − n² keeps its accuracy next to the critical angle.
            let tt = n1 * th.sin();
            let s2 = (tt / n1).powi(2);
            let c = ((n1 - tt) * (n1 + tt)).sqrt() / n1;
            let root = ((tt - 1.0) * (tt + 1.0)).sqrt() / n1;
            let rs = r(&at(&g, n1, th, Mode::S, true));
            let rp = r(&at(&g, n1, th, Mode::P, true));
            let (ds, dp) = (rs.arg(), rp.arg());
            // Compare phases, not tangents (tan(δs/2) → ∞ at grazing).
            let want_s = -2.0 * (root / c).atan();
            let want_p = -2.0 * (root / (n * n * c)).atan();
            assert!(close(ds, want_s, 1e-13), "θ = {th}: δs = {ds} vs {want_s}");
            assert!(close(dp, want_p, 1e-13), "θ = {th}: δp = {dp} vs {want_p}");
            let want = 2.0 * (c * root / s2).atan();
            assert!(
                close(ds - dp, want, 1e-13),
                "θ = {th}: δ = {} vs {want}",
                ds - dp
            );
        }
    }
}

#[test]
fn one_total_internal_reflection_at_45_degrees_gives_b_over_a_one_third() {
    // docs/physics.md §8.2: n = 1.5 glass, 45° inside: light linear at 45° to the
    // plane of incidence becomes an ellipse with b/a = 1/3, |δ| = 36.87°.
    let g = iso(1.5, 1.0);
    let th = 45f64.to_radians();
    let rs = r(&at(&g, 1.5, th, Mode::S, true));
    let rp = r(&at(&g, 1.5, th, Mode::P, true));
    let delta = (rs.arg() - rp.arg()).abs();
    assert!(
        close(delta, 2.0 * (1.0f64 / 3.0).atan(), 1e-13),
        "|δ| = {}",
        delta.to_degrees()
    );
    assert_eq!(format!("{:.2}", delta.to_degrees()), "36.87");
    let h = Complex64::new(std::f64::consts::FRAC_1_SQRT_2, 0.0);
    let e = reflected_field(&g, 1.5, th, h, h);
    assert!(
        close(ellipticity(e), 1.0 / 3.0, 1e-13),
        "b/a = {}",
        ellipticity(e)
    );
}

#[test]
fn fresnel_rhomb_makes_circular_light() {
    // docs/physics.md §8.2: n₁ = 1.51, θ ≈ 54.6° gives δ = 45° per reflection; two
    // reflections turn light linear at 45° into circular light.
    let n1 = 1.51;
    let a = iso(n1, 1.0);
    let delta = |th: f64| {
        let rs = r(&at(&a, n1, th, Mode::S, true));
        let rp = r(&at(&a, n1, th, Mode::P, true));
        rs.arg() - rp.arg()
    };
    // δ(θ) falls through 45° between 52° and 60°.
    let target = 45f64.to_radians();
    let (mut lo, mut hi) = (52f64.to_radians(), 60f64.to_radians());
    assert!(delta(lo) > target && delta(hi) < target);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if delta(mid) > target {
            lo = mid
        } else {
            hi = mid
        }
    }
    let th = 0.5 * (lo + hi);
    assert!(
        (th.to_degrees() - 54.6).abs() < 0.05,
        "θ = {}°",
        th.to_degrees()
    );

    // The rhomb: face A (normal +z, glass above) then the parallel face B
    // (normal −z into the glass). Follow the physical field in 3-D.
    let b = Interface::new(
        -DVec3::Z,
        Medium::Isotropic { n: n1 },
        Medium::Isotropic { n: 1.0 },
    )
    .unwrap();
    let h = Complex64::new(std::f64::consts::FRAC_1_SQRT_2, 0.0);
    let e1 = reflected_field(&a, n1, th, h, h);
    // Reflected from A, travelling +z toward B: decompose on B's incident
    // basis (real, orthonormal, transverse).
    let k1 = at(&a, n1, th, Mode::S, true).outgoing[0].wave.k.re;
    let sb = b.solve(Side::Plus, Mode::S, k1).unwrap();
    let pb = b.solve(Side::Plus, Mode::P, k1).unwrap();
    let (bs, bp) = (sb.incident.e.re, pb.incident.e.re);
    assert!(e1.dot_real(k1).norm() < 1e-15, "transverse");
    let e2 = sb.field_on(Side::Plus).scale(e1.dot_real(bs))
        + pb.field_on(Side::Plus).scale(e1.dot_real(bp));
    assert!(
        close(ellipticity(e2), 1.0, 1e-9),
        "b/a = {}",
        ellipticity(e2)
    );
    // No energy lost in the two total reflections.
    assert!(close(e2.norm_sqr(), 1.0, 1e-14));
}

#[test]
fn normal_incidence_is_rotation_invariant() {
    // At normal incidence s is a fixed tangent of N; the physical fields
    // must not depend on it: E_r = (n₁ − n₂)/(n₁ + n₂) E_i and
    // E_t = 2 n₁/(n₁ + n₂) E_i for every transverse E_i (B&W §1.5, normal incidence).
    let mut rng = rng(17);
    for _ in 0..200 {
        let n = unit(&mut rng);
        let (n1, n2) = (
            1.0 + 1.5 * rand::Rng::gen::<f64>(&mut rng),
            1.0 + 1.5 * rand::Rng::gen::<f64>(&mut rng),
        );
        let g =
            Interface::new(n, Medium::Isotropic { n: n1 }, Medium::Isotropic { n: n2 }).unwrap();
        let k = -n * n1;
        let s = g.solve(Side::Plus, Mode::S, k).unwrap();
        let p = g.solve(Side::Plus, Mode::P, k).unwrap();
        for _ in 0..5 {
            let v = unit(&mut rng);
            let e = (v - n * v.dot(n)).normalize();
            let (cs, cp) = (e.dot(s.incident.e.re), e.dot(p.incident.e.re));
            let er = s.field_on(Side::Plus) * cs + p.field_on(Side::Plus) * cp;
            let et = s.field_on(Side::Minus) * cs + p.field_on(Side::Minus) * cp;
            let want_r = e * ((n1 - n2) / (n1 + n2));
            let want_t = e * (2.0 * n1 / (n1 + n2));
            // A few dozen roundings of O(1) numbers: 1e-14.
            assert!(
                (er.re - want_r).length() < 1e-14 && er.im.length() < 1e-14,
                "{er:?} vs {want_r}"
            );
            assert!(
                (et.re - want_t).length() < 1e-14 && et.im.length() < 1e-14,
                "{et:?} vs {want_t}"
            );
        }
    }
}

#[test]
fn evanescent_waves_decay_away_from_the_interface() {
    // exp(i(k·r − ωt)): |exp(i q z)| = exp(−Im(q) z), so the transmitted
    // wave must have Im q < 0 on side − (z < 0) and Im q > 0 on side +.
    let n = 1.5;
    let th = 60f64.to_radians();
    let plus = iso(n, 1.0).solve(Side::Plus, Mode::S, t_at(n, th)).unwrap();
    let minus = iso(1.0, n)
        .solve(Side::Minus, Mode::S, t_at(n, th))
        .unwrap();
    for (sc, side) in [(plus, Side::Minus), (minus, Side::Plus)] {
        let o = sc.find(side, Mode::S).unwrap();
        assert!(o.wave.evanescent);
        let depth = [1.0, 2.0];
        let amp: Vec<f64> = depth
            .iter()
            .map(|&d| (Complex64::i() * o.wave.q * (side.sign() * d)).exp().norm())
            .collect();
        assert!(amp[1] < amp[0] && amp[0] < 1.0, "{side:?}: {amp:?}");
        // Its decay constant is √(T² − n₂²) (B&W §1.5.4).
        let want = ((n * th.sin()).powi(2) - 1.0).sqrt();
        assert!(close(o.wave.q.im.abs(), want, 1e-15));
        // A single evanescent wave carries no normal energy.
        let f = o.wave.e.cross(o.wave.h.conj()).re.dot(DVec3::Z) / 2.0;
        assert!(f.abs() < 1e-16, "{f}");
    }
}
