//! Russian roulette (`roulette = X`, `Tracer::roulette`): the mean of many
//! rouletted estimates of one camera ray is the exact tree's value, in the
//! incoherent model on gems and in the physical model where paths
//! interfere (a thin film: its reflections add as amplitudes, so a pair of
//! rouletted paths must be weighted once per decision, not twice); it
//! traces fewer rays; and below the pruning bound it changes nothing.

use crate::support::render as common;
use spar::render::approx::{CoherenceModel, Strategy};
use spar::render::integrator::{Tracer, TreeSettings, WavelengthMedia};

/// The strategies' test gem (trichecker over a polarized checker light and
/// a grey background, exact to depth 12).
use crate::render_strategies::gem_scene as gem;

/// A free-standing film n = 2.4, 0.3 µm thick, seen in reflection of a
/// collimated polarized light at 30°: its reflections leave along one
/// direction and interfere (docs/physics.md §9).
fn film() -> (spar::scene::Scene, tempfile::TempDir) {
    let toml = r#"
[camera]
projection = "orthographic"
width = 4.0
eye = [4.999999999999999, 0.0, 8.660254037844387]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [8, 8]
[render]
units = "mm"
max_depth = 12
prune = 0.0
[media.film]
n = 2.4
[[object]]
mesh = "plate.obj"
medium = "film"
transform = { scale = [10.0, 10.0, 0.0003], translate = [0.0, 0.0, -0.00015] }
[[light]]
direction = [0.5, 0.0, -0.8660254037844386]
radiance = 1.0
angular_diameter = 0.5
polarization = { linear = [1.0, 0.3, 0.0] }
"#;
    let plate = common::box_obj([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]);
    common::scene(toml, &[("plate.obj", plate)])
}

/// Checks that roulette at `threshold` is unbiased for camera rays through
/// pixel positions `at` of `scene` in `model`, and returns the fraction of
/// the exact tree's rays it traced.
fn check_unbiased(
    scene: &spar::scene::Scene,
    model: CoherenceModel,
    threshold: f64,
    at: &[(f64, f64)],
    what: &str,
) -> f64 {
    let accel = spar::render::prepare::accel(scene, Default::default(), 1, None).unwrap();
    let settings = TreeSettings {
        max_depth: 12,
        prune: 0.0,
        convex_exit: true,
    };
    let strategy = |roulette| Strategy {
        coherence: model,
        roulette,
        ..Strategy::default()
    };
    let exact = Tracer::new(scene, accel.as_ref(), settings).with_strategy(strategy(0.0));
    let rouletted = Tracer::new(scene, accel.as_ref(), settings).with_strategy(strategy(threshold));
    let media = WavelengthMedia::new(scene, 550.0);
    let n = 20_000;
    let (mut exact_rays, mut rays) = (0, 0);
    for &(fx, fy) in at {
        let (eye, d) = scene.camera.ray(fx, fy);
        let (x, y) = scene.camera.stokes_frame(d);
        let (truth, _, e_stats) =
            common::sampled_mean(&exact, (eye, d, [x, y]), &media, 1, (11, 5));
        assert!(truth[0] > 0.0, "{what}: no light at {fx},{fy}");
        let (mean, se, stats) =
            common::sampled_mean(&rouletted, (eye, d, [x, y]), &media, n, (11, 5));
        assert!(
            stats.rouletted > 0,
            "{what}: roulette never ended a subtree"
        );
        exact_rays += e_stats.rays * n as u64;
        rays += stats.rays;
        for c in 0..4 {
            // 5 standard errors, plus rounding.
            let tol = 5.0 * se[c] + 1e-9 * truth[0];
            assert!(
                (mean[c] - truth[c]).abs() <= tol,
                "{what} at {fx},{fy} S{c}: mean {} ± {} vs exact {}",
                mean[c],
                se[c],
                truth[c]
            );
        }
    }
    rays as f64 / exact_rays as f64
}

#[test]
fn roulette_is_unbiased_on_gems_and_traces_fewer_rays() {
    for (medium, axis) in [("n-bk7", ""), ("calcite", "optic_axis = [0.3, 0.5, 0.8]")] {
        let (scene, _d) = gem(medium, axis);
        let at = [(4.0, 4.0), (3.2, 4.6), (5.1, 3.7)];
        for model in [CoherenceModel::Incoherent, CoherenceModel::Physical] {
            let share = check_unbiased(&scene, model, 0.05, &at, &format!("{medium} {model}"));
            assert!(
                share < 0.5,
                "{medium} {model}: roulette traced {share} of the exact tree's rays"
            );
        }
    }
}

#[test]
fn rouletted_paths_that_interfere_are_weighted_once_per_decision() {
    // The film's reflections reach the camera along one direction from
    // one light at infinity: they add as amplitudes, and the cross term of
    // two rouletted paths is unbiased only when a decision both paths
    // share is weighted once (coherent::roulette_pair).
    let (scene, _d) = film();
    let at = [(4.0, 4.0), (2.5, 5.5)];
    check_unbiased(&scene, CoherenceModel::Physical, 0.5, &at, "film");
}

#[test]
fn roulette_below_the_pruning_bound_changes_nothing() {
    // A subtree below the threshold of roulette is pruned before roulette
    // sees it: the image is the plain render's, bit for bit (in the
    // incoherent model; the physical one sums rouletted samples unclipped,
    // which can differ from the plain render's clipped sum in the last
    // bit).
    let (mut scene, _d) = gem("calcite", "optic_axis = [0.3, 0.5, 0.8]");
    scene.settings.prune = 1e-3;
    scene.settings.approx.strategy.coherence = CoherenceModel::Incoherent;
    let (plain, plain_stats) = common::render_at(&scene, &[550.0]);
    scene.settings.approx.strategy.roulette = 1e-3;
    let (rouletted, stats) = common::render_at(&scene, &[550.0]);
    assert_eq!(stats.rouletted, 0);
    assert_eq!(stats.rays, plain_stats.rays);
    for y in 0..plain.height {
        for x in 0..plain.width {
            assert_eq!(plain.stokes(x, y, 0), rouletted.stokes(x, y, 0));
        }
    }
}
