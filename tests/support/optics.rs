//! Helpers shared by the optics integration tests: random configurations
//! (seeded), incident-wave sampling and small linear-algebra checks. Every
//! physical reference value a test asserts is computed in the test itself,
//! never by the code under test.

use glam::DVec3;
use num_complex::Complex64;
use rand::Rng;
use rand_pcg::Pcg64;
use spar::optics::directions::{k_from_wave_normal, ray_vector};
use spar::optics::{Interface, Medium, Mode, Side};

pub fn rng(seed: u64) -> Pcg64 {
    use rand::SeedableRng;
    Pcg64::seed_from_u64(seed)
}

/// Uniform random unit vector.
pub fn unit(rng: &mut Pcg64) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 1e-3 && l <= 1.0 {
            return v / l;
        }
    }
}

/// A random medium: isotropic, uniaxial, or uniaxial with n_o = n_e.
pub fn medium(rng: &mut Pcg64) -> Medium {
    match rng.gen_range(0..10) {
        0..=3 => Medium::Isotropic {
            n: rng.gen_range(1.0..2.6),
        },
        4 => {
            let n = rng.gen_range(1.3..2.5);
            Medium::Uniaxial {
                n_o: n,
                n_e: n,
                axis: unit(rng),
            }
        }
        _ => Medium::Uniaxial {
            n_o: rng.gen_range(1.3..2.5),
            n_e: rng.gen_range(1.3..2.5),
            axis: unit(rng),
        },
    }
}

/// Wave vector of a random incident `mode` wave on `side`: a random wave
/// normal, flipped if its energy flows away from the interface.
pub fn incident_k(rng: &mut Pcg64, iface: &Interface, side: Side, mode: Mode) -> DVec3 {
    let m = iface.medium(side);
    loop {
        let d = unit(rng);
        let k = k_from_wave_normal(m, mode.kind(), d);
        let sn = ray_vector(m, mode.kind(), k).dot(iface.normal()) * side.sign();
        if sn < 0.0 {
            return k;
        } else if sn > 0.0 {
            return -k;
        }
    }
}

pub fn random_mode(rng: &mut Pcg64, m: &Medium) -> Mode {
    Mode::pair_of(m)[rng.gen_range(0..2)]
}

pub fn c_is_finite(z: Complex64) -> bool {
    z.re.is_finite() && z.im.is_finite()
}

/// Incident wave direction at polar angle `theta` (from the normal, toward
/// the interface, in the x–z plane) for an interface with normal +z.
pub fn dir_at(theta: f64) -> DVec3 {
    DVec3::new(theta.sin(), 0.0, -theta.cos())
}

/// Tangential wave vector for index `n` at angle `theta` in the x–z plane.
pub fn t_at(n: f64, theta: f64) -> DVec3 {
    DVec3::new(n * theta.sin(), 0.0, 0.0)
}

/// Is `a` within `tol` of `b` (absolute)?
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Squared tangential length at which the wave sheets of `m` turn
/// evanescent along the in-plane unit direction `u` (normal `n`): `n²` for
/// an isotropic or ordinary sheet; for the extraordinary sheet the root of
/// Δ(λ u) = 0, where (docs/physics.md §4.3, with a = c·N, b = λ c·u, T = λ)
/// Δ = A − λ² [1/n_e⁴ + κ ((c·u)² + a²)/n_e²].
pub fn critical_tt(m: &Medium, n: DVec3, u: DVec3) -> Vec<f64> {
    match *m {
        Medium::Isotropic { n: idx } => vec![idx * idx],
        Medium::Uniaxial { n_o, n_e, axis } => {
            let ie2 = 1.0 / (n_e * n_e);
            let kappa = 1.0 / (n_o * n_o) - ie2;
            let a = axis.dot(n);
            let bu = axis.dot(u);
            let big_a = ie2 + kappa * a * a;
            let den = ie2 * ie2 + kappa * ie2 * (bu * bu + a * a);
            vec![n_o * n_o, big_a / den]
        }
        // Not used for biaxial media (the stress configurations are
        // isotropic and uniaxial).
        Medium::Biaxial { .. } => Vec::new(),
    }
}

/// A uniformly random configuration: random normal, media, incident side,
/// mode and wave-normal direction.
pub fn uniform_configuration(rng: &mut Pcg64) -> (Interface, Side, Mode, DVec3) {
    let n = unit(rng);
    let iface = Interface::new(n, medium(rng), medium(rng)).unwrap();
    let side = if rng.gen_bool(0.5) {
        Side::Plus
    } else {
        Side::Minus
    };
    let mode = random_mode(rng, iface.medium(side));
    let k = incident_k(rng, &iface, side, mode);
    (iface, side, mode, k)
}

