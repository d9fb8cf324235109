//! What a crystal costs against glass at equal error (issue 13's target
//! 2): the round brilliant of benches/bundle.rs (`spar cut
//! round-brilliant` over the checker light, 21 wavelengths with
//! dispersion, depth 30, pruning 1e-4) in N-BK7, quartz and calcite (or
//! the media SPAR_BENCH_MEDIA names), each
//! rendered with the exact tree at two seeds and with Russian roulette at
//! several thresholds; on all cores. Prints, per row, median CPU seconds
//! (user + system of the process), rays, the row's own error and its cost
//! at equal error.
//!
//! Equal error: one sample per pixel of the exact tree has an error
//! against the converged image (antialiasing: the pixel position) of σ,
//! measured as RMSE(seed 0, seed 1)/√2. A roulette render of the same
//! seed differs from the exact one by its own noise e (paired: the same
//! pixel positions), so one of its samples has error √(σ² + e²), and it
//! needs 1 + e²/σ² samples to reach an exact sample's error. Its cost at
//! equal error is its CPU time times that factor, taken for the worse of
//! two measures: S0 summed over the wavelengths, and the polarized
//! intensity √(S1²+S2²+S3²) at 580 nm (both RMSE relative to the mean S0
//! of the exact image). The last column divides by the cheapest N-BK7
//! row's cost at equal error.
//!
//!     cargo bench --bench crystal_cost
//!     SPAR_BENCH_SIZE=256 SPAR_BENCH_COHERENCE=physical cargo bench --bench crystal_cost
//!
//! SPAR_BENCH_MEDIA (comma-separated catalogue media rendered beside
//! N-BK7, default quartz,calcite; e.g. topaz for a biaxial stone, its
//! crystal z where the others have their optic axis),
//! SPAR_BENCH_SIZE (default 128), SPAR_BENCH_REPEATS (default 1; the
//! seed-1 rows are rendered once, for σ), SPAR_BENCH_COHERENCE
//! (incoherent, as benches/bundle.rs and scenes/quartz-brilliant.toml; or
//! physical), SPAR_BENCH_DISPERSION (true, or false as `--quality draft`
//! has it), SPAR_BENCH_PRUNE (default 1e-4; `--quality draft` has
//! 1e-3), SPAR_BENCH_ROULETTE (comma-separated thresholds, default
//! 0.01,0.03,0.1), SPAR_BENCH_BUNDLE (o/e bundle tolerances in pixels
//! for the crystals, each with every roulette threshold; incoherent model
//! only; default 3, 0 for none).

use spar::accel::AccelKind;
use spar::render::film::Film;
use spar::render::integrator::Stats;
use spar::render::{prepare, render};
use spar::scene::Scene;
use std::path::Path;
use std::time::Instant;

mod support;
use support::{brilliant_scene, cpu_seconds, errors, median};

#[derive(Clone, Copy)]
struct Row {
    medium: &'static str,
    roulette: f64,
    bundle: f64,
    seed: u64,
}

