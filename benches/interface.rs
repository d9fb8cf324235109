//! Interface solves per second (criterion): closed-form Fresnel, the same
//! isotropic problem through the 4×4 solver, uniaxial and biaxial forward
//! solves, and the renderer's backward query for glass, calcite and a
//! topaz-like biaxial crystal (the general eigenwave solver).
//!
//! Run: `cargo bench --no-default-features --bench interface`. Each
//! iteration solves a batch of 1024 precomputed random configurations, so
//! criterion's throughput line reads directly as solves per second.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::optics::fresnel::fresnel;
use spar::optics::{Interface, Medium, Mode, Side, WaveKind};

const BATCH: usize = 1024;

fn unit(rng: &mut Pcg64) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        if v.length() > 1e-3 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Directions in the half space `σ d·z > 0` (σ = +1 or −1).
fn directions(rng: &mut Pcg64, sigma: f64) -> Vec<DVec3> {
    (0..BATCH)
        .map(|_| {
            let d = unit(rng);
            if sigma * d.z > 0.0 {
                d
            } else {
                -d
            }
        })
        .collect()
}

fn calcite() -> Medium {
    Medium::Uniaxial {
        n_o: 1.6584,
        n_e: 1.4864,
        axis: DVec3::new(0.3, -0.5, 0.8).normalize(),
    }
}

/// Topaz-like principal indices (2V ≈ 57°), crystal axes tilted.
fn topaz_like() -> Medium {
    Medium::biaxial(
        [1.6093, 1.6116, 1.6194],
        DVec3::new(0.3, 0.5, 0.8).normalize(),
        DVec3::new(1.0, 0.0, 0.2),
    )
    .unwrap()
}

fn bench(c: &mut Criterion) {
    let mut rng = Pcg64::seed_from_u64(1);
    let air = Medium::Isotropic { n: 1.0 };
    let glass = Medium::Isotropic { n: 1.5168 };
    let g = Interface::new(DVec3::Z, air, glass).unwrap();
    let cal_in = Interface::new(DVec3::Z, air, calcite()).unwrap();
    let cal_out = Interface::new(DVec3::Z, calcite(), air).unwrap();
    let bx_in = Interface::new(DVec3::Z, air, topaz_like()).unwrap();
    let bx_out = Interface::new(DVec3::Z, topaz_like(), air).unwrap();

    // Incident wave vectors from side + (toward −z).
    let down = directions(&mut rng, -1.0);
    let k_air: Vec<DVec3> = down.iter().map(|d| *d * 1.0).collect();
    let k_cal: Vec<DVec3> = down
        .iter()
        .filter_map(|d| cal_out.incident_k(Side::Plus, Mode::E, *d).ok())
        .collect();
    // Forward ray directions of outgoing waves on side − (toward −z).
    let rays_minus = directions(&mut rng, -1.0);
    let tts: Vec<f64> = k_air.iter().map(|k| k.x * k.x + k.y * k.y).collect();

    let mut group = c.benchmark_group("interface");
    group.throughput(Throughput::Elements(BATCH as u64));

    group.bench_function(
        BenchmarkId::new("fresnel coefficients", "air→glass"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for &tt in &tts {
                    let f = fresnel(1.0, 1.5168, black_box(tt));
                    acc += f.rs.re + f.tp_energy.re;
                }
                acc
            })
        },
    );
    group.bench_function(
        BenchmarkId::new("isotropic solve, closed form", "air→glass"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for k in &k_air {
                    acc += g
                        .solve(Side::Plus, Mode::P, black_box(*k))
                        .unwrap()
                        .energy_sum();
                }
                acc
            })
        },
    );
    group.bench_function(
        BenchmarkId::new("isotropic solve, 4x4 solver", "air→glass"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for k in &k_air {
                    acc += g
                        .solve_4x4(Side::Plus, Mode::P, black_box(*k))
                        .unwrap()
                        .energy_sum();
                }
                acc
            })
        },
    );
    group.bench_function(
        BenchmarkId::new("uniaxial forward solve", "air→calcite"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for k in &k_air {
                    acc += cal_in
                        .solve(Side::Plus, Mode::S, black_box(*k))
                        .unwrap()
                        .energy_sum();
                }
                acc
            })
        },
    );
    group.throughput(Throughput::Elements(k_cal.len() as u64));
    group.bench_function(
        BenchmarkId::new("uniaxial forward solve", "calcite→air, e"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for k in &k_cal {
                    acc += cal_out
                        .solve(Side::Plus, Mode::E, black_box(*k))
                        .unwrap()
                        .energy_sum();
                }
                acc
            })
        },
    );
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(
        BenchmarkId::new("biaxial forward solve", "air→topaz-like"),
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for k in &k_air {
                    acc += bx_in
                        .solve(Side::Plus, Mode::S, black_box(*k))
                        .unwrap()
                        .energy_sum();
                }
                acc
            })
        },
    );
    group.bench_function(BenchmarkId::new("backward query", "glass"), |b| {
        b.iter(|| {
            let mut acc = 0usize;
            for r in &rays_minus {
                acc += g
                    .feeders(Side::Minus, WaveKind::Isotropic, black_box(*r))
                    .unwrap()
                    .len();
            }
            acc
        })
    });
    group.bench_function(
        BenchmarkId::new("backward query", "calcite, e wave inside"),
        |b| {
            b.iter(|| {
                let mut acc = 0usize;
                for r in &rays_minus {
                    acc += cal_in
                        .feeders(Side::Minus, WaveKind::Extraordinary, black_box(*r))
                        .unwrap()
                        .len();
                }
                acc
            })
        },
    );
    group.bench_function(
        BenchmarkId::new("backward query", "calcite, air side"),
        |b| {
            b.iter(|| {
                let mut acc = 0usize;
                for r in &rays_minus {
                    acc += cal_out
                        .feeders(Side::Minus, WaveKind::Isotropic, black_box(*r))
                        .unwrap()
                        .len();
                }
                acc
            })
        },
    );
    for (name, iface, kind) in [
        ("biaxial, slow wave inside", &bx_in, WaveKind::Slow),
        ("biaxial, air side", &bx_out, WaveKind::Isotropic),
    ] {
        group.bench_function(BenchmarkId::new("backward query", name), |b| {
            b.iter(|| {
                let mut acc = 0usize;
                for r in &rays_minus {
                    acc += iface
                        .feeders(Side::Minus, kind, black_box(*r))
                        .unwrap()
                        .len();
                }
                acc
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
