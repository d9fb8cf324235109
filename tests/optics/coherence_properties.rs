//! Properties of coherence matrices over many random cases (seeded), with
//! nasty magnitudes: exact zero, denormals, 1e-300, 1e300.

use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::optics::{Coherence, Jones, Polarimetry};
use std::f64::consts::PI;

const CASES: usize = 120_000;

/// Magnitudes the renderer can produce after deep paths, and worse.
const SCALES: [f64; 7] = [0.0, 4.9e-322, 2.3e-310, 1e-300, 1e-3, 1.0, 1e300];

fn rng() -> Pcg64 {
    Pcg64::seed_from_u64(0x5eed_c0de)
}

fn complex(rng: &mut Pcg64) -> Complex64 {
    Complex64::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0))
}

/// A random physical two-mode matrix: a few polarized states plus some
/// unpolarized light, sometimes pure, sometimes unpolarized only.
fn random_coherence(rng: &mut Pcg64) -> Coherence {
    let mut j = Coherence::unpolarized(if rng.gen_bool(0.3) {
        0.0
    } else {
        rng.gen_range(0.0..1.0)
    });
    for _ in 0..rng.gen_range(0..3) {
        j += Coherence::from_jones_vector([complex(rng), complex(rng)]);
    }
    j
}

fn random_jones(rng: &mut Pcg64, cols: usize) -> Jones {
    let rows = rng.gen_range(1..=2);
    let mut m = [[Complex64::new(0.0, 0.0); 2]; 2];
    for row in m.iter_mut() {
        for v in row.iter_mut() {
            *v = complex(rng);
        }
    }
    Jones::from_entries(rows, cols, m)
}

/// `T J Tᴴ` by plain complex matrix products (independent of
/// `Coherence::transform`); index loops, as the formula is written.
#[allow(clippy::needless_range_loop)]
fn naive_transform(t: &Jones, j: &Coherence) -> [[Complex64; 2]; 2] {
    let jm = j.matrix();
    let n = j.modes();
    let mut tj = [[Complex64::new(0.0, 0.0); 2]; 2];
    for r in 0..t.rows {
        for c in 0..n {
            for k in 0..n {
                tj[r][c] += t.m[r][k] * jm[k][c];
            }
        }
    }
    let mut out = [[Complex64::new(0.0, 0.0); 2]; 2];
    for r in 0..t.rows {
        for c in 0..t.rows {
            for k in 0..n {
                out[r][c] += tj[r][k] * t.m[c][k].conj();
            }
        }
    }
    out
}

fn check_invariants(j: &Coherence, what: &str) {
    let s = j.stokes();
    for v in s.to_array() {
        assert!(v.is_finite(), "{what}: Stokes {s:?} of {j:?}");
    }
    assert!(s.s0 >= 0.0, "{what}: S0 < 0: {s:?}");
    // S0 ≥ √(S1² + S2² + S3²) within rounding.
    let ip = s.polarized_intensity();
    assert!(ip <= s.s0 * (1.0 + 1e-12), "{what}: Ip {ip} > S0 {}", s.s0);
    let p = Polarimetry::of(j);
    let values = [
        p.intensity,
        p.polarized_intensity,
        p.degree_of_polarization,
        p.azimuth,
        p.ellipticity_angle,
        p.ellipticity,
        p.ellipticity_paper,
    ];
    assert!(values.iter().all(|v| v.is_finite()), "{what}: {p:?}");
    assert!(
        (0.0..=1.0).contains(&p.degree_of_polarization),
        "{what}: {p:?}"
    );
    assert!((0.0..=1.0).contains(&p.ellipticity), "{what}: {p:?}");
    assert!((0.0..=1.0).contains(&p.ellipticity_paper), "{what}: {p:?}");
    assert!(
        p.azimuth > -PI / 2.0 && p.azimuth <= PI / 2.0,
        "{what}: {p:?}"
    );
    assert!(p.ellipticity_angle.abs() <= PI / 4.0, "{what}: {p:?}");
    assert!(p.polarized_intensity <= p.intensity, "{what}: {p:?}");
    // The paper's map is b/a weighted by P: never above b/a.
    assert!(
        p.ellipticity_paper <= p.ellipticity + 1e-12,
        "{what}: {p:?}"
    );
}

#[test]
fn derived_quantities_stay_in_range_at_every_scale() {
    let mut rng = rng();
    for case in 0..CASES {
        let scale = SCALES[case % SCALES.len()];
        let j = random_coherence(&mut rng) * scale;
        check_invariants(&j, &format!("case {case}, scale {scale:e}"));
    }
}

