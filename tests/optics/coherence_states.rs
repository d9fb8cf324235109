//! Coherence matrices of standard polarization states, against values worked
//! out by hand from the definitions (docs/physics.md §1–3).

use glam::DVec3;
use num_complex::Complex64;
use spar::optics::{Coherence, Handedness, Jones, Polarimetry, PolarizationMap, Stokes};
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_4, PI};

fn c(re: f64, im: f64) -> Complex64 {
    Complex64::new(re, im)
}

fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: {actual} vs {expected} (tolerance {tol})"
    );
}

fn assert_stokes(j: &Coherence, expected: [f64; 4], what: &str) {
    let s = j.stokes().to_array();
    for k in 0..4 {
        assert_close(s[k], expected[k], 1e-14, &format!("{what} S{k}"));
    }
}

/// The ellipse of the tests: b/a = 0.5, major axis at 30° from x, drawn as
/// E = Rot(30°) (a, i b) with a² + b² = 1. In its own axes the field is
/// (a cos ωt, b sin ωt) (phasor convention exp(−iωt)): counter-clockwise for
/// the receiver, left-handed.
fn ellipse() -> [Complex64; 2] {
    let (a, b) = (1.0 / 1.25_f64.sqrt(), 0.5 / 1.25_f64.sqrt());
    let (s, co) = (PI / 6.0).sin_cos();
    let e = [c(a, 0.0), c(0.0, b)];
    [co * e[0] - s * e[1], s * e[0] + co * e[1]]
}

#[test]
fn time_convention_check_from_optics_md() {
    // Ex = 1, Ey = i: E(t) = (cos ωt, sin ωt), counter-clockwise for the
    // receiver; S3 = 2 Im(1 · conj(i)) = −2.
    let j = Coherence::from_jones_vector([c(1.0, 0.0), c(0.0, 1.0)]);
    assert_stokes(&j, [2.0, 0.0, 0.0, -2.0], "Ex=1, Ey=i");
    let p = Polarimetry::of(&j);
    assert_eq!(p.handedness, Some(Handedness::Left));
    assert_eq!(
        Coherence::circular(2.0, Handedness::Left).stokes(),
        j.stokes()
    );
    assert_close(
        Coherence::circular(1.0, Handedness::Right).stokes().s3,
        1.0,
        0.0,
        "right",
    );
}

#[test]
fn unpolarized() {
    let j = Coherence::unpolarized(2.0);
    assert_stokes(&j, [2.0, 0.0, 0.0, 0.0], "unpolarized");
    let p = Polarimetry::of(&j);
    assert_eq!(p.intensity, 2.0);
    assert_eq!(p.degree_of_polarization, 0.0);
    assert_eq!(p.ellipticity, 0.0);
    assert_eq!(p.ellipticity_paper, 0.0);
    assert_eq!(p.azimuth, 0.0);
    assert_eq!(p.handedness, None);
}

#[test]
fn linear_x_and_45() {
    let x = Coherence::from_jones_vector([c(1.0, 0.0), c(0.0, 0.0)]);
    assert_stokes(&x, [1.0, 1.0, 0.0, 0.0], "linear x");
    assert_eq!(Coherence::linear(1.0, 0.0), x);
    let p = Polarimetry::of(&x);
    assert_eq!(
        (p.degree_of_polarization, p.azimuth, p.ellipticity),
        (1.0, 0.0, 0.0)
    );

    let d = Coherence::from_jones_vector([c(FRAC_1_SQRT_2, 0.0), c(FRAC_1_SQRT_2, 0.0)]);
    assert_stokes(&d, [1.0, 0.0, 1.0, 0.0], "linear 45°");
    let p = Polarimetry::of(&d);
    assert_close(p.degree_of_polarization, 1.0, 1e-15, "P");
    assert_close(p.azimuth, FRAC_PI_4, 1e-15, "ψ");
    assert_close(p.ellipticity, 0.0, 1e-15, "b/a");
    let l = Coherence::linear(1.0, FRAC_PI_4).stokes().to_array();
    for k in 0..4 {
        assert_close(l[k], [1.0, 0.0, 1.0, 0.0][k], 1e-15, "linear(45°)");
    }
    // Light along y has azimuth π/2 (the top of the range (−π/2, π/2]).
    let y = Polarimetry::of(&Coherence::linear(1.0, PI / 2.0));
    assert_close(y.azimuth, PI / 2.0, 1e-15, "ψ of y");
    let y_exact = Polarimetry::of(&Coherence::from_jones_vector([c(0.0, 0.0), c(1.0, 0.0)]));
    assert_eq!(y_exact.azimuth, PI / 2.0);
}

