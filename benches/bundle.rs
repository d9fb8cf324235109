//! What o/e bundles buy (render::bundle, docs/speed-vs-error.md): a round
//! brilliant (`spar cut round-brilliant`) over the checker light, full
//! spectrum (21 wavelengths, dispersion on), depth 30, pruning 1e-4, the
//! incoherent model, in N-BK7, quartz and calcite, each crystal with
//! bundles off and at several tolerances; interleaved, on all cores.
//! Prints median CPU seconds (user + system of the process: the steadier
//! measure on a shared machine), wall seconds, rays, the CPU ratio to
//! N-BK7, and each bundled image's error against the exact tree's render
//! of the same stone and seed (RMSE of S0 summed over the wavelengths and
//! of the polarized intensity √(S1²+S2²+S3²) at 580 nm, relative to the
//! mean S0 of the exact image).
//!
//!     cargo bench --bench bundle
//!     SPAR_BENCH_SIZE=256 SPAR_BENCH_REPEATS=3 cargo bench --bench bundle
//!
//! SPAR_BENCH_SIZE (default 128) is the image side; the target 2
//! is stated at 256.

use spar::accel::AccelKind;
use spar::render::film::Film;
use spar::render::integrator::Stats;
use spar::render::{prepare, render};
use spar::scene::Scene;
use std::path::Path;
use std::time::Instant;

mod support;
use support::{brilliant_scene, cpu_seconds, errors, median};

fn scene_text(medium: &str, size: u32, bundle: f64) -> String {
    let keys = format!("prune = 1e-4\ncoherence = \"incoherent\"\nbundle = {bundle}");
    brilliant_scene(medium, size, &keys)
}

fn main() {
    let size: u32 = std::env::var("SPAR_BENCH_SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(128);
    let repeats: usize = std::env::var("SPAR_BENCH_REPEATS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1);
    let rows: [(&str, f64); 9] = [
        ("n-bk7", 0.0),
        ("quartz", 0.0),
        ("quartz", 0.3),
        ("quartz", 1.0),
        ("quartz", 3.0),
        ("calcite", 0.0),
        ("calcite", 0.3),
        ("calcite", 1.0),
        ("calcite", 3.0),
    ];
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes: Vec<Scene> = rows
        .iter()
        .map(|(m, b)| {
            Scene::parse(&scene_text(m, size, *b), "bundle-bench.toml", base)
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
    let mut wall = vec![vec![]; rows.len()];
    let mut results: Vec<Option<(Film, Stats)>> = (0..rows.len()).map(|_| None).collect();
    for _ in 0..repeats {
        for (i, scene) in scenes.iter().enumerate() {
            let lambdas = scene.settings.wavelengths.lambdas().to_vec();
            let options = prepare::options_at(scene, lambdas);
            let (c0, t0) = (cpu_seconds(), Instant::now());
            let out = render(scene, accels[i].as_ref(), &options);
            wall[i].push(t0.elapsed().as_secs_f64());
            cpu[i].push(cpu_seconds() - c0);
            results[i] = Some(out);
        }
    }
    println!(
        "backend: {}, {} threads, {size}×{size}, 21 wavelengths, median of {repeats}",
        AccelKind::default(),
        rayon::current_num_threads()
    );
    println!(
        "| stone | bundle | CPU s | wall s | rays | bundled nodes | splits | CPU / N-BK7 | S0 RMSE | \
         polarized RMSE |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let glass = median(cpu[0].clone());
    let at = 10; // 580 nm of 21 over 380–780 nm
    for (i, (medium, bundle)) in rows.iter().enumerate() {
        let (film, stats) = results[i].as_ref().expect("rendered");
        let exact = rows
            .iter()
            .position(|(m, b)| m == medium && *b == 0.0)
            .expect("an exact row per stone");
        let (e0, ep) = if *bundle > 0.0 {
            let (ef, _) = results[exact].as_ref().expect("rendered");
            let [a, b] = errors(ef, film, at);
            (format!("{a:.4}"), format!("{b:.4}"))
        } else {
            (String::new(), String::new())
        };
        let c = median(cpu[i].clone());
        println!(
            "| {medium} | {bundle} | {c:.2} | {:.2} | {} | {} | {} | {:.2} | {e0} | {ep} |",
            median(wall[i].clone()),
            stats.rays,
            stats.bundled,
            stats.splits,
            c / glass
        );
    }
}