#[test]
fn degree_of_polarization_matches_the_closed_form() {
    // P = √(1 − 4 det J / (tr J)²) (docs/physics.md §2), on moderate magnitudes
    // where the closed form is itself accurate.
    let mut rng = rng();
    for case in 0..CASES {
        let j = random_coherence(&mut rng);
        let (xx, yy) = (j.jxx(), j.jyy());
        let tr = xx + yy;
        if tr < 1e-3 {
            continue;
        }
        let det = xx * yy - j.jxy().norm_sqr();
        let closed = (1.0 - 4.0 * det / (tr * tr)).clamp(0.0, 1.0).sqrt();
        let p = Polarimetry::of(&j).degree_of_polarization;
        // √ amplifies rounding near P = 0: compare squares.
        assert!(
            (p * p - closed * closed).abs() < 1e-12,
            "case {case}: P {p} vs closed form {closed}"
        );
    }
}

#[test]
fn jones_transform_is_hermitian_psd_and_matches_matrix_products() {
    let mut rng = rng();
    for case in 0..CASES {
        let one_mode = rng.gen_bool(0.25);
        let j = if one_mode {
            Coherence::scalar(rng.gen_range(0.0..1.0))
        } else {
            random_coherence(&mut rng)
        };
        let t = random_jones(&mut rng, j.modes());
        let out = j.transform(&t);
        assert_eq!(out.modes(), t.rows);
        let naive = naive_transform(&t, &j);
        let size = 1.0 + naive.iter().flatten().map(|v| v.norm()).fold(0.0, f64::max);
        let m = out.matrix();
        for r in 0..t.rows {
            for c in 0..t.rows {
                assert!(
                    (m[r][c] - naive[r][c]).norm() <= 1e-13 * size,
                    "case {case}: {m:?} vs {naive:?}"
                );
            }
        }
        // Hermitian (exactly, by storage) and positive semidefinite: both
        // eigenvalues ≥ −rounding.
        assert_eq!(m[1][0], m[0][1].conj());
        let tr = out.jxx() + out.jyy();
        let det = out.jxx() * out.jyy() - out.jxy().norm_sqr();
        assert!(
            out.jxx() >= -1e-14 * size && out.jyy() >= -1e-14 * size,
            "case {case}"
        );
        assert!(det >= -1e-13 * size * size, "case {case}: det {det}");
        assert!(tr >= -1e-14 * size, "case {case}");
        check_invariants(&out, &format!("transformed case {case}"));
    }
}

#[test]
fn basis_rotation_keeps_intensity_p_and_ellipticity_and_turns_the_azimuth() {
    // Subnormal inputs carry a few significant bits: rotating them rounds
    // at the subnormal unit, so these invariants are checked from the
    // smallest normal magnitudes up (subnormals are covered by the range
    // checks of the other tests).
    let normal_scales = [1e-300, 1e-3, 1.0, 1e300];
    let mut rng = rng();
    for case in 0..CASES {
        let scale = normal_scales[case % normal_scales.len()];
        let j = random_coherence(&mut rng) * scale;
        let theta = rng.gen_range(-2.0 * PI..2.0 * PI);
        let a = Polarimetry::of(&j);
        let b = Polarimetry::of(&j.rotate_basis(theta));
        let what = format!("case {case}, scale {scale:e}, θ {theta}");
        assert!(
            (a.intensity - b.intensity).abs() <= 1e-13 * a.intensity,
            "{what}: I {} vs {}",
            a.intensity,
            b.intensity
        );
        assert!(
            (a.degree_of_polarization - b.degree_of_polarization).abs() < 1e-12,
            "{what}: P"
        );
        // The azimuth and b/a are only defined by a well-resolved polarized
        // part; ψ also needs a linear part.
        let s = j.stokes();
        let rel_ip = a.degree_of_polarization;
        if rel_ip > 1e-6 {
            assert!(
                (a.ellipticity - b.ellipticity).abs() < 1e-9 / rel_ip,
                "{what}: b/a {} vs {}",
                a.ellipticity,
                b.ellipticity
            );
        }
        let linear = s.s1.hypot(s.s2) / s.s0.max(f64::MIN_POSITIVE);
        if linear > 1e-6 {
            let turned = (a.azimuth - theta - b.azimuth).rem_euclid(PI);
            let err = turned.min(PI - turned);
            assert!(
                err < 1e-9 / linear,
                "{what}: ψ {} − θ vs {}",
                a.azimuth,
                b.azimuth
            );
        }
    }
}

