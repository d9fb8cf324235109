//! Property tests of the interface solver over seeded random
//! configurations: random normals, optic axes, wave directions, incident
//! sides and modes, isotropic/uniaxial/degenerate (n_o = n_e) media on both
//! sides (so crystal↔crystal is included).
//!
//! Laws checked (docs/physics.md §4.4–4.7):
//! - the normal energy flux is conserved: Σ |ã_j|² = 1;
//! - the energy-normalized scattering matrix over propagating modes is
//!   unitary: ÃᴴÃ = I;
//! - no NaN or Inf anywhere;
//! - closed-form Fresnel and the 4×4 solver agree to 1e-12;
//! - the backward query returns blocks equal to the forward amplitudes
//!   (1e-12).
//!
//! Tolerances. 100 000 uniformly random configurations must conserve energy
//! and be unitary to 1e-12 absolute: amplitudes are O(1) and each is a
//! handful of f64 operations and a pivoted 4×4 solve of a well-conditioned
//! system (observed maximum ~1.4e-13).
//!
//! A second set of 100 000 configurations is placed where the modal energy
//! balance is ill-conditioned (near grazing and critical incidence of every
//! sheet, and o/e near-degenerate near grazing). There the balance
//! Σ |a_j|² |F_j| / |F_i| = 1 relies on the cross fluxes C_jk between
//! different modes on one side vanishing; for exact modes
//! (q_j − q_k*) C_jk = 0, and with fields stored in f64 (eigen-equation
//! residual ~ ε n²) C_jk ≈ ε n² / |q_j − q_k*|. Divided by the incident flux
//! that bounds the error by B = ε n_max² / (|F_i| g), g the smallest such
//! gap between an o and an e wave on one side (`energy_conditioning`). The
//! test asserts |Σ − 1| ≤ 1e-12 + 4 B: the absolute 1e-12 as before, plus
//! the conditioning bound with a factor 4 of margin (the worst observed
//! ratio of error to B over 400 000 such cases was 1.12). 99% of these
//! cases still meet 1e-12 outright; the test prints the count.

use crate::support::optics::*;
use glam::DVec3;
use num_complex::Complex64;
use rand::Rng;
use spar::optics::modes::Travel;
use spar::optics::{Eigenwave, Interface, Medium, Mode, Side, WaveKind};

const CONFIGS: usize = 100_000;

/// All propagating incident modes (with non-zero flux) at tangential `t`.
fn incident_modes(iface: &Interface, t: DVec3) -> Vec<Eigenwave> {
    let mut v = Vec::new();
    for side in [Side::Plus, Side::Minus] {
        for mode in Mode::pair_of(iface.medium(side)) {
            if let Ok(w) = iface.incident_wave(side, mode, t) {
                if w.flux != 0.0 {
                    v.push(w);
                }
            }
        }
    }
    v
}

/// Check one configuration; returns (energy error, unitarity error,
/// conditioning bound B).
fn check_configuration(
    case: usize,
    iface: &Interface,
    side: Side,
    mode: Mode,
    k: DVec3,
    tol: impl Fn(f64) -> f64,
) -> (f64, f64, f64) {
    let sc = iface.solve(side, mode, k).unwrap();
    for o in &sc.outgoing {
        assert!(
            c_is_finite(o.amplitude) && c_is_finite(o.normalized) && o.energy.is_finite(),
            "case {case}: non-finite output {o:?}"
        );
        assert!(o.wave.k.is_finite() && o.wave.e.is_finite() && o.wave.h.is_finite());
        assert!(o.wave.ray.is_finite() && o.wave.flux.is_finite());
        if o.wave.evanescent {
            assert_eq!(o.energy, 0.0);
        }
    }
    let b = if sc.incident.flux != 0.0 {
        energy_conditioning(iface, &sc)
    } else {
        0.0
    };
    let err = (sc.energy_sum() - 1.0).abs();
    assert!(
        err <= tol(b),
        "case {case}: energy sum {} (bound {:.2e}; {iface:?}, {side:?}, {mode:?}, k={k})",
        sc.energy_sum(),
        tol(b)
    );

    // Energy-normalized scattering matrix over every propagating incident
    // mode at this t: columns = incident modes, rows = the propagating
    // outgoing modes.
    let inc = incident_modes(iface, k);
    let mut bounds = Vec::new();
    let cols: Vec<Vec<Complex64>> = inc
        .iter()
        .map(|w| {
            let s = iface.solve(w.side, w.mode, k).unwrap();
            bounds.push(energy_conditioning(iface, &s));
            // Physical-side order [+0, +1, -0, -1], propagating only.
            let mut col = Vec::new();
            for out_side in [Side::Plus, Side::Minus] {
                for m in Mode::pair_of(iface.medium(out_side)) {
                    let o = s.find(out_side, m).unwrap();
                    if !o.wave.evanescent && o.wave.flux != 0.0 {
                        col.push(o.normalized);
                    }
                }
            }
            col
        })
        .collect();
    let mut worst_unitary = 0.0f64;
    for (i, ci) in cols.iter().enumerate() {
        assert_eq!(ci.len(), cols.len(), "case {case}: S matrix not square");
        for (j, cj) in cols.iter().enumerate() {
            let g: Complex64 = ci.iter().zip(cj).map(|(a, b)| a.conj() * b).sum();
            let want = if i == j { 1.0 } else { 0.0 };
            let e = (g - want).norm();
            worst_unitary = worst_unitary.max(e);
            let t = tol(bounds[i].max(bounds[j]));
            assert!(
                e <= t,
                "case {case}: (ÃᴴÃ)[{i}][{j}] = {g}, bound {t:.2e} ({iface:?})"
            );
        }
    }
    (err, worst_unitary, b)
}

