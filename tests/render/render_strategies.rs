//! The integrator's strategies against the exact full tree: stochastic and
//! hybrid branching are unbiased (their mean converges to the full tree
//! within the statistical error they themselves show), and a wavelength
//! batch that shares its geometry gives exactly the per-wavelength trees.

use crate::support::render as common;
use spar::optics::Coherence;
use spar::render::approx::{Branching, PolarizationModel, Strategy};
use spar::render::integrator::{Stats, Tracer, TreeSettings, WavelengthMedia};
use spar::render::sampling::SampleKey;

/// The trichecker gem in `medium` (with the `axis` line of a crystal),
/// above a textured, polarized light.
pub(crate) fn gem_scene(medium: &str, axis: &str) -> (spar::scene::Scene, tempfile::TempDir) {
    gems_scene(&format!(
        "[[object]]\nmesh = \"builtin:trichecker12\"\nmedium = \"{medium}\"\n{axis}\n"
    ))
}

/// [`gem_scene`]'s camera, light and background around the `[[object]]`
/// tables `objects`.
pub(crate) fn gems_scene(objects: &str) -> (spar::scene::Scene, tempfile::TempDir) {
    let toml = format!(
        r#"
[camera]
eye = [0.0, -3.0, 2.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 30.0
resolution = [8, 8]
[render]
max_depth = 12
prune = 0.0
{objects}
[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
texture = "builtin:checker"
polarization = {{ linear = [1.0, 0.4, 0.0] }}
[background]
radiance = 0.3
"#
    );
    common::scene(&toml, &[])
}

fn stokes(j: &Coherence) -> [f64; 4] {
    let s = j.stokes();
    [s.s0, s.s1, s.s2, s.s3]
}

#[test]
fn stochastic_and_hybrid_branching_are_unbiased() {
    for (medium, axis) in [("n-bk7", ""), ("calcite", "optic_axis = [0.3, 0.5, 0.8]")] {
        let (scene, _d) = gem_scene(medium, axis);
        let accel = spar::render::prepare::accel(&scene, Default::default(), 1, None).unwrap();
        let settings = TreeSettings {
            max_depth: 12,
            prune: 0.0,
            convex_exit: true,
        };
        let full = Tracer::new(&scene, accel.as_ref(), settings);
        let media = WavelengthMedia::new(&scene, 550.0);
        let eye = scene.camera.eye;
        // Rays through the gem's crown at a few places.
        for (fx, fy) in [(4.0, 4.0), (3.2, 4.6), (5.1, 3.7)] {
            let d = scene.camera.direction(fx, fy);
            let (x, y) = scene.camera.stokes_frame(d);
            let mut stats = Stats::default();
            let exact = stokes(&full.camera_ray(eye, d, [x, y], &media, &mut stats));
            assert!(exact[0] > 0.0);
            for branching in [Branching::Stochastic, Branching::Hybrid { full_depth: 2 }] {
                let tracer =
                    Tracer::new(&scene, accel.as_ref(), settings).with_strategy(Strategy {
                        branching,
                        polarization: PolarizationModel::Full,
                        ..Strategy::default()
                    });
                let (mean, se, _) =
                    common::sampled_mean(&tracer, (eye, d, [x, y]), &media, 20_000, (7, 3));
                for c in 0..4 {
                    // 5 standard errors, plus rounding.
                    let tol = 5.0 * se[c] + 1e-9 * exact[0];
                    assert!(
                        (mean[c] - exact[c]).abs() <= tol,
                        "{medium} {branching:?} S{c}: mean {} ± {} vs exact {}",
                        mean[c],
                        se[c],
                        exact[c]
                    );
                }
            }
        }
    }
}

#[test]
fn a_shared_geometry_batch_equals_per_wavelength_trees() {
    // Constant indices: no dispersion, so every wavelength has the same tree.
    for (medium, axis) in [
        ("iso:1.6", ""),
        ("uniaxial:1.6584:1.4864", "optic_axis = [0.3, 0.5, 0.8]"),
    ] {
        let (scene, _d) = gem_scene(medium, axis);
        assert!(!scene.is_dispersive());
        let accel = spar::render::prepare::accel(&scene, Default::default(), 1, None).unwrap();
        let tracer = Tracer::new(
            &scene,
            accel.as_ref(),
            TreeSettings {
                max_depth: 12,
                prune: 0.0,
                convex_exit: true,
            },
        );
        let lambdas = [420.0, 510.0, 580.0, 690.0];
        let batch: Vec<WavelengthMedia> = lambdas
            .iter()
            .map(|&l| WavelengthMedia::new(&scene, l))
            .collect();
        let key = SampleKey {
            seed: 0,
            pixel: 0,
            sample: 0,
        };
        for (fx, fy) in [(4.0, 4.0), (3.2, 4.6), (1.0, 7.5)] {
            let d = scene.camera.direction(fx, fy);
            let (x, y) = scene.camera.stokes_frame(d);
            let mut stats = Stats::default();
            let mut out = vec![Coherence::zero(2); lambdas.len()];
            tracer.trace_camera(
                scene.camera.eye,
                d,
                [x, y],
                &batch,
                &key,
                &mut out,
                &mut stats,
            );
            for (i, m) in batch.iter().enumerate() {
                let one = tracer.camera_ray(scene.camera.eye, d, [x, y], m, &mut stats);
                assert_eq!(
                    stokes(&out[i]),
                    stokes(&one),
                    "{medium} at {} nm",
                    m.lambda_nm
                );
            }
        }
    }
}

#[test]
fn scalar_transport_is_unpolarized_and_exact_without_interfaces() {
    let (scene, _d) = gem_scene("n-bk7", "");
    let accel = spar::render::prepare::accel(&scene, Default::default(), 1, None).unwrap();
    let settings = TreeSettings {
        max_depth: 12,
        prune: 0.0,
        convex_exit: true,
    };
    let scalar = Tracer::new(&scene, accel.as_ref(), settings).with_strategy(Strategy {
        branching: Branching::Full,
        polarization: PolarizationModel::Scalar,
        ..Strategy::default()
    });
    let full = Tracer::new(&scene, accel.as_ref(), settings);
    let media = WavelengthMedia::new(&scene, 550.0);
    let mut stats = Stats::default();
    // A ray that misses the gem and sees the polarized light directly:
    // same intensity, no polarization.
    let d = scene.camera.direction(0.5, 7.5);
    let (x, y) = scene.camera.stokes_frame(d);
    let a = stokes(&scalar.camera_ray(scene.camera.eye, d, [x, y], &media, &mut stats));
    let b = stokes(&full.camera_ray(scene.camera.eye, d, [x, y], &media, &mut stats));
    assert!(
        b[0] > 0.0 && (b[1].abs() + b[2].abs()) > 0.5 * b[0],
        "the direct view is polarized: {b:?}"
    );
    assert!((a[0] - b[0]).abs() <= 1e-12 * b[0]);
    assert_eq!([a[1], a[2], a[3]], [0.0, 0.0, 0.0]);
    // Through the gem: finite, unpolarized.
    let d = scene.camera.direction(4.0, 4.0);
    let (x, y) = scene.camera.stokes_frame(d);
    let a = stokes(&scalar.camera_ray(scene.camera.eye, d, [x, y], &media, &mut stats));
    assert!(a[0].is_finite() && a[0] > 0.0);
    assert_eq!([a[1], a[2], a[3]], [0.0, 0.0, 0.0]);
}
