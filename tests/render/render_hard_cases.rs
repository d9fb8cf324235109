//! Hard cases for the whole tracer (not just the interface solver): rays
//! exactly along a crystal's optic axis and 1e-12 … 1e-6 rad away from it,
//! rays grazing a facet, rays meeting a facet exactly at the critical
//! angle. Every result must be finite, and results on either side of a
//! degeneracy must agree to within what the geometry of the neighbouring
//! rays can change.

use crate::support::render as common;
use common::*;
use glam::{DMat3, DVec3};
use spar::render::integrator::{Stats, Tracer, WavelengthMedia};

fn stokes_of(scene: &spar::scene::Scene, eye: DVec3, dir: DVec3, lambda: f64) -> [f64; 4] {
    let accel = spar::render::prepare::accel(scene, Default::default(), 1, None).unwrap();
    let tracer = Tracer::new(scene, accel.as_ref(), spar::render::prepare::tree(scene));
    let media = WavelengthMedia::new(scene, lambda);
    let x = dir.any_orthonormal_vector();
    let y = x.cross(dir);
    let mut stats = Stats::default();
    let j = tracer.camera_ray(eye, dir, [x, y], &media, &mut stats);
    let s = j.stokes();
    let v = [s.s0, s.s1, s.s2, s.s3];
    assert!(v.iter().all(|c| c.is_finite()), "non-finite Stokes {v:?}");
    v
}

const SLAB: &str = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [4, 4]
[render]
max_depth = 8
prune = 0.0
[[object]]
mesh = "slab.obj"
medium = "calcite"
optic_axis = AXIS
[[light]]
corners = [[-4.0, -4.0, -3.0], [4.0, -4.0, -3.0], [4.0, 4.0, -3.0], [-4.0, 4.0, -3.0]]
texture = "builtin:checker"
polarization = { linear = [1.0, 0.3, 0.0] }
[background]
radiance = 0.25
"#;

/// A camera ray straight down a calcite slab whose optic axis is vertical:
/// inside, o and e are degenerate (k ∥ c) and their split is a convention
/// (E_o from a fixed tangent at normal incidence); 1e-14 … 1e-6 rad away the
/// plane of incidence picks the split, in a direction that turns with the
/// tilt. At (near) normal incidence Fresnel does not depend on polarization,
/// so for unpolarized light the result cannot depend on the split: it must
/// agree to O(ε) with the ray exactly on the axis.
///
/// (For polarized light the split does matter: o and e are summed as
/// incoherent rays, so light along the axis is depolarized by an amount
/// that depends on the split's orientation, where physically it would pass
/// unchanged. That is a limit of the incoherent eigenwave model, documented
/// in `render::integrator`.)
#[test]
fn rays_along_the_optic_axis_are_finite_and_continuous() {
    let toml = SLAB
        .replace("AXIS", "[0.0, 0.0, 1.0]")
        .replace("polarization = { linear = [1.0, 0.3, 0.0] }", "");
    let slab = box_obj([-10.0, -10.0, -1.0], [10.0, 10.0, 0.0]);
    let (scene, _d) = common::scene(&toml, &[("slab.obj", slab)]);
    let eye = DVec3::new(0.11, 0.07, 5.0);
    let down = -DVec3::Z;
    let base = stokes_of(&scene, eye, down, 589.3);
    assert!(base[0] > 0.0);
    for eps in [1e-14, 1e-12, 1e-9, 1e-6] {
        for turn in [0.0, 1.0, 2.0, 4.0] {
            let tilt_axis = DMat3::from_rotation_z(turn) * DVec3::X;
            let dir = DMat3::from_axis_angle(tilt_axis, eps) * down;
            let s = stokes_of(&scene, eye, dir, 589.3);
            for c in 0..4 {
                assert!(
                    (s[c] - base[c]).abs() < 1e-9 * base[0] + 10.0 * eps * base[0],
                    "eps {eps}, turn {turn}: {s:?} vs {base:?}"
                );
            }
        }
    }
}