#[test]
fn energy_unitarity_and_finiteness_over_uniform_random_configurations() {
    let mut rng = rng(0x5EED_0001);
    let (mut worst_energy, mut worst_unitary) = (0.0f64, 0.0f64);
    for case in 0..CONFIGS {
        let (iface, side, mode, k) = uniform_configuration(&mut rng);
        let (e, u, _) = check_configuration(case, &iface, side, mode, k, |_| 1e-12);
        worst_energy = worst_energy.max(e);
        worst_unitary = worst_unitary.max(u);
    }
    eprintln!(
        "uniform: worst |Σ energy − 1| = {worst_energy:.2e}, worst |ÃᴴÃ − I| = {worst_unitary:.2e}"
    );
}

#[test]
fn energy_unitarity_and_finiteness_near_critical_and_degenerate_configurations() {
    let mut rng = rng(0x5EED_0004);
    let (mut worst_energy, mut worst_ratio, mut within_1e12) = (0.0f64, 0.0f64, 0usize);
    for case in 0..CONFIGS {
        let (iface, side, mode, t) = stress_configuration(&mut rng);
        let (e, _, b) = check_configuration(case, &iface, side, mode, t, |b| 1e-12 + 4.0 * b);
        worst_energy = worst_energy.max(e);
        if e > 1e-12 {
            worst_ratio = worst_ratio.max(e / b);
        } else {
            within_1e12 += 1;
        }
    }
    eprintln!(
        "stress: worst |Σ energy − 1| = {worst_energy:.2e}, {within_1e12} of {CONFIGS} within 1e-12, \
         worst error/B above 1e-12 = {worst_ratio:.2}"
    );
}

#[test]
fn closed_form_agrees_with_the_4x4_solver() {
    let mut rng = rng(0x5EED_0002);
    let mut worst = 0.0f64;
    for case in 0..CONFIGS {
        let n = unit(&mut rng);
        let n1 = rng.gen_range(1.0..2.6);
        // A quarter of the cases with equal indices, many under TIR.
        let n2 = if rng.gen_range(0..4) == 0 {
            n1
        } else {
            rng.gen_range(1.0..2.6)
        };
        let iface =
            Interface::new(n, Medium::Isotropic { n: n1 }, Medium::Isotropic { n: n2 }).unwrap();
        let side = if rng.gen_bool(0.5) {
            Side::Plus
        } else {
            Side::Minus
        };
        let mode = random_mode(&mut rng, iface.medium(side));
        let mut k = incident_k(&mut rng, &iface, side, mode);
        if case % 2 == 1 {
            // Half of the cases within 10^-U(1,12) of grazing or of the
            // critical angle. Near grazing the solver's transmitted ã =
            // a sqrt(Q₂/Q₁) carries an absolute error ≈ ε sqrt(Q₂/Q₁), with
            // Q₁ ≥ n sqrt(2·1e-12) here: below 1e-13·n^½, inside 1e-12.
            let nn = iface.normal();
            let u = (k - nn * k.dot(nn)).normalize_or_zero();
            let nc = if rng.gen_bool(0.5) {
                n1.min(n2)
            } else {
                n1.max(n2)
            };
            let nc = nc.min(if side == Side::Plus { n1 } else { n2 });
            let d = 10f64.powf(-rng.gen_range(1.0..12.0));
            k = u * (nc * (1.0 - d));
            if u == DVec3::ZERO {
                continue;
            }
        }
        let a = iface.solve_closed_form(side, mode, k).unwrap();
        let b = iface.solve_4x4(side, mode, k).unwrap();
        for (x, y) in a.outgoing.iter().zip(&b.outgoing) {
            assert_eq!((x.wave.side, x.wave.mode), (y.wave.side, y.wave.mode));
            let e = (x.amplitude - y.amplitude)
                .norm()
                .max((x.normalized - y.normalized).norm());
            worst = worst.max(e);
            assert!(e < 1e-12, "case {case}: closed {x:?} vs 4x4 {y:?}");
        }
    }
    eprintln!("worst closed-form vs 4×4 difference {worst:.2e}");
}