#[test]
fn circular() {
    let j = Coherence::from_jones_vector([c(FRAC_1_SQRT_2, 0.0), c(0.0, -FRAC_1_SQRT_2)]);
    assert_stokes(&j, [1.0, 0.0, 0.0, 1.0], "right circular");
    let p = Polarimetry::of(&j);
    assert_close(p.degree_of_polarization, 1.0, 1e-15, "P");
    assert_close(p.ellipticity, 1.0, 1e-15, "b/a");
    assert_close(p.ellipticity_paper, 1.0, 1e-15, "E_paper");
    assert_close(p.ellipticity_angle, FRAC_PI_4, 1e-15, "χ");
    assert_eq!(p.handedness, Some(Handedness::Right));
}

#[test]
fn ellipse_half_at_30_degrees() {
    let j = Coherence::from_jones_vector(ellipse());
    let p = Polarimetry::of(&j);
    assert_close(p.intensity, 1.0, 1e-15, "I");
    assert_close(p.degree_of_polarization, 1.0, 1e-15, "P");
    assert_close(p.ellipticity, 0.5, 1e-15, "b/a");
    assert_close(p.ellipticity_paper, 0.5, 1e-15, "E_paper = b/a when P = 1");
    assert_close(p.azimuth, PI / 6.0, 1e-15, "ψ");
    assert_close(p.ellipticity_angle, -(0.5_f64).atan(), 1e-15, "χ");
    assert_eq!(p.handedness, Some(Handedness::Left));
    // Stokes by hand: S = (1, cos 2χ cos 2ψ, cos 2χ sin 2ψ, sin 2χ),
    // cos 2χ = 0.6, sin 2χ = −0.8 for b/a = 0.5.
    let expected = [1.0, 0.6 * 0.5, 0.6 * (3.0_f64).sqrt() / 2.0, -0.8];
    let s = j.stokes().to_array();
    for k in 0..4 {
        assert_close(s[k], expected[k], 1e-15, &format!("S{k}"));
    }
}

#[test]
fn half_unpolarized_half_ellipse() {
    // docs/physics.md §2.2: P = 0.5, b/a = 0.5, E_paper = tan(½ asin 0.4) = 0.2087.
    let j = Coherence::unpolarized(0.5) + Coherence::from_jones_vector(ellipse()) * 0.5;
    let p = Polarimetry::of(&j);
    assert_close(p.degree_of_polarization, 0.5, 1e-15, "P");
    assert_close(p.ellipticity, 0.5, 1e-15, "b/a");
    assert_close(p.ellipticity_paper, 0.2087, 5e-5, "E_paper");
    assert_close(
        p.ellipticity_paper,
        (0.5 * 0.4_f64.asin()).tan(),
        1e-15,
        "E_paper exact",
    );
    assert_close(p.azimuth, PI / 6.0, 1e-15, "ψ");
    assert_close(p.polarized_intensity, 0.5, 1e-15, "Ip");
}

/// The seed paper's eq. (3) as printed: sqrt(1 − (4 Jxx Jyy − Jxy Jyx) /
/// (Jxx + Jyy)²) — the factor 4 belongs to the whole determinant.
fn p_printed(j: &Coherence) -> f64 {
    let (xx, yy) = (j.jxx(), j.jyy());
    let xy_yx = (j.jxy() * j.jyx()).re;
    (1.0 - (4.0 * xx * yy - xy_yx) / (xx + yy).powi(2)).sqrt()
}

/// The corrected closed form sqrt(1 − 4 det J / (tr J)²).
fn p_closed_form(j: &Coherence) -> f64 {
    let (xx, yy) = (j.jxx(), j.jyy());
    let det = xx * yy - (j.jxy() * j.jyx()).re;
    (1.0 - 4.0 * det / (xx + yy).powi(2)).max(0.0).sqrt()
}