#[test]
fn grazing_rays_are_finite() {
    let toml = SLAB.replace("AXIS", "[0.0, 0.6, 0.8]");
    let slab = box_obj([-10.0, -10.0, -1.0], [10.0, 10.0, 0.0]);
    let (scene, _d) = common::scene(&toml, &[("slab.obj", slab)]);
    // Rays skimming the top face at 1e-3 … 1e-12 rad, and exactly in its
    // plane, from outside; and along the slab's edges.
    for eps in [1e-3, 1e-6, 1e-9, 1e-12, 0.0] {
        let dir = DVec3::new(1.0, 0.1, -eps).normalize();
        stokes_of(&scene, DVec3::new(-12.0, 0.0, 0.0), dir, 550.0);
        stokes_of(&scene, DVec3::new(-12.0, -10.0, 0.0), dir, 550.0);
    }
}

#[test]
fn critical_angle_inside_glass_is_finite_and_continuous() {
    // A right-angle glass prism: light enters the hypotenuse... simpler: a
    // slab of glass seen from below the critical angle: the backward ray
    // inside meets the bottom face at exactly the critical angle when the
    // outside angle of incidence is 90°; instead use a 45° prism whose
    // slanted face is met from inside at angle θc ± ε.
    let n: f64 = 1.5;
    let theta_c = (1.0 / n).asin();
    // Prism in x–z: right triangle with legs on x and z axes.
    let prism = prism_obj(&[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]], -2.0, 2.0);
    let toml = r#"
[camera]
eye = [0.5, 0.0, -5.0]
look_at = [0.5, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [4, 4]
[render]
max_depth = 8
prune = 0.0
[[object]]
mesh = "prism.obj"
medium = "iso:1.5"
[background]
radiance = 1.0
[[light]]
corners = [[4.0, -4.0, -4.0], [4.0, 4.0, -4.0], [4.0, 4.0, 4.0], [4.0, -4.0, 4.0]]
radiance = 3.0
"#;
    let (scene, _d) = common::scene(toml, &[("prism.obj", prism)]);
    // A ray entering the bottom face (z = 0) from below with refraction
    // angle φ inside meets the hypotenuse (normal (1,1)/√2) at incidence
    // |45° − φ|-ish; solve for the outside direction numerically: inside
    // direction making angle θc with the hypotenuse normal.
    let hyp = DVec3::new(1.0, 0.0, 1.0).normalize();
    let mut values = Vec::new();
    for eps in [-1e-6, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-6] {
        let ang = theta_c + eps;
        // Inside direction: rotate the hypotenuse normal by `ang` in x–z.
        let inside = DMat3::from_rotation_y(-ang) * hyp;
        assert!(((inside.dot(hyp)).acos() - ang).abs() < 1e-12);
        // Refract back out through the bottom face (normal −z outside).
        let st = (inside.x * inside.x + inside.y * inside.y).sqrt() * n;
        assert!(st < 1.0, "inside ray must leave the bottom face");
        let outside = DVec3::new(
            inside.x / (inside.x * inside.x + inside.y * inside.y).sqrt() * st,
            0.0,
            (1.0 - st * st).sqrt(),
        );
        let eye = DVec3::new(0.5, 0.0, 0.0) - 3.0 * outside;
        values.push((eps, stokes_of(&scene, eye, outside, 550.0)));
    }
    // Across the critical angle reflectance is continuous but not smooth:
    // below it, 1 − R grows like the square root of the distance, so within
    // ε = 1e-6 rad the light can move by about sqrt(ε) = 1e-3 of itself.
    let mid = values[3].1[0];
    for (eps, s) in &values {
        assert!((s[0] - mid).abs() < 1e-3 * mid, "eps {eps}: {s:?} vs {mid}");
    }
}