/// A random configuration placed where the numerics are most stressed:
/// half of the cases put `t` within a relative distance 10^-U(1,12)
/// (either way) of the point where one of the four sheets turns evanescent
/// (grazing or critical incidence, any side, any sheet); the other half
/// send an ordinary wave of a crystal whose optic axis lies within ~6° of
/// the interface plane along (±0.6°) the axis' projection, within
/// 10^-U(3,12) of grazing, so that o and e are near-degenerate and near
/// grazing at once.
pub fn stress_configuration(rng: &mut Pcg64) -> (Interface, Side, Mode, DVec3) {
    loop {
        if rng.gen_bool(0.5) {
            let axis = unit(rng);
            let n = unit(rng);
            let n = n - axis * n.dot(axis) * rng.gen_range(0.9..1.0);
            if n.length() < 1e-3 {
                continue;
            }
            let n = n.normalize();
            let n_o = rng.gen_range(1.3..2.5);
            let crystal = Medium::Uniaxial {
                n_o,
                n_e: rng.gen_range(1.3..2.5),
                axis,
            };
            let iface = Interface::new(n, crystal, medium(rng)).unwrap();
            let u = (axis - n * axis.dot(n)).normalize();
            let u = (u + n.cross(u) * rng.gen_range(-0.01..0.01)).normalize();
            let d = 10f64.powf(-rng.gen_range(3.0..12.0));
            let t = u * (n_o * (1.0 - d));
            if iface
                .incident_wave(Side::Plus, Mode::O, t)
                .map(|w| w.flux != 0.0)
                .unwrap_or(false)
            {
                return (iface, Side::Plus, Mode::O, t);
            }
            continue;
        }
        let n = unit(rng);
        let iface = Interface::new(n, medium(rng), medium(rng)).unwrap();
        let nn = iface.normal();
        let u = {
            let v = unit(rng);
            let t = v - nn * v.dot(nn);
            if t.length() < 1e-3 {
                continue;
            }
            t.normalize()
        };
        let crits: Vec<f64> = critical_tt(iface.medium(Side::Plus), nn, u)
            .into_iter()
            .chain(critical_tt(iface.medium(Side::Minus), nn, u))
            .collect();
        let tt = crits[rng.gen_range(0..crits.len())];
        if tt.is_nan() || tt <= 0.0 {
            continue;
        }
        let delta =
            10f64.powf(-rng.gen_range(1.0..12.0)) * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
        let t = u * (tt.sqrt() * (1.0 + delta));
        let candidates: Vec<(Side, Mode)> = [Side::Plus, Side::Minus]
            .iter()
            .flat_map(|&s| {
                Mode::pair_of(iface.medium(s))
                    .into_iter()
                    .map(move |m| (s, m))
            })
            .filter(|&(s, m)| {
                iface
                    .incident_wave(s, m, t)
                    .map(|w| w.flux != 0.0)
                    .unwrap_or(false)
            })
            .collect();
        if candidates.is_empty() {
            continue;
        }
        let (side, mode) = candidates[rng.gen_range(0..candidates.len())];
        return (iface, side, mode, t);
    }
}

/// Conditioning of the modal energy balance of one solve (see
/// `optics_properties.rs`, "near-critical stress"): ε n_max² / (|F_i| g),
/// where g is the smallest gap |q_j − q_k*| between the normal components
/// of two waves of different sheets (o vs e) on the same side, among the
/// incident wave and the outgoing ones (evanescent included). No such pair:
/// ε n_max² / |F_i|.
pub fn energy_conditioning(iface: &Interface, sc: &spar::optics::Scattering) -> f64 {
    let eps = f64::EPSILON;
    let nmax = [Side::Plus, Side::Minus]
        .iter()
        .map(|&s| match *iface.medium(s) {
            Medium::Isotropic { n } => n,
            Medium::Uniaxial { n_o, n_e, .. } => n_o.max(n_e),
            Medium::Biaxial { n, .. } => n.into_iter().fold(0.0, f64::max),
        })
        .fold(0.0, f64::max);
    let mut waves: Vec<&spar::optics::Eigenwave> = vec![&sc.incident];
    waves.extend(sc.outgoing.iter().map(|o| &o.wave));
    let mut gap = f64::INFINITY;
    for (i, a) in waves.iter().enumerate() {
        for b in &waves[i + 1..] {
            let sheets_differ = a.mode.kind() != b.mode.kind();
            if a.side == b.side && sheets_differ {
                // Cross fluxes of exact modes vanish because
                // (q_a − q_b*) C_ab = 0; with rounded fields C_ab ≈ residual
                // / |q_a − q_b*|.
                gap = gap.min((a.q - b.q.conj()).norm());
            }
        }
    }
    eps * nmax * nmax / (sc.incident.flux.abs() * gap.min(1.0))
}
