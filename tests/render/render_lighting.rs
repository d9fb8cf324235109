//! Gemological lighting (docs/scenes.md, "Light rigs" and "Tilting"):
//! each built-in rig's light is where its stated numbers put it, seen by a
//! probe camera that looks back at the rig; a rig of known radiance seen
//! through a glass slab gives the two-face Fresnel value; the `rig` scene
//! key and its errors; and the tilt's rotation (axis, sense, centre, crystal
//! axes) against the scene file's own rotation.

use crate::support::render::{box_obj, render_model, scene};
use glam::{DMat3, DVec3};
use spar::accel::AccelKind;
use spar::render::approx::CoherenceModel;
use spar::render::camera::Camera;
use spar::render::rig::LightRig;
use spar::render::tilt;
use spar::scene::Scene;
use spar::spectrum::cie::d65;

const NM: f64 = 550.0;

/// Camera A, whose rig is probed: at +z looking down −z, image up +y (so
/// its image right is +x).
fn camera_a() -> Camera {
    Camera::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y, 30.0, 8, 8).unwrap()
}

/// Renders `rig` (for camera A) as seen by a pinhole probe at the origin
/// looking up +z (back toward where A's rig light comes from), `fov`
/// degrees, n×n pixels through their centres; returns each pixel's
/// direction (where the light it sees comes from) and its radiance in
/// units of D65 at 550 nm.
fn probe(rig: LightRig, fov: f64, n: u32) -> Vec<(DVec3, f64)> {
    let toml = format!(
        "[camera]\neye = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, 1.0]\nup = [0.0, 1.0, 0.0]\n\
         fov = {fov}\nresolution = [{n}, {n}]\nsampling = \"center\"\n\
         [[light]]\nrig = \"ring\"\n"
    );
    let (mut s, _dir) = scene(&toml, &[]);
    s.distant_lights = rig.lights(&camera_a(), 1.0);
    let (film, _) = render_model(&s, &[NM], AccelKind::Rust, CoherenceModel::Physical);
    let mut out = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let d = s.camera.direction(x as f64 + 0.5, y as f64 + 0.5);
            out.push((d, film.stokes(x, y, 0)[0] / d65(NM)));
        }
    }
    out
}

/// Angle between unit vectors, degrees.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

/// Checks a probe: every pixel's radiance is `want(direction)` (to f32
/// rounding), except pixels within 0.05° of an edge (`near_edge`); returns
/// (dark, lit) pixel counts.
fn check(
    probe: &[(DVec3, f64)],
    want: impl Fn(DVec3) -> f64,
    near_edge: impl Fn(DVec3) -> bool,
) -> (usize, usize) {
    let (mut dark, mut lit) = (0, 0);
    for &(d, got) in probe {
        if near_edge(d) {
            continue;
        }
        let w = want(d);
        assert!(
            (got - w).abs() <= 1e-6 * w.max(1.0),
            "direction {d} ({:.3}° off the rig's axis): radiance {got}, want {w}",
            angle(d, DVec3::Z)
        );
        if w == 0.0 {
            dark += 1;
        } else {
            lit += 1;
        }
    }
    (dark, lit)
}

#[test]
fn the_dome_is_dark_exactly_within_its_head_shadow() {
    // Light comes from +z's side (behind camera A); the head shadow is the
    // cone of half its angular diameter around +z, the dome reaches 90°.
    for (rig, half) in [
        (LightRig::Dome { head_shadow: 30.0 }, 15.0),
        ("dome:40".parse().unwrap(), 20.0),
    ] {
        let p = probe(rig, 100.0, 61);
        let (dark, lit) = check(
            &p,
            |d| if angle(d, DVec3::Z) > half { 1.0 } else { 0.0 },
            |d| (angle(d, DVec3::Z) - half).abs() < 0.05,
        );
        assert!(dark > 20 && lit > 1000, "{rig}: {dark} dark, {lit} lit");
    }
}

#[test]
fn the_ring_lights_the_stated_cone_only() {
    let p = probe(LightRig::Ring, 40.0, 81);
    let (dark, lit) = check(
        &p,
        |d| {
            let a = angle(d, DVec3::Z);
            if a > 10.0 && a <= 15.0 {
                1.0
            } else {
                0.0
            }
        },
        |d| {
            let a = angle(d, DVec3::Z);
            (a - 10.0).abs() < 0.05 || (a - 15.0).abs() < 0.05
        },
    );
    assert!(dark > 1000 && lit > 500, "{dark} dark, {lit} lit");
}

