//! Uniaxial crystals against docs/physics.md §8.3 and first principles: calcite
//! walk-off and the calcite slab, Malus's law with calcite as the analyzer,
//! the reduction to the isotropic answer when n_o = n_e, Maxwell's equations
//! for every eigenwave, and the energy rule for choosing roots. Expected
//! values are computed here from their own formulas.

use crate::support::optics::*;
use glam::DVec3;
use num_complex::Complex64;
use rand::Rng;
use spar::optics::linalg::CVec3;
use spar::optics::{Eigenwave, Interface, Medium, Mode, Scattering, Side};

const N_O: f64 = 1.6584;
const N_E: f64 = 1.4864;

fn calcite(axis: DVec3) -> Medium {
    Medium::Uniaxial {
        n_o: N_O,
        n_e: N_E,
        axis: axis.normalize(),
    }
}

const AIR: Medium = Medium::Isotropic { n: 1.0 };

/// Index of the extraordinary wave whose wave normal makes angle θ with the
/// axis: 1/n(θ)² = cos²θ/n_o² + sin²θ/n_e² (docs/physics.md §4.3).
fn n_theta(theta: f64) -> f64 {
    1.0 / ((theta.cos() / N_O).powi(2) + (theta.sin() / N_E).powi(2)).sqrt()
}

/// Walk-off angle: tan ρ = ½ n(θ)² (1/n_e² − 1/n_o²) sin 2θ (docs/physics.md §4.3).
fn tan_walk_off(theta: f64) -> f64 {
    0.5 * n_theta(theta).powi(2) * (1.0 / (N_E * N_E) - 1.0 / (N_O * N_O)) * (2.0 * theta).sin()
}

/// Normal-incidence transmittance between index 1 and index n:
/// 4n/(1 + n)² (B&W §1.5, normal incidence).
fn t_normal(n: f64) -> f64 {
    4.0 * n / (1.0 + n).powi(2)
}

fn ellipticity(e: CVec3) -> f64 {
    let tot = e.norm_sqr();
    let lin = e.dot(e).norm();
    ((tot - lin) / (tot + lin)).max(0.0).sqrt()
}

fn axis45() -> DVec3 {
    DVec3::new(1.0, 0.0, 1.0).normalize()
}

#[test]
fn calcite_walk_off_is_6_22_degrees() {
    // Air → calcite at normal incidence, axis 45° to the face: the
    // refracted wave normal is 45° from the axis.
    let g = Interface::new(DVec3::Z, AIR, calcite(axis45())).unwrap();
    let sc = g.solve(Side::Plus, Mode::S, DVec3::ZERO).unwrap();
    let e = sc.find(Side::Minus, Mode::E).unwrap().wave;
    let k = e.k.re.normalize();
    assert!((k + DVec3::Z).length() < 1e-15, "k ∥ −z");
    let rho = e.ray.angle_between(k);
    let want = tan_walk_off(45f64.to_radians());
    assert!(
        close(rho.tan(), want, 1e-13),
        "tan ρ = {} vs {want}",
        rho.tan()
    );
    assert_eq!(format!("{:.2}", rho.to_degrees()), "6.22");
    // The ordinary ray does not walk off.
    let o = sc.find(Side::Minus, Mode::O).unwrap().wave;
    assert!(o.ray.angle_between(o.k.re) < 1e-15);
}

/// Field leaving the slab's exit face for a unit incident wave `mode`
/// inside, with the exit interface `b`.
fn exit(b: &Interface, mode: Mode) -> Scattering {
    b.solve(Side::Plus, mode, DVec3::ZERO).unwrap()
}

