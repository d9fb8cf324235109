//! Property tests of the interface solver over ≥100 000 seeded random
//! configurations: random normals, optic axes, wave directions, incident
//! sides and modes, isotropic/uniaxial/degenerate (n_o = n_e) media on both
//! sides (so crystal↔crystal is included).
//!
//! Laws checked (optics.md §4, §5):
//! - the normal energy flux is conserved: Σ |ã_j|² = 1 within 1e-12;
//! - the energy-normalized scattering matrix over propagating modes is
//!   unitary: ÃᴴÃ = I within 1e-12;
//! - no NaN or Inf anywhere;
//! - closed-form Fresnel and the 4×4 solver agree to 1e-12;
//! - the backward query returns blocks equal to the forward amplitudes.
//!
//! Tolerance 1e-12: amplitudes are O(1) and every quantity is a handful of
//! f64 operations plus a pivoted 4×4 solve (error ~ 10 ε κ(A) with ε = 1.1e-16
//! and well-conditioned systems); we observed maxima quoted in each test's
//! failure message, which stay well under 1e-12.

mod optics_common;

use glam::DVec3;
use num_complex::Complex64;
use optics_common::*;
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

#[test]
fn energy_unitarity_and_finiteness_over_random_configurations() {
    let mut rng = rng(0x5EED_0001);
    let mut worst_energy = 0.0f64;
    let mut worst_unitary = 0.0f64;
    let mut tir = 0usize;
    for case in 0..CONFIGS {
        let (iface, side, mode, k) = uniform_configuration(&mut rng);
        let sc = iface.solve(side, mode, k).unwrap();
        for o in &sc.outgoing {
            assert!(
                c_is_finite(o.amplitude) && c_is_finite(o.normalized) && o.energy.is_finite(),
                "case {case}: non-finite output {o:?}"
            );
            assert!(o.wave.k.is_finite() && o.wave.e.is_finite() && o.wave.h.is_finite());
            assert!(o.wave.ray.is_finite());
            if o.wave.evanescent {
                assert_eq!(o.energy, 0.0);
                tir += 1;
            }
        }
        let err = (sc.energy_sum() - 1.0).abs();
        worst_energy = worst_energy.max(err);
        assert!(
            err < 1e-12,
            "case {case}: energy sum {} ({iface:?}, {side:?}, {mode:?}, k={k})",
            sc.energy_sum()
        );

        // Energy-normalized scattering matrix over every propagating
        // incident mode at this t: columns = incident modes, rows = the
        // propagating outgoing modes.
        let inc = incident_modes(&iface, k);
        let cols: Vec<Vec<Complex64>> = inc
            .iter()
            .map(|w| {
                let s = iface.solve(w.side, w.mode, k).unwrap();
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
        for (i, ci) in cols.iter().enumerate() {
            assert_eq!(ci.len(), cols.len(), "case {case}: S matrix not square");
            for (j, cj) in cols.iter().enumerate() {
                let g: Complex64 = ci.iter().zip(cj).map(|(a, b)| a.conj() * b).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                let e = (g - want).norm();
                worst_unitary = worst_unitary.max(e);
                assert!(e < 1e-12, "case {case}: (ÃᴴÃ)[{i}][{j}] = {g} ({iface:?})");
            }
        }
    }
    eprintln!("worst |Σ energy − 1| = {worst_energy:.2e}, worst |ÃᴴÃ − I| = {worst_unitary:.2e}, evanescent outputs {tir}");
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
        let k = incident_k(&mut rng, &iface, side, mode);
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
        // Outgoing waves w at the t of a random configuration.
        let (iface, _, _, t) = random_configuration(&mut rng);
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
