//! Rays inside a convex stone leave it by its facet planes
//! (`accel::convex`, `TreeSettings::convex_exit`) instead of the backend's
//! triangles: the light every camera ray gathers is the backend's to f64
//! rounding, in both coherence models, on glass and calcite and on both
//! backends. Rays that leave a convex stone into air cannot meet it again:
//! with no other object ahead they skip the backend too, which then sees
//! only the camera's rays; a neighbour ahead still gets traced.

use crate::render_strategies::{gem_scene as gem, gems_scene};
use crate::support::render as common;
use spar::accel::{AccelKind, Hit, Intersector, Ray};
use spar::render::approx::{CoherenceModel, Strategy};
use spar::render::integrator::WavelengthMedia;
use spar::render::integrator::{Tracer, TreeSettings};
use std::sync::atomic::{AtomicU64, Ordering};

/// A backend that counts the rays it is asked to trace.
struct Counting<'a> {
    inner: &'a dyn Intersector,
    calls: AtomicU64,
}

impl Intersector for Counting<'_> {
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.intersect(ray)
    }
    fn name(&self) -> &'static str {
        "counting"
    }
}

/// The Stokes vector each of the 8×8 pixel centres (offset) of `scene`
/// gathers at 550 nm, the rays traced and the backend's calls, with the
/// facet planes (`convex_exit`) or with the backend alone.
fn gathered(
    scene: &spar::scene::Scene,
    backend: &dyn Intersector,
    model: CoherenceModel,
    convex_exit: bool,
) -> (Vec<[f64; 4]>, u64, u64) {
    let media = WavelengthMedia::new(scene, 550.0);
    let counting = Counting {
        inner: backend,
        calls: AtomicU64::new(0),
    };
    let settings = TreeSettings {
        max_depth: 12,
        prune: 0.0,
        convex_exit,
    };
    let tracer = Tracer::new(scene, &counting, settings).with_strategy(Strategy {
        coherence: model,
        ..Strategy::default()
    });
    let mut pixels = Vec::new();
    let mut rays = 0;
    for y in 0..8 {
        for x in 0..8 {
            let (fx, fy) = (x as f64 + 0.37, y as f64 + 0.61);
            let (eye, d) = scene.camera.ray(fx, fy);
            let (bx, by) = scene.camera.stokes_frame(d);
            let (s, _, stats) =
                common::sampled_mean(&tracer, (eye, d, [bx, by]), &media, 1, (1, 0));
            assert_eq!(stats.lost, 0, "lost rays");
            rays += stats.rays;
            pixels.push(s);
        }
    }
    (pixels, rays, counting.calls.into_inner())
}

/// Fails unless every Stokes component of every pixel agrees to 1e-9 of
/// the brightest pixel.
fn assert_same_light(what: &str, backend: &[[f64; 4]], planes: &[[f64; 4]]) {
    let brightest = backend.iter().map(|s| s[0]).fold(0.0, f64::max);
    assert!(brightest > 0.0);
    for (i, (a, b)) in backend.iter().zip(planes).enumerate() {
        for c in 0..4 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-9 * brightest,
                "{what}: pixel {i} S{c} {} with the planes, {} with the backend",
                b[c],
                a[c]
            );
        }
    }
}

#[test]
fn convex_exits_gather_the_backends_light() {
    let kinds: Vec<AccelKind> = AccelKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .collect();
    for (medium, axis) in [("n-bk7", ""), ("calcite", "optic_axis = [0.3, 0.5, 0.8]")] {
        let (scene, _d) = gem(medium, axis);
        for &kind in &kinds {
            let backend = spar::render::prepare::accel(&scene, kind, 1, None).unwrap();
            for model in [CoherenceModel::Incoherent, CoherenceModel::Physical] {
                let what = format!("{medium} {kind} {model}");
                let (backend_light, backend_rays, backend_calls) =
                    gathered(&scene, backend.as_ref(), model, false);
                let (convex_light, convex_rays, convex_calls) =
                    gathered(&scene, backend.as_ref(), model, true);
                assert_eq!(
                    backend_rays, backend_calls,
                    "{what}: every ray to the backend"
                );
                assert_eq!(convex_rays, backend_rays, "{what}: the same tree");
                // Every other ray travels inside the stone or leaves it
                // (the only object): the backend sees at most the 64
                // camera rays.
                assert!(
                    convex_calls <= 64 && backend_calls > 10 * 64,
                    "{what}: the backend still traced {convex_calls} of {backend_calls} rays"
                );
                assert_same_light(&what, &backend_light, &convex_light);
            }
        }
    }
}

/// Two stones side by side, the calcite one lit through the glass one:
/// rays leaving one stone towards the other still reach the backend, and
/// the image is the backend's.
#[test]
fn rays_leaving_a_stone_still_meet_its_neighbour() {
    let stone = |x: f64, medium: &str, axis: &str| {
        format!(
            "[[object]]\nmesh = \"builtin:trichecker12\"\nmedium = \"{medium}\"\n{axis}\n\
             transform = {{ scale = 0.4, rotate = [0.0, 20.0, 0.0], translate = [{x}, 0.0, 0.0] }}\n"
        )
    };
    let (scene, _d) = gems_scene(&format!(
        "{}{}",
        stone(-0.5, "n-bk7", ""),
        stone(0.5, "calcite", "optic_axis = [0.3, 0.5, 0.8]"),
    ));
    for kind in common::backends() {
        let backend = spar::render::prepare::accel(&scene, kind, 1, None).unwrap();
        let what = format!("{kind}");
        let model = CoherenceModel::Physical;
        let (backend_light, backend_rays, _) = gathered(&scene, backend.as_ref(), model, false);
        let (convex_light, convex_rays, convex_calls) =
            gathered(&scene, backend.as_ref(), model, true);
        assert_eq!(convex_rays, backend_rays, "{what}: the same tree");
        // Rays that leave one stone with the other's box ahead are traced.
        assert!(
            convex_calls > 2 * 64,
            "{what}: only {convex_calls} rays reached the backend"
        );
        assert_same_light(&what, &backend_light, &convex_light);
    }
}
