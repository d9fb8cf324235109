//! The cost of coherent sums (docs/physics.md §9): each seed scene and each
//! polariscope scene rendered in the physical and the incoherent model,
//! interleaved, at the scene's own wavelengths, on all cores. Prints a
//! table of median CPU seconds (user + system of the process, the steadier
//! measure on a shared machine), median wall seconds, rays, coherent paths
//! and the physical/incoherent CPU ratio.
//!
//!     cargo bench --bench coherence
//!     SPAR_BENCH_SIZE=256 SPAR_BENCH_REPEATS=5 cargo bench --bench coherence
//!
//! SPAR_BENCH_SIZE (default 128) is the side of the seed scenes' images;
//! the polariscope scenes keep their own resolution.

use spar::accel::AccelKind;
use spar::render::approx::CoherenceModel;
use spar::render::integrator::Stats;
use spar::render::{prepare, render};
use spar::scene::Scene;
use std::path::Path;
use std::time::Instant;

mod support;
use support::{cpu_seconds, median};

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
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let scenes = [
        ("glass-unpolarized.toml", true),
        ("glass-polarized.toml", true),
        ("calcite-unpolarized.toml", true),
        ("calcite-polarized.toml", true),
        ("polariscope/quarter-wave.toml", false),
        ("polariscope/half-wave.toml", false),
        ("polariscope/michel-levy.toml", false),
        ("polariscope/conoscope-calcite.toml", false),
        ("polariscope/thin-film.toml", false),
        ("polariscope/optic-axis.toml", false),
    ];
    println!(
        "backend: {}, {} threads, median of {repeats}",
        AccelKind::default(),
        rayon::current_num_threads()
    );
    println!("| scene | size | λ | model | CPU s | wall s | rays | coherent paths | CPU ratio |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, resize) in scenes {
        let mut scene = Scene::load(&root.join(name)).expect("the scene loads");
        if resize {
            scene.camera = scene.camera.clone().with_resolution(size, size);
        }
        let accel = prepare::accel(
            &scene,
            AccelKind::default(),
            rayon::current_num_threads(),
            None,
        )
        .expect("the intersector builds");
        let lambdas = scene.settings.wavelengths.lambdas().to_vec();
        let models = [CoherenceModel::Incoherent, CoherenceModel::Physical];
        let mut cpu = [vec![], vec![]];
        let mut wall = [vec![], vec![]];
        let mut stats = [Stats::default(); 2];
        for _ in 0..repeats {
            for (m, model) in models.iter().enumerate() {
                scene.settings.approx.strategy.coherence = *model;
                let options = prepare::options_at(&scene, lambdas.clone());
                let (c0, t0) = (cpu_seconds(), Instant::now());
                let (_, s) = render(&scene, accel.as_ref(), &options);
                wall[m].push(t0.elapsed().as_secs_f64());
                cpu[m].push(cpu_seconds() - c0);
                stats[m] = s;
            }
        }
        let medians = [median(cpu[0].clone()), median(cpu[1].clone())];
        for (m, model) in models.iter().enumerate() {
            println!(
                "| {name} | {}×{} | {} | {model} | {:.2} | {:.2} | {} | {} | {} |",
                scene.camera.width,
                scene.camera.height,
                lambdas.len(),
                medians[m],
                median(wall[m].clone()),
                stats[m].rays,
                stats[m].coherent,
                if m == 1 && medians[0] > 0.0 {
                    format!("{:.3}", medians[1] / medians[0])
                } else {
                    String::new()
                }
            );
        }
    }
}