/// Renders `mesh` (a path under scenes/, or a built-in) as `medium` over a
/// uniform light and returns the film and the brightest radiance any pixel
/// could see at 580 nm.
fn gem_over_light(
    mesh: &str,
    (scale, tz): (f64, f64),
    medium: &str,
    depth: u32,
    prune: f64,
) -> (
    spar::render::film::Film,
    spar::render::integrator::Stats,
    f64,
) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mesh = if mesh.starts_with("builtin:") {
        mesh.to_string()
    } else {
        root.join(mesh).to_string_lossy().into_owned()
    };
    let axis = if medium == "calcite" {
        "optic_axis = [0.2, 0.5, 0.8]"
    } else {
        ""
    };
    let toml = format!(
        r#"
[camera]
eye = [0.3, -2.6, 2.4]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 24.0
resolution = [6, 6]
samples = 2
[render]
max_depth = {depth}
prune = {prune:e}
[[object]]
mesh = "{mesh}"
medium = "{medium}"
{axis}
transform = {{ scale = {scale:e}, translate = [0.0, 0.0, {tz:e}] }}
[[light]]
corners = [[-3.0, -3.0, -1.5], [3.0, -3.0, -1.5], [3.0, 3.0, -1.5], [-3.0, 3.0, -1.5]]
radiance = 1.0
polarization = {{ linear = [1.0, 0.3, 0.0] }}
[background]
radiance = 0.3
"#
    );
    let (scene, _d) = scene(&toml, &[]);
    let (film, stats) = render_at(&scene, &[580.0]);
    (film, stats, spar::spectrum::cie::d65(580.0))
}

/// Passive optics cannot make light brighter than its brightest source, or
/// more than fully polarized; every value must be finite.
fn assert_physical(film: &spar::render::film::Film, brightest: f64, what: &str) {
    for y in 0..film.height {
        for x in 0..film.width {
            let s = film.stokes(x, y, 0);
            assert!(s.iter().all(|v| v.is_finite()), "{what}: {s:?}");
            // f32 sums: a few roundings of slack.
            let slack = 1.0 + 1e-6;
            assert!(
                s[0] >= 0.0 && s[0] <= brightest * slack,
                "{what}: S0 {}",
                s[0]
            );
            let pol = (s[1] * s[1] + s[2] * s[2] + s[3] * s[3]).sqrt();
            assert!(
                pol <= s[0] * slack + 1e-12,
                "{what}: |S123| {pol} > S0 {}",
                s[0]
            );
        }
    }
}

#[test]
fn real_cuts_with_near_degenerate_triangles_render_physically() {
    // The OpenSCAD-made cuts have facets whose triangulations contain
    // slivers (facet normals from Newell's method keep them flat); the
    // triangulated trichecker has every facet split into thin fans.
    // (mesh, scale and lift to about unit size around the origin)
    for (mesh, fit) in [
        ("gems/openscad_brilliant.obj", (1.0 / 25.0, -1.0)),
        ("gems/openscad_portuguese.obj", (1.0 / 7.0, -0.7)),
        ("gems/openscad_rose.obj", (1.0 / 25.0, -1.0)),
        ("gems/openscad_swiss.obj", (1.0 / 25.0, -1.0)),
        ("gems/trichecker12_tri.obj", (1.0, 0.0)),
    ] {
        for medium in ["diamond", "calcite"] {
            let (film, stats, brightest) = gem_over_light(mesh, fit, medium, 16, 1e-5);
            assert_physical(&film, brightest, &format!("{mesh} in {medium}"));
            assert!(stats.nodes > 36, "{mesh}: the gem must be hit");
        }
    }
}

#[test]
fn very_deep_trees_stay_finite_and_bounded() {
    // Glass: depth 400 with pruning at 1e-13 (total internal reflection
    // keeps paths alive for hundreds of bounces). Calcite: depth 80 with
    // pruning at 1e-7 (four-way branching).
    let (film, stats, brightest) =
        gem_over_light("builtin:brilliant", (1.0 / 25.0, -1.0), "n-bk7", 400, 1e-13);
    assert_physical(&film, brightest, "glass, depth 400");
    assert!(stats.nodes > 1000);
    let (film, stats, brightest) =
        gem_over_light("builtin:brilliant", (1.0 / 25.0, -1.0), "calcite", 80, 1e-7);
    assert_physical(&film, brightest, "calcite, depth 80");
    assert!(stats.nodes > 1000);
}