#[test]
fn the_spot_is_a_two_degree_disc_twenty_degrees_above_the_camera_over_a_dim_dome() {
    // Camera A's image up is +y: the spot's light comes from 20° off +z
    // toward +y; it replaces the dome (0.05) within its 1° radius.
    let spot = DVec3::new(0.0, 20f64.to_radians().sin(), 20f64.to_radians().cos());
    let p = probe(LightRig::Spot, 60.0, 121);
    let (dark, lit) = check(
        &p,
        |d| {
            if angle(d, spot) <= 1.0 {
                2.0
            } else if angle(d, DVec3::Z) > 15.0 {
                0.05
            } else {
                0.0
            }
        },
        |d| (angle(d, spot) - 1.0).abs() < 0.05 || (angle(d, DVec3::Z) - 15.0).abs() < 0.05,
    );
    let in_spot = p.iter().filter(|(d, _)| angle(*d, spot) < 0.95).count();
    assert!(
        in_spot >= 4 && dark > 100 && lit > 1000,
        "{in_spot} in the spot, {dark} dark, {lit} lit"
    );
}

/// A 2×2×0.2 slab of n = 1.5 at the origin turned by `rotate_x` degrees
/// about x, seen face-on by an orthographic camera whose rays run along
/// its normal (from −5 normal), lit by `rig` for camera A: pixels through
/// the slab see `radiance` × (1 − R)/(1 + R), R = ((n − 1)/(n + 1))² (the
/// incoherent sum of the slab's internal reflections at normal incidence),
/// pixels beside it `radiance` itself.
fn through_a_slab(rig: LightRig, rotate_x: f64, radiance: f64) {
    let n = DMat3::from_rotation_x(rotate_x.to_radians()) * DVec3::Z;
    let eye = -5.0 * n;
    let toml = format!(
        "[camera]\neye = [{}, {}, {}]\nlook_at = [0.0, 0.0, 0.0]\nup = [1.0, 0.0, 0.0]\n\
         projection = \"orthographic\"\nwidth = 4.0\nresolution = [9, 9]\nsampling = \"center\"\n\
         [render]\nprune = 0\nmax_depth = 60\n\
         [[object]]\nmesh = \"slab.obj\"\nmedium = \"iso:1.5\"\n\
         transform = {{ rotate = [{rotate_x}, 0.0, 0.0] }}\n\
         [[light]]\nrig = \"ring\"\n",
        eye.x, eye.y, eye.z
    );
    let slab = box_obj([-1.0, -1.0, -0.1], [1.0, 1.0, 0.1]);
    let (mut s, _dir) = scene(&toml, &[("slab.obj", slab)]);
    s.distant_lights = rig.lights(&camera_a(), 1.0);
    let r = (0.5f64 / 2.5).powi(2);
    let through = (1.0 - r) / (1.0 + r);
    let (film, _) = render_model(&s, &[NM], AccelKind::Rust, CoherenceModel::Incoherent);
    for y in 0..9 {
        for x in 0..9 {
            // Pixel centres at −2 + (i + 0.5) 4/9: columns and rows 2 to 6
            // lie within the slab's ±1.
            let inside = (2..=6).contains(&x) && (2..=6).contains(&y);
            let want = radiance * if inside { through } else { 1.0 };
            let got = film.stokes(x, y, 0)[0] / d65(NM);
            assert!(
                (got - want).abs() < 1e-6,
                "{rig} pixel ({x}, {y}): {got}, want {want}"
            );
        }
    }
}

#[test]
fn rigs_of_known_radiance_give_the_fresnel_value_through_a_glass_slab() {
    // Light travelling 45° off camera A's axis (dome), 12.5° (the ring),
    // from the spot's centre (20° above), and the spot rig's dim dome.
    through_a_slab(LightRig::Dome { head_shadow: 30.0 }, 45.0, 1.0);
    through_a_slab(LightRig::Ring, 12.5, 1.0);
    through_a_slab(LightRig::Spot, -20.0, 2.0);
    through_a_slab(LightRig::Spot, 45.0, 0.05);
}

const BOX_SCENE: &str = "[camera]\neye = [0.0, -6.0, 0.5]\nlook_at = [0.0, 0.0, 0.0]\n\
    fov = 30.0\nresolution = [8, 8]\n\
    [[object]]\nmesh = \"box.obj\"\nmedium = \"calcite\"\noptic_axis = [0.0, 0.6, 0.8]\n\
    transform = { translate = [0.3, 0.2, 0.1] }\n";

fn box_scene(extra: &str) -> Result<Scene, String> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("box.obj"),
        box_obj([-0.5, -0.4, -1.0], [0.5, 0.4, 1.0]),
    )
    .unwrap();
    Scene::parse(&format!("{BOX_SCENE}{extra}"), "s.toml", dir.path()).map_err(|e| e.to_string())
}

