//! Tilting the stone (`spar render --tilt DEG`, `spar tilt`): every object
//! turned about the camera's horizontal axis (image right) through the
//! centre of the objects' bounding box, as a buyer tilts a stone in the
//! hand. The objects turn, not the camera: the room's lights (area lights,
//! lights at infinity, an environment map fixed to world +z) stay where
//! they are, and a rig, defined relative to the camera, stays with the
//! observer.

use super::world::Scene;
use crate::geometry::overlap;
use glam::{DAffine3, DMat3, DVec3};

/// The rotation of a tilt by `degrees`: right-handed about the camera's
/// image right `right`, so a positive tilt turns image up toward the
/// camera (the stone's top edge, as the image shows it, comes forward).
pub fn rotation(right: DVec3, degrees: f64) -> DMat3 {
    DMat3::from_axis_angle(right, degrees.to_radians())
}

/// The centre the objects turn about: the middle of their joint bounding
/// box (`None` without objects).
pub fn centre(scene: &Scene) -> Option<DVec3> {
    let (lo, hi) = scene.objects.iter().map(|o| o.mesh.bounds()).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
    );
    (!scene.objects.is_empty()).then(|| 0.5 * (lo + hi))
}

/// The scene with its objects tilted by `degrees` (a finite number from
/// −90 to 90): meshes, optic axes and crystal axes turned together. A tilt
/// of exactly 0 returns the scene unchanged, bit for bit. Refused (with a
/// message saying why) when the turned stone would reach where the camera's
/// rays start.
pub fn tilted(scene: &Scene, degrees: f64) -> Result<Scene, String> {
    if !(degrees.is_finite() && (-90.0..=90.0).contains(&degrees)) {
        return Err("a tilt must be a finite number of degrees from -90 to 90".to_string());
    }
    let mut out = scene.clone();
    let Some(c) = centre(scene) else {
        return Ok(out);
    };
    if degrees == 0.0 {
        return Ok(out);
    }
    let r = rotation(scene.camera.right(), degrees);
    let about =
        DAffine3::from_translation(c) * DAffine3::from_mat3(r) * DAffine3::from_translation(-c);
    for o in &mut out.objects {
        o.mesh = o.mesh.transformed(&about);
        let m = o.material.clone();
        o.material = if let Some(axis) = m.axis() {
            m.with_axis(r * axis)?
        } else if let Some((z, x)) = m.crystal_axes() {
            m.with_crystal_axes(r * z, r * x)?
        } else {
            m
        };
    }
    let cam = &out.camera;
    let (w, h) = (cam.width as f64, cam.height as f64);
    for (fx, fy) in [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)] {
        let start = cam.ray(fx, fy).0;
        if let Some(o) = out
            .objects
            .iter()
            .find(|o| overlap::point_inside(&o.mesh, start))
        {
            return Err(format!(
                "tilted by {degrees}°, {} reaches where the camera's rays start ({start}): move \
                 the camera back or tilt less",
                o.name
            ));
        }
    }
    Ok(out)
}