fn scene_text(row: Row, size: u32, coherence: &str, dispersion: &str, prune: f64) -> String {
    let keys = format!(
        "prune = {prune}\ncoherence = \"{coherence}\"\ndispersion = {dispersion}\n\
         roulette = {}\nbundle = {}\nseed = {}",
        row.roulette, row.bundle, row.seed
    );
    brilliant_scene(row.medium, size, &keys)
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let size: u32 = env_or("SPAR_BENCH_SIZE", 128);
    let repeats: usize = env_or("SPAR_BENCH_REPEATS", 1usize).max(1);
    let coherence: String = env_or("SPAR_BENCH_COHERENCE", "incoherent".to_string());
    let dispersion: String = env_or("SPAR_BENCH_DISPERSION", "true".to_string());
    let prune: f64 = env_or("SPAR_BENCH_PRUNE", 1e-4);
    let thresholds: Vec<f64> = std::env::var("SPAR_BENCH_ROULETTE")
        .unwrap_or_else(|_| "0.01,0.03,0.1".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let bundles: Vec<f64> = std::env::var("SPAR_BENCH_BUNDLE")
        .unwrap_or_else(|_| "3".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .filter(|b: &f64| *b > 0.0)
        .collect();
    // N-BK7 first: the last column divides by its cheapest row.
    let mut media: Vec<&'static str> = vec!["n-bk7"];
    let list = std::env::var("SPAR_BENCH_MEDIA").unwrap_or_else(|_| "quartz,calcite".into());
    for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        if spar::material::Material::parse(name).is_err() {
            eprintln!("crystal_cost: SPAR_BENCH_MEDIA: `{name}` is not a catalogue medium");
            std::process::exit(2);
        }
        if !media.contains(&name) {
            media.push(Box::leak(name.to_string().into_boxed_str()));
        }
    }
    let mut rows = Vec::new();
    for medium in media {
        let uniaxial = spar::material::Material::parse(medium).is_ok_and(|m| m.is_uniaxial());
        for seed in [0, 1] {
            rows.push(Row {
                medium,
                roulette: 0.0,
                bundle: 0.0,
                seed,
            });
        }
        for &roulette in &thresholds {
            rows.push(Row {
                medium,
                roulette,
                bundle: 0.0,
                seed: 0,
            });
        }
        // o/e bundles are for uniaxial crystals.
        if uniaxial && coherence == "incoherent" {
            for &bundle in &bundles {
                for &roulette in &thresholds {
                    rows.push(Row {
                        medium,
                        roulette,
                        bundle,
                        seed: 0,
                    });
                }
            }
        }
    }
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes: Vec<Scene> = rows
        .iter()
        .map(|&row| {
            Scene::parse(
                &scene_text(row, size, &coherence, &dispersion, prune),
                "crystal-cost-bench.toml",
                base,
            )
            .expect("the bench scene parses")
        })
        .collect();
    let accels: Vec<_> = scenes
        .iter()
        .map(|s| {
            prepare::accel(s, AccelKind::default(), rayon::current_num_threads(), None)
                .expect("the intersector builds")
        })
        .collect();
    let mut cpu = vec![vec![]; rows.len()];
    let mut results: Vec<Option<(Film, Stats)>> = (0..rows.len()).map(|_| None).collect();
    for repeat in 0..repeats {
        for (i, scene) in scenes.iter().enumerate() {
            if repeat > 0 && rows[i].seed != 0 {
                continue;
            }
            let lambdas = scene.settings.wavelengths.lambdas().to_vec();
            let options = prepare::options_at(scene, lambdas);
            let (c0, _t0) = (cpu_seconds(), Instant::now());
            let out = render(scene, accels[i].as_ref(), &options);
            cpu[i].push(cpu_seconds() - c0);
            results[i] = Some(out);
        }
    }
    let film = |i: usize| &results[i].as_ref().expect("rendered").0;
    let at = 10; // 580 nm of 21 over 380–780 nm
    let exact_of = |medium: &str, seed: u64| {
        rows.iter()
            .position(|r| {
                r.medium == medium && r.roulette == 0.0 && r.bundle == 0.0 && r.seed == seed
            })
            .expect("exact rows for each stone")
    };
    // Cost at equal error and the row's own error, per row.
    let mut equal_cost = vec![f64::NAN; rows.len()];
    let mut own = vec![[f64::NAN; 2]; rows.len()];
    let mut sigma = vec![[f64::NAN; 2]; rows.len()];
    for (i, row) in rows.iter().enumerate() {
        if row.seed != 0 {
            continue;
        }
        let e0 = exact_of(row.medium, 0);
        let e1 = exact_of(row.medium, 1);
        let s = errors(film(e0), film(e1), at).map(|x| x / 2f64.sqrt());
        let e = if i != e0 {
            errors(film(e0), film(i), at)
        } else {
            [0.0, 0.0]
        };
        // Roulette's error is noise, which samples average away: 1 + e²/σ²
        // samples. A bundle's is mostly bias, which they do not: counted
        // as all bias (the larger count), σ²/(σ² − e²), none if e ≥ σ.
        let factor = (0..2)
            .map(|m| {
                let r = (e[m] / s[m]).powi(2);
                if row.bundle > 0.0 {
                    if r < 1.0 {
                        1.0 / (1.0 - r)
                    } else {
                        f64::INFINITY
                    }
                } else {
                    1.0 + r
                }
            })
            .fold(1.0, f64::max);
        equal_cost[i] = median(cpu[i].clone()) * factor;
        own[i] = e;
        sigma[i] = s;
    }
    let glass = rows
        .iter()
        .enumerate()
        .filter(|(i, r)| r.medium == "n-bk7" && r.seed == 0 && equal_cost[*i].is_finite())
        .map(|(i, _)| equal_cost[i])
        .fold(f64::INFINITY, f64::min);
    println!(
        "backend: {}, {} threads, {size}×{size}, 21 wavelengths, dispersion {dispersion}, \
         pruning {prune:e}, {coherence} model, median of {repeats}",
        AccelKind::default(),
        rayon::current_num_threads()
    );
    println!(
        "| stone | roulette | bundle | CPU s | rays | σ S0 | σ pol | own S0 | own pol | samples for equal error | \
         CPU s at equal error | ÷ N-BK7 |"
    );
    println!("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (i, row) in rows.iter().enumerate() {
        if row.seed != 0 {
            continue;
        }
        let stats = &results[i].as_ref().expect("rendered").1;
        let c = median(cpu[i].clone());
        // The factor from the errors alone (CPU time may round to 0 on a
        // tiny image).
        let factor = equal_cost[i] / c;
        let factor = if factor.is_finite() {
            format!("{factor:.2}")
        } else {
            "n/a".into()
        };
        println!(
            "| {} | {} | {} | {c:.2} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {factor} | {:.2} | {:.2} |",
            row.medium,
            row.roulette,
            row.bundle,
            stats.rays,
            sigma[i][0],
            sigma[i][1],
            own[i][0],
            own[i][1],
            equal_cost[i],
            equal_cost[i] / glass
        );
    }
}