#[test]
fn seed_equation_3_as_printed_is_wrong_for_linear_45() {
    let j = Coherence::linear(1.0, FRAC_PI_4);
    // Jxx = Jyy = Jxy = Jyx = ½: the printed form gives √(1 − ¾) = ½.
    assert_close(p_printed(&j), 0.5, 1e-15, "printed eq. (3)");
    assert_close(p_closed_form(&j), 1.0, 1e-7, "corrected eq. (3)");
    assert_close(Polarimetry::of(&j).degree_of_polarization, 1.0, 1e-15, "P");
    // On light linear along x the printed and corrected forms agree (the
    // error needs Jxy ≠ 0).
    let x = Coherence::linear(1.0, 0.0);
    assert_close(p_printed(&x), 1.0, 1e-15, "printed, x");
}

#[test]
fn malus_law() {
    // An ideal linear polarizer at φ passes cos² φ of light linear along x.
    for k in 0..=12 {
        let phi = k as f64 * PI / 12.0;
        let (s, co) = phi.sin_cos();
        let polarizer = Jones::from_entries(
            2,
            2,
            [
                [c(co * co, 0.0), c(co * s, 0.0)],
                [c(co * s, 0.0), c(s * s, 0.0)],
            ],
        );
        let out = Coherence::linear(1.0, 0.0).transform(&polarizer);
        assert_close(out.intensity(), co * co, 1e-15, "Malus");
        if co * co > 1e-9 {
            let p = Polarimetry::of(&out);
            assert_close(p.degree_of_polarization, 1.0, 1e-12, "P after polarizer");
        }
    }
}

#[test]
fn quarter_wave_plate_makes_circular_light() {
    // Linear 45° through diag(1, i) (fast axis x, y retarded by π/2 in the
    // exp(−iωt) convention): (1, 1)/√2 → (1, i)/√2, left-handed (S3 = −1).
    let qwp = Jones::diagonal(c(1.0, 0.0), c(0.0, 1.0));
    let out = Coherence::linear(1.0, FRAC_PI_4).transform(&qwp);
    assert_stokes(&out, [1.0, 0.0, 0.0, -1.0], "after QWP");
}

#[test]
fn jones_blocks_of_every_shape() {
    // 1×2: projection of unpolarized light onto x keeps half.
    let out = Coherence::unpolarized(2.0).transform(&Jones::row(c(1.0, 0.0), c(0.0, 0.0)));
    assert_eq!(out.modes(), 1);
    assert_close(out.intensity(), 1.0, 1e-15, "1×2");
    // 1×2 of a polarized state: |a Ex + b Ey|².
    let e = ellipse();
    let (a, b) = (c(0.3, -0.2), c(-0.5, 0.7));
    let out = Coherence::from_jones_vector(e).transform(&Jones::row(a, b));
    assert_close(
        out.jxx(),
        (a * e[0] + b * e[1]).norm_sqr(),
        1e-15,
        "1×2 polarized",
    );
    // 2×1: one eigenwave into two modes: fully polarized along (a, b).
    let out = Coherence::scalar(2.0).transform(&Jones::column(a, b));
    let expected = Coherence::from_jones_vector([a * 2.0_f64.sqrt(), b * 2.0_f64.sqrt()]);
    for (x, y) in out
        .matrix()
        .iter()
        .flatten()
        .zip(expected.matrix().iter().flatten())
    {
        assert_close((x - y).norm(), 0.0, 1e-15, "2×1");
    }
    assert_close(
        Polarimetry::of(&out).degree_of_polarization,
        1.0,
        1e-12,
        "2×1 P",
    );
    // 1×1.
    let out = Coherence::scalar(2.0).transform(&Jones::scalar(c(0.0, 0.5)));
    assert_close(out.intensity(), 0.5, 1e-15, "1×1");
    // A one-mode matrix reads as light polarized along its mode.
    let p = Polarimetry::of(&Coherence::scalar(3.0));
    assert_eq!((p.intensity, p.degree_of_polarization), (3.0, 1.0));
}