#[test]
fn the_rig_key_builds_the_rig_for_the_scene_camera_and_refuses_what_it_cannot_take() {
    let s = box_scene("[[light]]\nrig = \"dome:40\"\nradiance = 2.0\n").unwrap();
    let want = LightRig::Dome { head_shadow: 40.0 }.lights(&s.camera, 2.0);
    assert_eq!(s.distant_lights, want);
    assert_eq!(want.len(), 1);
    assert!((want[0].inner_diameter - 40f64.to_radians()).abs() < 1e-15);
    assert!((want[0].angular_diameter - std::f64::consts::PI).abs() < 1e-15);
    assert_eq!(want[0].direction, s.camera.forward());
    assert_eq!(want[0].radiance, 2.0);
    // With other lights: the rig's lights at infinity join theirs.
    let s = box_scene("[[light]]\ndirection = [0, 0, -1]\n[[light]]\nrig = \"spot\"\n").unwrap();
    assert_eq!(s.distant_lights.len(), 3);

    let refused = |extra: &str, line: usize, says: &[&str]| {
        let e = box_scene(extra).unwrap_err();
        assert!(e.starts_with(&format!("s.toml:{line}: ")), "{e}");
        for w in says {
            assert!(e.contains(w), "{extra}: {e}");
        }
    };
    refused(
        "[[light]]\nrig = \"studio\"\n",
        12,
        &[
            "light[0].rig",
            "unknown light rig `studio`",
            "ring, dome, spot",
        ],
    );
    refused(
        "[[light]]\nrig = \"dome:200\"\n",
        12,
        &["light[0].rig", "from 0 to 180"],
    );
    refused("[[light]]\nrig = \"ring:3\"\n", 12, &["takes no parameter"]);
    refused(
        "[[light]]\nrig = \"dome\"\npolarization = { linear = [1, 0, 0] }\n",
        13,
        &["light[0].polarization", "only `radiance`"],
    );
    refused(
        "[[light]]\nrig = \"dome\"\nangular_diameter = 3.0\n",
        13,
        &["light[0].angular_diameter"],
    );
    refused(
        "[[light]]\nrig = \"dome\"\nradiance = -1.0\n",
        13,
        &["light[0].radiance"],
    );
    refused(
        "[[light]]\nrig = \"dome\"\ndirection = [0, 0, -1]\n",
        11,
        &["light[0]", "both `direction` and `rig`"],
    );
}

#[test]
fn a_tilt_turns_the_objects_about_image_right_through_their_centre() {
    let s = box_scene("[background]\nradiance = 1.0\n").unwrap();
    // Zero: the scene itself, bit for bit.
    let t0 = tilt::tilted(&s, 0.0).unwrap();
    assert_eq!(t0.objects[0].mesh.positions, s.objects[0].mesh.positions);
    // The camera looks along +y from −y, up +z: image right is +x. The
    // box's centre is its translation; a tilt of θ is the scene file's
    // rotation about x by θ applied about that centre.
    let right = s.camera.right();
    assert!((right - DVec3::X).length() < 1e-15);
    let c = tilt::centre(&s).unwrap();
    assert!((c - DVec3::new(0.3, 0.2, 0.1)).length() < 1e-15);
    for theta in [-30.0, 12.5, 75.0] {
        let t = tilt::tilted(&s, theta).unwrap();
        let file = {
            let dir = tempfile::tempdir().unwrap();
            std::fs::write(
                dir.path().join("box.obj"),
                box_obj([-0.5, -0.4, -1.0], [0.5, 0.4, 1.0]),
            )
            .unwrap();
            let text = BOX_SCENE.replace(
                "transform = { translate",
                &format!("transform = {{ rotate = [{theta}, 0.0, 0.0], translate"),
            );
            Scene::parse(
                &format!("{text}[background]\nradiance = 1.0\n"),
                "s.toml",
                dir.path(),
            )
            .unwrap()
        };
        for (p, q) in t.objects[0]
            .mesh
            .positions
            .iter()
            .zip(&file.objects[0].mesh.positions)
        {
            assert!((*p - *q).length() < 1e-12, "{theta}°: {p} vs {q}");
        }
        // The optic axis turns with the stone.
        let (a, b) = (
            t.objects[0].material.axis().unwrap(),
            file.objects[0].material.axis().unwrap(),
        );
        assert!((a - b).length() < 1e-12, "{theta}°: axis {a} vs {b}");
        // Positive tilts bring the top (+z, image up) toward the camera
        // (−y): the box's top face's centre moves to smaller y.
        let top = |sc: &Scene| {
            let ps = &sc.objects[0].mesh.positions;
            let zmax = ps.iter().map(|p| p.z).fold(f64::MIN, f64::max);
            ps.iter()
                .filter(|p| p.z > zmax - 0.5)
                .map(|p| p.y)
                .sum::<f64>()
        };
        if theta > 0.0 {
            assert!(top(&t) < top(&s), "{theta}°");
        }
    }
    // Tilted until it reaches the camera: refused, saying so.
    let mut near = box_scene("[background]\nradiance = 1.0\n").unwrap();
    near.camera = Camera::new(
        DVec3::new(0.3, -0.7, 0.1),
        DVec3::new(0.3, 0.0, 0.1),
        DVec3::Z,
        30.0,
        8,
        8,
    )
    .unwrap();
    let e = tilt::tilted(&near, 80.0).unwrap_err();
    assert!(e.contains("reaches where the camera's rays start"), "{e}");
    assert!(tilt::tilted(&near, 10.0).is_ok());
    for bad in [f64::NAN, 90.5, -100.0] {
        assert!(tilt::tilted(&s, bad).is_err(), "{bad}");
    }
}
