//! Render benchmark: time and traced rays per second for each of the seed
//! paper's four scenes, in colour (21 wavelengths, the scenes' own depth
//! and pruning), at 256×256 and 512×512, on all cores. Prints a table.
//!
//!     cargo bench --bench render
//!     SPAR_BENCH_SIZES=256 SPAR_BENCH_ACCEL=embree cargo bench --bench render
//!
//! Each row is one render (these take seconds to minutes; the spread of
//! repeated runs on a quiet machine is a few percent, on a shared one much
//! more: rerun before quoting). `CPU (s)` is the process's user + system
//! time over the render: steadier than wall time where other work shares
//! the cores, and, beside the wall time, what the threads did in parallel
//! (wall × threads ÷ CPU is their busy share).

use spar::accel::AccelKind;
use spar::render::output::OutputMode;
use spar::render::{prepare, render};
use spar::scene::Scene;
use std::path::Path;
use std::time::Instant;

#[path = "support/mod.rs"]
#[allow(dead_code)]
mod support;

fn main() {
    let sizes: Vec<u32> = std::env::var("SPAR_BENCH_SIZES")
        .unwrap_or_else(|_| "256,512".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    // SPAR_BENCH_ACCEL: embree or rust (default: this build's default).
    let accel = std::env::var("SPAR_BENCH_ACCEL")
        .map(|s| AccelKind::parse(&s).expect("SPAR_BENCH_ACCEL"))
        .unwrap_or_default();
    println!("backend: {accel}");
    let scenes = [
        "glass-unpolarized",
        "glass-polarized",
        "calcite-unpolarized",
        "calcite-polarized",
    ];
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    println!(
        "| scene | size | spp | depth | prune | time (s) | CPU (s) | rays | M rays/s | nodes | nodes/camera ray |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for size in &sizes {
        for name in scenes {
            let mut scene =
                Scene::load(&dir.join(format!("{name}.toml"))).expect("seed scene loads");
            scene.camera = scene.camera.clone().with_resolution(*size, *size);
            let built = prepare::accel(&scene, accel, rayon::current_num_threads(), None)
                .expect("the seed scene's intersector builds");
            let options = prepare::options(&scene, &[OutputMode::Color], 580.0, false);
            let (t0, c0) = (Instant::now(), support::cpu_seconds());
            let (_, stats) = render(&scene, built.as_ref(), &options);
            let secs = t0.elapsed().as_secs_f64();
            let cpu = support::cpu_seconds() - c0;
            let camera_rays =
                (*size as u64).pow(2) * scene.samples as u64 * options.lambdas.len() as u64;
            println!(
                "| {name} | {size}² | {} | {} | {:e} | {secs:.2} | {cpu:.2} | {} | {:.2} | {} | {:.1} |",
                scene.samples,
                scene.settings.max_depth,
                scene.settings.prune,
                stats.rays,
                stats.rays as f64 / secs / 1e6,
                stats.nodes,
                stats.nodes as f64 / camera_rays as f64
            );
        }
    }
}