/// Forward amplitude ã of incident (side, mode) into outgoing (side, mode).
fn forward(iface: &Interface, inc: (Side, Mode), out: (Side, Mode), t: DVec3) -> Complex64 {
    iface
        .solve(inc.0, inc.1, t)
        .unwrap()
        .find(out.0, out.1)
        .unwrap()
        .normalized
}

fn modes_of(kind: WaveKind) -> &'static [Mode] {
    match kind {
        WaveKind::Isotropic => &[Mode::S, Mode::P],
        WaveKind::Ordinary => &[Mode::O],
        WaveKind::Extraordinary => &[Mode::E],
        WaveKind::Fast => &[Mode::Fast],
        WaveKind::Slow => &[Mode::Slow],
    }
}

#[test]
fn backward_query_equals_the_forward_amplitudes() {
    let mut rng = rng(0x5EED_0003);
    let mut worst_t = 0.0f64;
    let mut worst_ray = 0.0f64;
    let mut worst_dt = 0.0f64;
    let mut feeders_seen = 0usize;
    for case in 0..CONFIGS {
        // Outgoing waves w at the t of a random configuration, half of them
        // uniform, half near critical points.
        let (iface, _, _, t) = if case % 2 == 0 {
            uniform_configuration(&mut rng)
        } else {
            stress_configuration(&mut rng)
        };
        let frame = iface.frame(t);
        for w_side in [Side::Plus, Side::Minus] {
            let w_medium = *iface.medium(w_side);
            for &kind in WaveKind::all_of(&w_medium) {
                let w = Eigenwave::new(
                    &w_medium,
                    &frame,
                    w_side,
                    Travel::Outgoing,
                    kind.first_mode(),
                )
                .unwrap();
                if w.evanescent || w.flux == 0.0 {
                    continue;
                }
                let fb = iface.feeders_tangential(w_side, kind, t).unwrap();
                // Every propagating incident wave with flux appears exactly once.
                let expected: usize = [Side::Plus, Side::Minus]
                    .iter()
                    .map(|&s| {
                        WaveKind::all_of(iface.medium(s))
                            .iter()
                            .filter(|k| {
                                iface
                                    .incident_wave(s, k.first_mode(), t)
                                    .map(|x| x.flux != 0.0)
                                    .unwrap_or(false)
                            })
                            .count()
                    })
                    .sum();
                assert_eq!(fb.len(), expected, "case {case}: feeder count");
                for f in fb.as_slice() {
                    feeders_seen += 1;
                    assert_eq!(f.block.rows, kind.mode_count());
                    assert_eq!(f.block.cols, f.wave.kind.mode_count());
                    for (c, &im) in modes_of(f.wave.kind).iter().enumerate() {
                        for (r, &om) in modes_of(kind).iter().enumerate() {
                            let want = forward(&iface, (f.wave.side, im), (w_side, om), t);
                            let e = (f.block.m[r][c] - want).norm();
                            worst_t = worst_t.max(e);
                            assert!(
                                e < 1e-12,
                                "case {case}: block[{r}][{c}] {} vs forward {want}",
                                f.block.m[r][c]
                            );
                        }
                    }
                }
                // The renderer's entry point: from the ray direction. Its
                // tangential component must reproduce t to rounding, and its
                // blocks must equal the forward amplitudes at the t it
                // reconstructed. (Comparing with the blocks at the original
                // t instead would test the conditioning of ã(t), which has
                // square-root branch points at grazing: δã/ã ≈ n δt / 2Q².)
                let fr = iface.feeders(w_side, kind, w.ray).unwrap();
                let nn = iface.normal();
                let dt = (fr.frame.t - (t - nn * t.dot(nn))).length();
                worst_dt = worst_dt.max(dt);
                assert!(dt < 1e-14, "case {case}: t from ray differs by {dt}");
                assert_eq!(fr.len(), fb.len(), "case {case}");
                for f in fr.as_slice() {
                    for (c, &im) in modes_of(f.wave.kind).iter().enumerate() {
                        for (r, &om) in modes_of(kind).iter().enumerate() {
                            let want = iface
                                .solve_in(f.wave.side, im, &fr.frame)
                                .unwrap()
                                .find(w_side, om)
                                .unwrap()
                                .normalized;
                            let e = (f.block.m[r][c] - want).norm();
                            worst_ray = worst_ray.max(e);
                            assert!(
                                e < 1e-12,
                                "case {case}: ray query block[{r}][{c}] {} vs forward {want}",
                                f.block.m[r][c]
                            );
                        }
                    }
                }
            }
        }
    }
    eprintln!("worst backward-vs-forward {worst_t:.2e}, ray query {worst_ray:.2e}, |δt| {worst_dt:.2e}, feeders {feeders_seen}");
}
