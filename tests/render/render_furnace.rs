//! White furnace: a lossless gem inside a uniform unpolarized background
//! must vanish, in intensity and in polarization, as the depth limit grows
//! (every path ends on the same background; Fresnel conserves energy and
//! unpolarized light summed over all paths stays unpolarized).
//!
//! The gem is the round brilliant seen from above. With enough depth every
//! gem vanishes (the Trichecker-12 in N-BK7 reaches 4e-12 at depth 80 with
//! no pruning), but how deep is "enough" depends on the cut and the view:
//! the Trichecker's girdle band traps rays by total internal reflection
//! around its polygon, and 6.6% of one pixel's light is still inside after
//! 40 interactions. The brilliant from above has no such loop within 40.

use crate::support::render as common;
use common::*;

/// Both ways paths may combine (docs/physics.md §9): every furnace holds
/// in each.
const MODELS: [&str; 2] = ["physical", "incoherent"];

fn furnace(medium: &str, axis: &str, depth: u32, prune: f64, res: u32, model: &str) -> String {
    format!(
        r#"
[camera]
eye = [0.0, -0.001, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 34.0
resolution = [{res}, {res}]
samples = 1
[render]
max_depth = {depth}
prune = {prune}
coherence = "{model}"
[[object]]
mesh = "builtin:brilliant"
medium = "{medium}"
transform = {{ scale = 0.0416667, translate = [0.0, 0.0, -1.0] }}
{axis}
[background]
radiance = 1.0
"#
    )
}

/// Worst |I/I_bg − 1| and worst P over the image, and the nodes traced.
fn worst(toml: &str) -> (f64, f64, u64) {
    let (di, dp, stats) = furnace_worst(toml);
    (di, dp, stats.nodes)
}

#[test]
fn glass_gem_vanishes_in_a_white_furnace() {
    for model in MODELS {
        let (di, dp, nodes) = worst(&furnace("n-bk7", "", 40, 0.0, 24, model));
        eprintln!(
            "glass, {model}, depth 40: worst |I − 1| = {di:.2e}, worst P = {dp:.2e}, {nodes} nodes"
        );
        assert!(di < 1e-3, "{model}: intensity off by {di}");
        assert!(dp < 1e-3, "{model}: P = {dp}");
    }
}

#[test]
fn calcite_gem_fades_into_a_white_furnace_as_depth_grows() {
    let axis = "optic_axis = [0.3, 0.5, 0.8]";
    for model in MODELS {
        let mut last = (f64::INFINITY, f64::INFINITY);
        for depth in [10, 20, 40] {
            let (di, dp, nodes) = worst(&furnace("calcite", axis, depth, 1e-6, 16, model));
            eprintln!(
                "calcite, {model}, depth {depth}: worst |I − 1| = {di:.2e}, worst P = {dp:.2e}, \
                 {nodes} nodes"
            );
            assert!(
                di < last.0 && dp <= last.1,
                "{model}: no improvement at depth {depth}: {di} {dp} after {last:?}"
            );
            last = (di, dp);
        }
        assert!(
            last.0 < 0.01 && last.1 < 0.01,
            "{model}, depth 40: {last:?}"
        );
    }
}

#[test]
fn a_thin_film_vanishes_in_a_white_furnace_with_its_reflections_coherent() {
    // A 500 nm film seen obliquely in a uniform background: in the
    // physical model the light reflected from one direction adds its
    // multiply reflected paths as amplitudes (R(λ) of the Airy formula),
    // the light transmitted from another direction likewise (T(λ)), and
    // R + T = 1 per polarization at every wavelength. Pruning at 1e-14
    // leaves out paths of amplitude below 1e-7, whose cross terms are
    // below 2e-7 of the background.
    let toml = r#"
[camera]
projection = "orthographic"
width = 4.0
eye = [5.0, 0.0, 8.660254037844386]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [8, 8]
[render]
units = "mm"
max_depth = 30
prune = 1e-14
[media.film]
n = 1.33
[[object]]
mesh = "box.obj"
medium = "film"
[background]
radiance = 1.0
"#;
    let (scene, _d) = common::scene(
        toml,
        &[("box.obj", box_obj([-5.0, -5.0, 0.0], [5.0, 5.0, 0.0005]))],
    );
    for lambda in [450.0, 520.0, 610.0] {
        let (film, stats) = render_at(&scene, &[lambda]);
        assert!(stats.coherent > 0, "the film's paths form coherent groups");
        let bg = spar::spectrum::cie::d65(lambda);
        for y in 0..film.height {
            for x in 0..film.width {
                let s = film.stokes(x, y, 0);
                let (p, _, _) = polarimetry(s);
                assert!(
                    (s[0] / bg - 1.0).abs() < 1e-6,
                    "{lambda} nm: I/I_bg = {}",
                    s[0] / bg
                );
                assert!(p < 1e-6, "{lambda} nm: P = {p}");
            }
        }
    }
}
