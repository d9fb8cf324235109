//! Rays inside a convex stone leave it by its facet planes
//! (`accel::convex`, `TreeSettings::convex_exit`) instead of the backend's
//! triangles: the light every camera ray gathers is the backend's to f64
//! rounding, in both coherence models, on glass and calcite and on both
//! backends; and the backend then sees only the rays outside the stone.

use crate::render_strategies::gem_scene as gem;
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

#[test]
fn convex_exits_gather_the_backends_light() {
    let kinds: Vec<AccelKind> = AccelKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .collect();
    for (medium, axis) in [("n-bk7", ""), ("calcite", "optic_axis = [0.3, 0.5, 0.8]")] {
        let (scene, _d) = gem(medium, axis);
        let media = WavelengthMedia::new(&scene, 550.0);
        for &kind in &kinds {
            let backend = spar::render::prepare::accel(&scene, kind, 1, None).unwrap();
            for model in [CoherenceModel::Incoherent, CoherenceModel::Physical] {
                let what = format!("{medium} {kind} {model}");
                let run = |convex_exit: bool| {
                    let counting = Counting {
                        inner: backend.as_ref(),
                        calls: AtomicU64::new(0),
                    };
                    let settings = TreeSettings {
                        max_depth: 12,
                        prune: 0.0,
                        convex_exit,
                    };
                    let tracer = Tracer::new(&scene, &counting, settings).with_strategy(Strategy {
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
                            let (s, _, stats) = common::sampled_mean(
                                &tracer,
                                (eye, d, [bx, by]),
                                &media,
                                1,
                                (1, 0),
                            );
                            assert_eq!(stats.lost, 0, "{what}: lost rays");
                            rays += stats.rays;
                            pixels.push(s);
                        }
                    }
                    (pixels, rays, counting.calls.into_inner())
                };
                let (backend_light, backend_rays, backend_calls) = run(false);
                let (convex_light, convex_rays, convex_calls) = run(true);
                assert_eq!(
                    backend_rays, backend_calls,
                    "{what}: every ray to the backend"
                );
                assert_eq!(convex_rays, backend_rays, "{what}: the same tree");
                // Most of the rays travel inside the stone (the rest start
                // on the camera or leave the stone).
                assert!(
                    convex_calls * 2 < backend_calls,
                    "{what}: the backend still traced {convex_calls} of {backend_calls} rays"
                );
                let brightest = backend_light.iter().map(|s| s[0]).fold(0.0, f64::max);
                assert!(brightest > 0.0);
                for (i, (a, b)) in backend_light.iter().zip(&convex_light).enumerate() {
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
        }
    }
}