#[test]
fn calcite_slab_splits_unpolarized_light_into_two_parallel_orthogonal_beams() {
    let d = 1.0;
    let a = Interface::new(DVec3::Z, AIR, calcite(axis45())).unwrap();
    let b = Interface::new(DVec3::Z, calcite(axis45()), AIR).unwrap();
    let entry = [Mode::S, Mode::P].map(|m| a.solve(Side::Plus, m, DVec3::ZERO).unwrap());

    // Inside: the o ray goes straight, the e ray walks off by ρ.
    let e_in = entry[0].find(Side::Minus, Mode::E).unwrap().wave;
    let o_in = entry[0].find(Side::Minus, Mode::O).unwrap().wave;
    let shift = |w: &Eigenwave| d * (w.ray - DVec3::Z * w.ray.z).length() / w.ray.z.abs();
    let want = d * tan_walk_off(45f64.to_radians());
    assert!(
        close(shift(&e_in), want, 1e-13),
        "{} vs {want}",
        shift(&e_in)
    );
    assert!((shift(&e_in) - 0.109 * d).abs() < 5e-4);
    assert!(shift(&o_in) < 1e-15);

    // Out: both beams leave along −z (parallel).
    let out_o = exit(&b, Mode::O);
    let out_e = exit(&b, Mode::E);
    for sc in [&out_o, &out_e] {
        for o in sc.transmitted() {
            assert!((o.wave.ray + DVec3::Z).length() < 1e-15);
        }
    }

    // Each exit beam is linearly polarized (the beam is one eigenwave
    // inside, so every incident polarization maps onto the same exit
    // vector), and the two are orthogonal.
    let fo = out_o.field_on(Side::Minus);
    let fe = out_e.field_on(Side::Minus);
    assert!(ellipticity(fo) < 1e-14 && ellipticity(fe) < 1e-14);
    let overlap = fo.dot(fe.conj()).norm() / (fo.norm_sqr() * fe.norm_sqr()).sqrt();
    assert!(overlap < 1e-14, "overlap {overlap}");
    // Unpolarized light: J_out = ½ Σ_m v_m v_mᴴ over incident s and p; with
    // v_m ∝ one vector, det J = 0 and P = 1.
    for (mode, out) in [(Mode::O, &out_o), (Mode::E, &out_e)] {
        let exit_energy: f64 = out.transmitted().iter().map(|o| o.energy).sum();
        let v: Vec<[Complex64; 2]> = entry
            .iter()
            .map(|sc| {
                let a = sc.find(Side::Minus, mode).unwrap().normalized;
                [
                    a * out.transmitted()[0].normalized,
                    a * out.transmitted()[1].normalized,
                ]
            })
            .collect();
        let j = |r: usize, c: usize| 0.5 * v.iter().map(|x| x[r] * x[c].conj()).sum::<Complex64>();
        let tr = (j(0, 0) + j(1, 1)).re;
        let det = (j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0)).re;
        let p = (1.0 - 4.0 * det / (tr * tr)).max(0.0).sqrt();
        assert!(close(p, 1.0, 1e-12), "{mode:?}: P = {p}");

        // Power: half of the unpolarized beam enters each eigenmode; the
        // Fresnel losses at normal incidence follow from the tangential
        // impedance of each wave: n_o for o, n(45°) for e (its tangential H
        // over tangential E is |q| = n(θ)), once in and once out.
        let entered = 0.5
            * entry
                .iter()
                .map(|sc| sc.find(Side::Minus, mode).unwrap().energy)
                .sum::<f64>();
        let n_w = if mode == Mode::O {
            N_O
        } else {
            n_theta(45f64.to_radians())
        };
        let t = t_normal(n_w);
        assert!(
            close(entered, 0.5 * t, 1e-14),
            "{mode:?}: entered {entered} vs {}",
            0.5 * t
        );
        assert!(
            close(exit_energy, t, 1e-14),
            "{mode:?}: exit {exit_energy} vs {t}"
        );
        assert!(
            close(tr, 0.5 * t * t, 1e-14),
            "{mode:?}: beam {tr} vs {}",
            0.5 * t * t
        );
    }
}

#[test]
fn malus_law_with_calcite_as_the_analyzer() {
    // Normal incidence on calcite, axis 45° in the x–z plane: the ordinary
    // field is along y, the extraordinary one along x. Light linear at φ to
    // y sends T_o cos²φ into o and T_e sin²φ into e.
    let g = Interface::new(DVec3::Z, AIR, calcite(axis45())).unwrap();
    let s = g.solve(Side::Plus, Mode::S, DVec3::ZERO).unwrap();
    let p = g.solve(Side::Plus, Mode::P, DVec3::ZERO).unwrap();
    let (t_o, t_e) = (t_normal(N_O), t_normal(n_theta(45f64.to_radians())));
    for i in 0..=24 {
        let phi = f64::from(i) * std::f64::consts::PI / 24.0;
        let e_in = DVec3::new(phi.sin(), phi.cos(), 0.0);
        let (cs, cp) = (e_in.dot(s.incident.e.re), e_in.dot(p.incident.e.re));
        let amp = |m: Mode| {
            s.find(Side::Minus, m).unwrap().normalized * cs
                + p.find(Side::Minus, m).unwrap().normalized * cp
        };
        let (eo, ee) = (amp(Mode::O).norm_sqr(), amp(Mode::E).norm_sqr());
        assert!(
            close(eo, t_o * phi.cos().powi(2), 1e-14),
            "φ = {phi}: o {eo}"
        );
        assert!(
            close(ee, t_e * phi.sin().powi(2), 1e-14),
            "φ = {phi}: e {ee}"
        );
    }
}

