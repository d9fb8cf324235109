//! Absorption benchmark (issue 18): the same round brilliant rendered
//! colourless (corundum) and coloured (ruby: corundum's indices with its
//! o and e absorption), in colour (21 wavelengths, depth 30, pruning at
//! 1e-4), in a uniform white background. Absorbed light is pruned sooner,
//! so the ruby's trees are smaller: the table prints rays per pixel and
//! CPU seconds for each (the median of three renders).
//!
//!     cargo bench --bench absorption
//!     SPAR_BENCH_SIZE=128 SPAR_BENCH_SCALE=2 cargo bench --bench absorption
//!
//! `SPAR_BENCH_SCALE` multiplies the stone's size (6 mm across by
//! default) and the camera's distance: the same image of a larger, so
//! deeper-coloured, stone.

#[path = "support/mod.rs"]
mod support;

use spar::render::output::OutputMode;
use spar::render::{prepare, render};
use spar::scene::Scene;

fn scene(medium: &str, size: u32, scale: f64) -> Scene {
    let toml = format!(
        r#"
[camera]
eye = [0.0, {ey}, {ez}]
look_at = [0.0, 0.0, {lz}]
fov = 22.0
resolution = [{size}, {size}]
[render]
units = "mm"
[[object]]
mesh = "builtin:brilliant"
medium = "{medium}"
optic_axis = [0.3, 0.2, 0.93]
transform = {{ scale = {s}, translate = [0.0, 0.0, {lz}] }}
[background]
radiance = 1.0
"#,
        s = 0.12 * scale,
        ey = -12.0 * scale,
        ez = 16.0 * scale,
        lz = -0.5 * scale,
    );
    Scene::parse(&toml, "bench.toml", std::path::Path::new(".")).expect("the bench scene loads")
}

fn main() {
    let size: u32 = std::env::var("SPAR_BENCH_SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(128);
    let scale: f64 = std::env::var("SPAR_BENCH_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    println!(
        "| medium | size | stone (mm) | CPU s (median of 3) | rays | rays/pixel | nodes | pruned |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for medium in ["corundum", "ruby"] {
        let scene = scene(medium, size, scale);
        let accel = prepare::accel(
            &scene,
            spar::accel::AccelKind::default(),
            rayon::current_num_threads(),
            None,
        )
        .expect("the bench scene's intersector builds");
        let options = prepare::options(&scene, &[OutputMode::Color], 580.0, false);
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..3 {
            let t0 = support::cpu_seconds();
            let (_, stats) = render(&scene, accel.as_ref(), &options);
            times.push(support::cpu_seconds() - t0);
            last = Some(stats);
        }
        let stats = last.expect("three renders");
        let (lo, hi) = scene.objects[0].mesh.bounds();
        println!(
            "| {medium} | {size}² | {:.1} | {:.2} | {} | {:.1} | {} | {} |",
            (hi - lo).max_element(),
            support::median(times),
            stats.rays,
            stats.rays as f64 / (size as f64 * size as f64),
            stats.nodes,
            stats.pruned,
        );
    }
}