#[test]
fn jones_algebra() {
    let t = Jones::from_entries(
        2,
        2,
        [[c(1.0, 2.0), c(0.5, -1.0)], [c(0.0, 1.0), c(3.0, 0.0)]],
    );
    let u = Jones::row(c(2.0, 0.0), c(0.0, -1.0));
    // (u t) by hand: [2(1+2i) + (−i)(i), 2(0.5 − i) + (−i)(3)] = [3 + 4i, 1 − 5i].
    let ut = u * t;
    assert_eq!((ut.rows, ut.cols), (1, 2));
    assert_eq!(ut.m[0], [c(3.0, 4.0), c(1.0, -5.0)]);
    assert_eq!(ut.m[1], [c(0.0, 0.0); 2]);
    let h = t.adjoint();
    assert_eq!(h.m[0][1], c(0.0, -1.0));
    assert_eq!(h.m[1][0], c(0.5, 1.0));
    assert_eq!(u.adjoint().rows, 2);
    assert_eq!(Jones::identity(2) * t, t);
    assert_eq!(
        t.apply([c(1.0, 0.0), c(0.0, 0.0)]),
        [c(1.0, 2.0), c(0.0, 1.0)]
    );
    assert_close(Jones::identity(2).norm_sqr(), 2.0, 0.0, "‖1‖²");
    // (A B)ᴴ = Bᴴ Aᴴ
    let lhs = (u * t).adjoint();
    let rhs = t.adjoint() * u.adjoint();
    assert_eq!(lhs, rhs);
}

#[test]
fn basis_rotation_and_change() {
    let j = Coherence::from_jones_vector(ellipse());
    let theta = 0.4;
    let r = Polarimetry::of(&j.rotate_basis(theta));
    assert_close(r.azimuth, PI / 6.0 - theta, 1e-14, "ψ − θ");
    assert_close(r.ellipticity, 0.5, 1e-14, "b/a");
    // The same rotation as a change between 3-vector bases.
    let from = [DVec3::X, DVec3::Y];
    let (s, co) = theta.sin_cos();
    let to = [DVec3::new(co, s, 0.0), DVec3::new(-s, co, 0.0)];
    let changed = j.change_basis(&from, &to);
    for (x, y) in changed
        .matrix()
        .iter()
        .flatten()
        .zip(j.rotate_basis(theta).matrix().iter().flatten())
    {
        assert_close((x - y).norm(), 0.0, 1e-15, "change_basis = rotate_basis");
    }
    // A mirrored basis flips the handedness.
    let mirrored = j.change_basis(&from, &[DVec3::X, DVec3::NEG_Y]);
    assert_close(mirrored.stokes().s3, -j.stokes().s3, 1e-15, "S3 flips");
    // Linear light at θ seen in a basis rotated by θ is along x.
    let l = Coherence::linear(1.0, 1.1).rotate_basis(1.1);
    assert_close(l.stokes().s1, 1.0, 1e-15, "aligned");
}

#[test]
fn maps_by_name() {
    for m in PolarizationMap::ALL {
        assert_eq!(PolarizationMap::parse(m.name()).unwrap(), m);
    }
    assert_eq!(
        PolarizationMap::parse("DOP").unwrap(),
        PolarizationMap::DegreeOfPolarization
    );
    let err = PolarizationMap::parse("chirality").unwrap_err();
    assert!(err.contains("ellipticity-paper"), "{err}");
    let p = Polarimetry::of(
        &(Coherence::unpolarized(0.5) + Coherence::from_jones_vector(ellipse()) * 0.5),
    );
    assert_close(
        PolarizationMap::EllipticityPaper.value(&p),
        0.2087,
        5e-5,
        "map",
    );
    assert_close(
        PolarizationMap::Azimuth.value(&p),
        (PI / 6.0 + PI / 2.0) / PI,
        1e-15,
        "ψ map",
    );
    let s = Stokes {
        s0: 1.0,
        s1: 0.0,
        s2: 0.0,
        s3: 0.5,
    };
    assert_close(
        Polarimetry::from_stokes(s).degree_of_polarization,
        0.5,
        1e-15,
        "from_stokes",
    );
}