/// The incident field vector decomposed on an isotropic incident wave's
/// (s, p) — both real and orthonormal for a propagating wave.
fn as_isotropic(
    iso: &Interface,
    side: Side,
    k: DVec3,
    e: CVec3,
) -> (Scattering, Scattering, Complex64, Complex64) {
    let s = iso.solve(side, Mode::S, k).unwrap();
    let p = iso.solve(side, Mode::P, k).unwrap();
    let (cs, cp) = (e.dot_real(s.incident.e.re), e.dot_real(p.incident.e.re));
    (s, p, cs, cp)
}

#[test]
fn equal_indices_reduce_to_the_isotropic_answer() {
    let mut rng = rng(23);
    let mut worst = 0.0f64;
    for case in 0..20_000 {
        let n = unit(&mut rng);
        let (n1, n2) = (rng.gen_range(1.0..2.5), rng.gen_range(1.0..2.5));
        let fake = |idx: f64, rng: &mut rand_pcg::Pcg64| Medium::Uniaxial {
            n_o: idx,
            n_e: idx,
            axis: unit(rng),
        };
        let (plus, minus) = match case % 3 {
            0 => (fake(n1, &mut rng), Medium::Isotropic { n: n2 }),
            1 => (Medium::Isotropic { n: n1 }, fake(n2, &mut rng)),
            _ => (fake(n1, &mut rng), fake(n2, &mut rng)),
        };
        let crystal = Interface::new(n, plus, minus).unwrap();
        let iso =
            Interface::new(n, Medium::Isotropic { n: n1 }, Medium::Isotropic { n: n2 }).unwrap();
        let side = if rng.gen_bool(0.5) {
            Side::Plus
        } else {
            Side::Minus
        };
        let mode = random_mode(&mut rng, crystal.medium(side));
        let k = incident_k(&mut rng, &crystal, side, mode);
        let sc = crystal.solve(side, mode, k).unwrap();
        // The same physical incident field in the isotropic problem.
        let (s, p, cs, cp) = as_isotropic(&iso, side, k, sc.incident.e);
        assert!((cs.norm_sqr() + cp.norm_sqr() - 1.0).abs() < 1e-14);
        for out_side in [Side::Plus, Side::Minus] {
            let want = s.field_on(out_side).scale(cs) + p.field_on(out_side).scale(cp);
            let got = sc.field_on(out_side);
            let e = (got - want).norm_sqr().sqrt();
            worst = worst.max(e);
            assert!(
                e < 1e-12,
                "case {case}: {out_side:?} field {got:?} vs {want:?}"
            );
            let energy = |x: &Scattering| -> f64 {
                x.outgoing
                    .iter()
                    .filter(|o| o.wave.side == out_side)
                    .map(|o| o.energy)
                    .sum()
            };
            // Incoherent energies add for orthogonal s/p inputs only after
            // recombining amplitudes: compare the crystal's total with the
            // isotropic total of the combined field.
            let iso_energy: f64 = [0usize, 1]
                .iter()
                .map(|&m| {
                    let a = s
                        .outgoing
                        .iter()
                        .chain(&p.outgoing)
                        .filter(|o| o.wave.side == out_side)
                        .collect::<Vec<_>>();
                    let sm = a[m].normalized * cs + a[m + 2].normalized * cp;
                    sm.norm_sqr()
                })
                .sum();
            assert!(
                close(energy(&sc), iso_energy, 1e-12),
                "case {case}: {} vs {iso_energy}",
                energy(&sc)
            );
        }
    }
    eprintln!("n_o = n_e vs isotropic: worst field difference {worst:.2e}");
}

fn epsilon_times(m: &Medium, e: CVec3) -> CVec3 {
    match *m {
        Medium::Isotropic { n } => e * (n * n),
        Medium::Uniaxial { n_o, n_e, axis } => {
            e * (n_o * n_o) + CVec3::real(axis).scale(e.dot_real(axis) * (n_e * n_e - n_o * n_o))
        }
        Medium::Biaxial { n, x, z } => [x, z.cross(x), z]
            .iter()
            .zip(n)
            .fold(CVec3::ZERO, |acc, (a, ni)| {
                acc + CVec3::real(*a).scale(e.dot_real(*a) * (ni * ni))
            }),
    }
}

