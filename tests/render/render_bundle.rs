//! o and e bundles (`bundle = TOL`, render::bundle): where the two
//! eigenwaves share their rays the bundled image is the exact tree's;
//! where they part by more than the tolerance the bundle splits and the
//! image is again the exact tree's; with every mode-changing wave riding
//! on a member, energy is still conserved (a white furnace); and on a
//! weakly birefringent gem the bundled image stays close to the exact one
//! for a fraction of its rays. Russian roulette (`roulette = X`) thins a
//! bundled tree as it thins the exact one, and stays unbiased.

use crate::support::render as common;
use common::*;
use spar::render::approx::{CoherenceModel, Strategy};
use spar::render::film::Film;
use spar::render::integrator::{Stats, Tracer, TreeSettings, WavelengthMedia};

/// A `W`×`W`-pixel crystal slab `t` thick, oriented by `axis` (an
/// `optic_axis` vector, or a `crystal_axes` table for a biaxial medium), seen
/// by a camera `view` (TOML lines) above a checker-textured light, in the
/// incoherent model with `bundle` pixel footprints.
fn slab(medium: &str, axis: &str, view: &str, bundle: f64) -> String {
    let orientation = if axis.starts_with('{') {
        format!("crystal_axes = {axis}")
    } else {
        format!("optic_axis = {axis}")
    };
    format!(
        r#"
{view}
[render]
wavelengths = [550.0]
max_depth = 12
prune = 1e-6
coherence = "incoherent"
bundle = {bundle}
[[object]]
mesh = "slab.obj"
medium = "{medium}"
{orientation}
[[light]]
corners = [[-3.0, -3.0, -2.0], [3.0, -3.0, -2.0], [3.0, 3.0, -2.0], [-3.0, 3.0, -2.0]]
radiance = 1.0
texture = "builtin:checker"
"#
    )
}

const STRAIGHT_DOWN: &str = r#"
[camera]
projection = "orthographic"
width = 3.0
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [24, 24]
samples = 1
"#;