#[test]
fn nasty_inputs_never_give_nan_or_infinity() {
    let mut rng = rng();
    let specials = [
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        4.9e-324,
        -4.9e-324,
        1e-300,
        1e300,
        f64::MAX,
        -f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        -1e-17,
        1.0,
    ];
    let pick = |rng: &mut Pcg64| {
        if rng.gen_bool(0.5) {
            specials[rng.gen_range(0..specials.len())]
        } else {
            rng.gen_range(-1.0..1.0)
        }
    };
    for case in 0..CASES {
        // Arbitrary, possibly non-Hermitian, non-positive, non-finite
        // matrices.
        let m = [
            [
                Complex64::new(pick(&mut rng), pick(&mut rng)),
                Complex64::new(pick(&mut rng), pick(&mut rng)),
            ],
            [
                Complex64::new(pick(&mut rng), pick(&mut rng)),
                Complex64::new(pick(&mut rng), pick(&mut rng)),
            ],
        ];
        let j = Coherence::from_matrix(m);
        check_invariants(&j, &format!("case {case}: {m:?}"));
        check_invariants(&Coherence::scalar(m[0][0].re), "scalar");
    }
}

#[test]
fn slightly_non_hermitian_and_slightly_negative_inputs() {
    // Rounding leaves a pure state with a tiny negative eigenvalue or a
    // slightly non-Hermitian off-diagonal: P must come out 1, not NaN or
    // above 1.
    let mut rng = rng();
    for case in 0..CASES / 4 {
        let e = [complex(&mut rng), complex(&mut rng)];
        let mut m = Coherence::from_jones_vector(e).matrix();
        let eps = 1e-15 * (m[0][0].re + m[1][1].re);
        m[0][1] += Complex64::new(
            eps * rng.gen_range(-1.0..1.0),
            eps * rng.gen_range(-1.0..1.0),
        );
        m[1][0] += Complex64::new(
            eps * rng.gen_range(-1.0..1.0),
            eps * rng.gen_range(-1.0..1.0),
        );
        m[0][0].re -= eps * rng.gen_range(0.0..1.0);
        let j = Coherence::from_matrix(m);
        let p = Polarimetry::of(&j);
        assert!(
            (p.degree_of_polarization - 1.0).abs() < 1e-6,
            "case {case}: P {}",
            p.degree_of_polarization
        );
        check_invariants(&j, &format!("case {case}"));
    }
}

/// `Jones::product` (unrolled for speed) is the textbook sum
/// `Σ_k A_rk B_kc` over `k < A.cols`, added from zero in order, bit for
/// bit, for every shape and magnitudes from zero to 1e300 (where products
/// overflow to infinity); unused entries stay zero.
#[test]
fn jones_product_is_the_plain_sum_bit_for_bit() {
    let mut rng = rng();
    let shapes = [1usize, 2];
    for _ in 0..CASES / 10 {
        for &rows in &shapes {
            for &inner in &shapes {
                for &cols in &shapes {
                    let mut entries = |r: usize, c: usize| {
                        let mut m = [[Complex64::new(0.0, 0.0); 2]; 2];
                        for row in m.iter_mut().take(r) {
                            for v in row.iter_mut().take(c) {
                                *v = complex(&mut rng) * SCALES[rng.gen_range(0..SCALES.len())];
                            }
                        }
                        Jones::from_entries(r, c, m)
                    };
                    let a = entries(rows, inner);
                    let b = entries(inner, cols);
                    let p = a.product(&b);
                    assert_eq!((p.rows, p.cols), (rows, cols));
                    for r in 0..2 {
                        for c in 0..2 {
                            let want = if r < rows && c < cols {
                                let mut sum = Complex64::new(0.0, 0.0);
                                for k in 0..inner {
                                    sum += a.m[r][k] * b.m[k][c];
                                }
                                sum
                            } else {
                                Complex64::new(0.0, 0.0)
                            };
                            let got = p.m[r][c];
                            let same = |x: f64, y: f64| {
                                x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan())
                            };
                            assert!(
                                same(got.re, want.re) && same(got.im, want.im),
                                "{rows}×{inner} · {inner}×{cols}, entry ({r},{c}): {got} against {want}"
                            );
                        }
                    }
                }
            }
        }
    }
}