#[test]
fn every_eigenwave_satisfies_maxwell_and_the_energy_rule() {
    let mut rng = rng(29);
    for case in 0..20_000 {
        let (iface, side, mode, k) = uniform_configuration(&mut rng);
        let sc = iface.solve(side, mode, k).unwrap();
        let nn = iface.normal();
        let mut waves = vec![sc.incident];
        waves.extend(sc.outgoing.iter().map(|o| o.wave));
        for w in waves {
            let m = iface.medium(w.side);
            let nmax = match *m {
                Medium::Isotropic { n } => n,
                Medium::Uniaxial { n_o, n_e, .. } => n_o.max(n_e),
                Medium::Biaxial { n, .. } => n.into_iter().fold(0.0, f64::max),
            };
            // Unit field (an evanescent p wave keeps E = k × s / n, the
            // vector the textbook tp refers to).
            if !(w.evanescent && w.mode == Mode::P) {
                assert!(close(w.e.norm_sqr(), 1.0, 1e-14), "case {case}");
            }
            // Wave equation k × (k × E) + ε E = 0 (B&W §15.2).
            let res = w.k.cross(w.k.cross(w.e)) + epsilon_times(m, w.e);
            assert!(
                res.norm_sqr().sqrt() < 1e-13 * nmax * nmax,
                "case {case}: {w:?} residual {res:?}"
            );
            // D = εE is transverse to k; H = k × E.
            let d = epsilon_times(m, w.e);
            assert!(d.dot(w.k).norm() < 1e-13 * nmax * nmax);
            assert!((w.h - w.k.cross(w.e)).norm_sqr() < 1e-28);
            match (w.mode, *m) {
                (Mode::O, Medium::Uniaxial { axis, .. }) => {
                    assert!(w.e.dot_real(axis).norm() < 1e-14)
                }
                (Mode::E, Medium::Uniaxial { axis, .. }) => {
                    // D in the plane of k and c.
                    let kc = w.k.cross_real(axis);
                    assert!(
                        d.dot(kc).norm() < 1e-13 * nmax * nmax * kc.norm_sqr().sqrt().max(1e-300)
                    );
                }
                _ => {}
            }
            // Flux and ray from the Poynting vector Re(E × H*)/2.
            let poynting = w.e.cross(w.h.conj()).re * 0.5;
            assert!(
                (poynting.dot(nn) - w.flux).abs() < 1e-14 * nmax,
                "case {case}: flux {} vs {}",
                poynting.dot(nn),
                w.flux
            );
            let sigma = w.side.sign();
            if w.evanescent {
                assert_eq!(w.flux, 0.0);
                assert!(
                    sigma * w.q.im > 0.0,
                    "case {case}: evanescent wave must decay away"
                );
            } else {
                assert!(
                    poynting.normalize().cross(w.ray).length() < 1e-12,
                    "case {case}: ray"
                );
                let outgoing = sigma * w.ray.dot(nn);
                match w.travel {
                    spar::optics::modes::Travel::Outgoing => assert!(outgoing >= 0.0),
                    spar::optics::modes::Travel::Incoming => assert!(outgoing <= 0.0),
                }
            }
        }
    }
}

#[test]
fn roots_are_chosen_by_energy_not_by_the_wave_vector() {
    // Calcite on side + with its axis 45° in the x–z plane, t along +x. For
    // the incident e wave q = (−β − √Δ)/A with β = (n_e² − n_o²) a b < 0,
    // so close to grazing k·N > 0 — k points away from the interface —
    // while the energy flows toward it (docs/physics.md §4.1).
    let c = axis45();
    let g = Interface::new(DVec3::Z, calcite(c), AIR).unwrap();
    let mut found = 0;
    // The e sheet grazes at T = sqrt((n_o² + n_e²)/2) ≈ 1.575 along x.
    for i in 1..20_000 {
        let tx = 1.50 + 1e-5 * f64::from(i);
        let Ok(w) = g.incident_wave(Side::Plus, Mode::E, DVec3::new(tx, 0.0, 0.0)) else {
            break;
        };
        // The ray from docs/physics.md §4.3, computed here: S ∝ k/n_e² + κ (k·c) c.
        let k = w.k.re;
        let kappa = 1.0 / (N_O * N_O) - 1.0 / (N_E * N_E);
        let s = k / (N_E * N_E) + c * (kappa * k.dot(c));
        assert!(
            s.z < 0.0 || w.flux == 0.0,
            "incident e wave must carry energy toward the interface"
        );
        if k.z > 0.0 && s.z < 0.0 {
            found += 1;
            let sc = g.solve(Side::Plus, Mode::E, k).unwrap();
            assert!((sc.energy_sum() - 1.0).abs() < 1e-12);
            // The direction API agrees: this k (pointing into side +) is an
            // incident wave, and its reverse is not.
            assert!(g.incident_k(Side::Plus, Mode::E, k).is_ok());
            assert!(g.incident_k(Side::Plus, Mode::E, -k).is_err());
        }
    }
    assert!(found > 0, "no case where k and S point to different sides");
}