const OBLIQUE: &str = r#"
[camera]
eye = [0.0, -3.0, 4.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 30.0
resolution = [24, 24]
samples = 1
"#;

fn render_slab(toml: &str) -> (Film, Stats) {
    let slab = box_obj([-1.0, -1.0, -0.25], [1.0, 1.0, 0.25]);
    let (scene, _d) = common::scene(toml, &[("slab.obj", slab)]);
    render_at(&scene, &[550.0])
}

/// Largest difference of any Stokes component over the image, relative to
/// the brightest S0.
fn worst_difference(a: &Film, b: &Film) -> f64 {
    let mut peak = 0.0f64;
    let mut worst = 0.0f64;
    for y in 0..a.height {
        for x in 0..a.width {
            let (sa, sb) = (a.stokes(x, y, 0), b.stokes(x, y, 0));
            peak = peak.max(sa[0]);
            for i in 0..4 {
                worst = worst.max((sa[i] - sb[i]).abs());
            }
        }
    }
    worst / peak
}

/// Topaz-like principal indices (2V ≈ 57°), as `render_biaxial.rs` uses.
const TOPAZ_LIKE: &str = "biaxial:1.6093:1.6116:1.6194";

#[test]
fn where_o_and_e_share_their_rays_a_bundle_is_the_exact_tree() {
    // Straight down onto a slab whose optic axis lies in its faces: o and
    // e travel the same normal line, and no reflection changes a mode.
    // Likewise a biaxial slab whose crystal x is the slab's normal: its
    // fast and slow waves along a principal axis do not walk off.
    for (medium, axis) in [
        ("calcite", "[0.6, 0.8, 0.0]"),
        (TOPAZ_LIKE, "{ z = [0.6, 0.8, 0.0], x = [0.0, 0.0, 1.0] }"),
    ] {
        straight_down_bundle_is_exact(medium, axis);
    }
}

fn straight_down_bundle_is_exact(medium: &str, axis: &str) {
    let (exact, es) = render_slab(&slab(medium, axis, STRAIGHT_DOWN, 0.0));
    let (bundled, bs) = render_slab(&slab(medium, axis, STRAIGHT_DOWN, 1.0));
    let d = worst_difference(&exact, &bundled);
    eprintln!(
        "{medium}, straight down: worst difference {d:.2e}; rays exact {} bundled {}; {} \
         bundled nodes, {} splits",
        es.rays, bs.rays, bs.bundled, bs.splits
    );
    assert_eq!(es.bundled, 0, "tolerance 0 must not bundle");
    assert!(bs.bundled > 0, "nothing was bundled");
    assert_eq!(bs.splits, 0, "o and e on one line must not split");
    assert!(d < 1e-12, "bundled differs from the exact tree by {d}");
}

#[test]
fn a_bundle_whose_rays_part_splits_into_the_exact_tree() {
    // Calcite seen obliquely with a tilted axis: the o and e rays leave
    // the slab a tenth of its thickness apart, tens of pixel footprints at
    // 24×24. With a hundredth of a footprint every bundle whose members
    // part splits, and every mode-changing wave that would drift from its
    // member is traced on its own: the image converges to the exact tree's
    // (a tolerance of 1 footprint moves the double image's light by up to
    // a pixel).
    // A topaz-like biaxial slab with tilted crystal axes parts its fast and
    // slow rays too (walk-offs of a few tenths of a degree: a fraction of
    // a pixel here, so a footprint need not move light; it must still
    // split and converge).
    for (medium, axis) in [
        ("calcite", "[0.3, 0.5, 0.8]"),
        (TOPAZ_LIKE, "{ z = [0.3, 0.5, 0.8], x = [1.0, 0.0, 0.2] }"),
    ] {
        oblique_bundle_splits_into_the_exact_tree(medium, axis);
    }
}

fn oblique_bundle_splits_into_the_exact_tree(medium: &str, axis: &str) {
    let (exact, _) = render_slab(&slab(medium, axis, OBLIQUE, 0.0));
    let mut last = f64::INFINITY;
    for tol in [1.0, 0.1, 0.01] {
        let (bundled, bs) = render_slab(&slab(medium, axis, OBLIQUE, tol));
        let d = worst_difference(&exact, &bundled);
        eprintln!(
            "oblique {medium}, tolerance {tol}: worst difference {d:.2e} of the peak; {} \
             bundled nodes, {} splits, {} rays",
            bs.bundled, bs.splits, bs.rays
        );
        assert!(bs.splits > 0, "{medium}: no bundle split at {tol}");
        assert!(
            d <= last,
            "{medium}: farther from the exact tree at {tol}: {d} after {last}"
        );
        if tol == 1.0 && medium == "calcite" {
            assert!(d > 1e-3, "a footprint moved no light: {d}");
        }
        last = d;
    }
    assert!(
        last < 1e-6,
        "{medium}: at 0.01 footprints still {last} from the exact tree"
    );
}

#[test]
fn bundles_conserve_energy_in_a_white_furnace() {
    // The brilliant in a uniform background (render_furnace.rs), every
    // eigenwave pair bundled however far its rays part on a shared facet:
    // the mode-changing waves ride on the wrong ray, but every Jones block
    // is applied, so the gem must still vanish.
    for (medium, depth) in [("quartz", 40), ("calcite", 40), (TOPAZ_LIKE, 40)] {
        let orientation = if medium.starts_with("biaxial") {
            "crystal_axes = { z = [0.3, 0.5, 0.8], x = [1.0, 0.0, 0.2] }"
        } else {
            "optic_axis = [0.3, 0.5, 0.8]"
        };
        let toml = format!(
            r#"
[camera]
eye = [0.0, -0.001, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 34.0
resolution = [16, 16]
samples = 1
[render]
max_depth = {depth}
prune = 1e-7
coherence = "incoherent"
bundle = 1e9
[[object]]
mesh = "builtin:brilliant"
medium = "{medium}"
{orientation}
transform = {{ scale = 0.0416667, translate = [0.0, 0.0, -1.0] }}
[background]
radiance = 1.0
"#
        );
        let (di, dp, stats) = furnace_worst(&toml);
        eprintln!(
            "{medium} furnace, bundled, depth {depth}: worst |I − 1| = {di:.2e}, worst P = \
             {dp:.2e}, {} bundled nodes, {} splits, {} rays",
            stats.bundled, stats.splits, stats.rays
        );
        assert!(stats.bundled > 0);
        assert!(di < 0.01, "{medium}: intensity off by {di}");
        assert!(dp < 0.01, "{medium}: P = {dp}");
    }
}

#[test]
fn a_bundled_quartz_gem_trades_rays_for_a_bounded_error() {
    // The Trichecker in quartz (Δn = 0.009) over the checker light, seen
    // obliquely. The error of a bundle is light moved by up to its
    // tolerance per segment: it must shrink with the tolerance (to the
    // exact tree's image), and the rays must fall as the tolerance grows.
    let toml = |bundle: f64| {
        format!(
            r#"
[camera]
eye = [0.0, -3.2, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 28.0
resolution = [32, 32]
samples = 1
[render]
max_depth = 20
prune = 1e-4
coherence = "incoherent"
bundle = {bundle}
[[object]]
mesh = "builtin:trichecker12"
medium = "quartz"
optic_axis = [0.0, 0.6, 0.8]
[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
radiance = 1.0
texture = "builtin:checker"
"#
        )
    };
    let (s0, _d0) = common::scene(&toml(0.0), &[]);
    let (exact, es) = render_at(&s0, &[550.0]);
    // RMSE of S0 over the image, relative to the mean S0.
    let rmse = |film: &Film| {
        let (mut mean, mut e, mut n) = (0.0, 0.0, 0.0);
        for y in 0..exact.height {
            for x in 0..exact.width {
                let (a, b) = (exact.stokes(x, y, 0), film.stokes(x, y, 0));
                mean += a[0];
                e += (a[0] - b[0]).powi(2);
                n += 1.0;
            }
        }
        (e / n).sqrt() / (mean / n)
    };
    let mut last: Option<(f64, u64)> = None;
    for tol in [0.001, 0.3, 3.0] {
        let (s, _d) = common::scene(&toml(tol), &[]);
        let (bundled, bs) = render_at(&s, &[550.0]);
        let r = rmse(&bundled);
        eprintln!(
            "quartz 32×32, tolerance {tol}: S0 RMSE {r:.2e} of the mean; rays {} of the exact \
             tree's {} ({:.2}×)",
            bs.rays,
            es.rays,
            es.rays as f64 / bs.rays as f64
        );
        match last {
            None => assert!(r < 1e-6, "at 0.001 footprints S0 is {r} off"),
            Some((lr, lrays)) => {
                assert!(r > lr, "a wider tolerance, no more error: {r} after {lr}");
                assert!(bs.rays < lrays, "a wider tolerance, no fewer rays");
            }
        }
        last = Some((r, bs.rays));
    }
    let (_, rays) = last.expect("three tolerances");
    assert!(
        rays * 3 < es.rays,
        "3 footprints saved too little: {rays} vs {}",
        es.rays
    );
}

/// The quartz brilliant of `scenes/quartz-brilliant.toml` (Δn = 0.009,
/// depth 30, pruning 1e-4) over the checker light at 32×32, with `bundle`
/// pixel footprints and roulette threshold `roulette`.
fn quartz_brilliant(bundle: f64, roulette: f64) -> String {
    format!(
        r#"
[camera]
eye = [0.0, -3.2, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 28.0
resolution = [32, 32]
samples = 1
[render]
max_depth = 30
prune = 1e-4
coherence = "incoherent"
bundle = {bundle}
roulette = {roulette}
[[object]]
cut = {{ name = "round-brilliant" }}
medium = "quartz"
optic_axis = [0.0, 0.6, 0.8]
transform = {{ scale = 2.4, rotate = [0.0, 0.0, 15.0] }}
[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
radiance = 1.0
texture = "builtin:checker"
"#
    )
}

#[test]
fn roulette_thins_a_bundled_tree() {
    // Before roulette applied inside bundles, every subtree a bundle
    // entered was traced whatever its throughput: on this brilliant
    // (64×64, 21 wavelengths) roulette 0.01 with 1 footprint traced 3.6×
    // the rays of roulette alone. Now a bundled render with roulette must
    // trace under half the rays of the same bundled render without it
    // (measured at 550 nm: 77 750 → 20 419 rays at 1 footprint, 34 125 →
    // 12 431 at 3), and no more than roulette without bundles (27 371).
    let rays = |bundle: f64, roulette: f64| {
        let (scene, _d) = common::scene(&quartz_brilliant(bundle, roulette), &[]);
        let (_, stats) = render_at(&scene, &[550.0]);
        stats
    };
    let rouletted_only = rays(0.0, 0.01);
    for tol in [1.0, 3.0] {
        let bundled = rays(tol, 0.0);
        let both = rays(tol, 0.01);
        eprintln!(
            "quartz brilliant 32×32, {tol} footprints: rays {} bundled, {} bundled with \
             roulette 0.01 ({} ended by roulette, {} splits), {} with roulette alone",
            bundled.rays, both.rays, both.rouletted, both.splits, rouletted_only.rays
        );
        assert!(both.bundled > 0 && both.rouletted > 0);
        assert!(
            both.rays * 2 < bundled.rays,
            "{tol}: roulette saved too little in a bundled tree: {} vs {}",
            both.rays,
            bundled.rays
        );
        assert!(
            both.rays <= rouletted_only.rays,
            "{tol}: bundles with roulette traced more than roulette alone: {} vs {}",
            both.rays,
            rouletted_only.rays
        );
    }
}

#[test]
fn roulette_in_bundles_is_unbiased() {
    // Roulette keeps a subtree with probability p and weights it by 1/p:
    // the mean of many rouletted estimates of one camera ray must be the
    // same bundled tree's value without roulette (which is deterministic:
    // one evaluation is the truth). Each estimate is independent (another
    // sample index, so other random numbers), so their mean is normal to
    // within a standard error `se` estimated from their spread; 5 `se`
    // (a two-sided chance of 6e-7 per check, some 50 checks) plus 1e-9 of
    // the value for rounding. A bias as small as 5 `se` of 20 000
    // estimates (a few 1e-3 of S0 here) would show.
    //
    // Scenes: a calcite Trichecker under a polarized checker light (large
    // birefringence: bundles split often, so the member decisions after a
    // split count), and the quartz brilliant in a white furnace with
    // every eigenwave pair bundled (the exact answer is known: the
    // background, to within the depth and pruning cuts, checked too); and
    // a ruby Trichecker, whose absorption lowers a bundle's throughput
    // along each member's segment before roulette looks at it.
    let furnace = r#"
[camera]
eye = [0.0, -0.001, 4.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 34.0
resolution = [16, 16]
samples = 1
[render]
max_depth = 40
prune = 1e-7
coherence = "incoherent"
[[object]]
mesh = "builtin:brilliant"
medium = "quartz"
optic_axis = [0.3, 0.5, 0.8]
transform = { scale = 0.0416667, translate = [0.0, 0.0, -1.0] }
[background]
radiance = 1.0
"#;
    let (furnace, _fd) = common::scene(furnace, &[]);
    let (calcite, _cd) =
        crate::render_strategies::gem_scene("calcite", "optic_axis = [0.3, 0.5, 0.8]");
    let (ruby, _rd) = crate::render_strategies::gem_scene("ruby", "optic_axis = [0.3, 0.5, 0.8]");
    let cases = [
        (
            &ruby,
            1e9,
            0.05,
            [(4.0, 4.0), (3.2, 4.6), (5.1, 3.7)],
            12,
            "ruby",
        ),
        (
            &calcite,
            1.0,
            0.05,
            [(4.0, 4.0), (3.2, 4.6), (5.1, 3.7)],
            12,
            "calcite",
        ),
        (
            &furnace,
            1e9,
            0.05,
            [(8.0, 8.0), (6.5, 9.2), (9.7, 7.1)],
            40,
            "quartz furnace",
        ),
    ];
    for (scene, bundle, threshold, at, max_depth, what) in cases {
        let accel = spar::render::prepare::accel(scene, Default::default(), 1, None).unwrap();
        let settings = TreeSettings {
            max_depth,
            prune: scene.settings.prune,
            convex_exit: true,
        };
        let strategy = |roulette| Strategy {
            coherence: CoherenceModel::Incoherent,
            bundle,
            roulette,
            ..Strategy::default()
        };
        let plain = Tracer::new(scene, accel.as_ref(), settings).with_strategy(strategy(0.0));
        let rouletted =
            Tracer::new(scene, accel.as_ref(), settings).with_strategy(strategy(threshold));
        let media = WavelengthMedia::new(scene, 550.0);
        let n = 20_000;
        let (mut plain_rays, mut rays) = (0, 0);
        for (fx, fy) in at {
            let (eye, d) = scene.camera.ray(fx, fy);
            let (x, y) = scene.camera.stokes_frame(d);
            let (truth, _, p_stats) =
                common::sampled_mean(&plain, (eye, d, [x, y]), &media, 1, (11, 5));
            assert!(truth[0] > 0.0, "{what}: no light at {fx},{fy}");
            assert!(p_stats.bundled > 0, "{what}: nothing bundled at {fx},{fy}");
            let (mean, se, stats) =
                common::sampled_mean(&rouletted, (eye, d, [x, y]), &media, n, (11, 5));
            assert!(
                stats.rouletted > 0,
                "{what}: roulette never ended a subtree"
            );
            plain_rays += p_stats.rays * n as u64;
            rays += stats.rays;
            eprintln!(
                "{what} at {fx},{fy}: S0 {:.6} ± {:.1e} rouletted vs {:.6} bundled; {} splits \
                 in {n} samples",
                mean[0], se[0], truth[0], stats.splits
            );
            for c in 0..4 {
                let tol = 5.0 * se[c] + 1e-9 * truth[0];
                assert!(
                    (mean[c] - truth[c]).abs() <= tol,
                    "{what} at {fx},{fy} S{c}: mean {} ± {} vs bundled {}",
                    mean[c],
                    se[c],
                    truth[c]
                );
            }
            if what == "quartz furnace" {
                // The gem vanishes: S0 is the background's (the unrouletted
                // furnace is within 0.01 of it, bundles_conserve_energy_…).
                let bg = spar::spectrum::cie::d65(550.0);
                assert!(
                    (mean[0] / bg - 1.0).abs() <= 0.01 + 5.0 * se[0] / bg,
                    "{what} at {fx},{fy}: S0 {} vs the background {bg}",
                    mean[0]
                );
            }
        }
        let share = rays as f64 / plain_rays as f64;
        eprintln!("{what}: roulette {threshold} traced {share:.3} of the bundled tree's rays");
        assert!(
            share < 0.5,
            "{what}: roulette traced {share} of the bundled rays"
        );
    }
}
