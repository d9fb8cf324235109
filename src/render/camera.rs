//! The camera (pinhole or orthographic), the per-ray polarization frame of
//! the film, and an optional analyzer in front of it.
//!
//! Stokes frame (Mitsuba 3's `stokes` integrator convention): for a camera
//! ray of direction d, the light arriving travels along −d; the receiver
//! looks back along d at the source. x = unit(d × camera up) is image
//! right, y = x × d is image up, and (x, y, −d) is right-handed.
//! S1 > 0 is horizontal, S2 > 0 is at +45° from image right toward image up.

use crate::optics::Jones;
use glam::DVec3;

/// How film positions become rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Every ray starts at the eye; the vertical field of view is given.
    Pinhole,
    /// Every ray travels along the viewing direction from a point of the
    /// image plane through the eye, `width` scene units across the image.
    Orthographic { width: f64 },
}

/// Where in a pixel a sample's ray passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelSampling {
    /// Low-discrepancy positions over the pixel, one per sample
    /// (`render::sampling`): the pixel's area is integrated.
    #[default]
    Jittered,
    /// Every sample through the pixel's centre: a point sample of the
    /// image, for comparisons with references that sample centres.
    Center,
}

/// A camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_half_fov: f64,
    pub width: u32,
    pub height: u32,
    pub projection: Projection,
    /// A Jones matrix in the film's frame (x image right, y image up)
    /// applied to the light reaching every pixel before its coherence
    /// matrix is recorded: a polarizer, a retarder or a chain of them.
    pub analyzer: Option<Jones>,
    /// Where in each pixel the samples' rays pass.
    pub sampling: PixelSampling,
}

impl Camera {
    /// A camera at `eye` looking at `look_at`, `up` roughly up, vertical
    /// field of view `vfov_deg` degrees, `width` × `height` pixels.
    pub fn new(
        eye: DVec3,
        look_at: DVec3,
        up: DVec3,
        vfov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Camera, String> {
        let forward = (look_at - eye).normalize_or_zero();
        if forward == DVec3::ZERO || !forward.is_finite() {
            return Err("look_at must differ from eye".into());
        }
        let right = forward.cross(up).normalize_or_zero();
        if right == DVec3::ZERO || !right.is_finite() {
            return Err("up must not be parallel to the viewing direction".into());
        }
        if !(vfov_deg > 0.0 && vfov_deg < 180.0) {
            return Err(format!(
                "field of view must be in (0, 180) degrees, not {vfov_deg}"
            ));
        }
        if width == 0 || height == 0 {
            return Err("resolution must be at least 1×1".into());
        }
        Ok(Camera {
            eye,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov: (vfov_deg.to_radians() / 2.0).tan(),
            width,
            height,
            projection: Projection::Pinhole,
            analyzer: None,
            sampling: PixelSampling::Jittered,
        })
    }

    /// The same camera with an orthographic projection `width` scene
    /// units across the image (its field of view is then unused).
    pub fn orthographic(mut self, width: f64) -> Result<Camera, String> {
        if !(width.is_finite() && width > 0.0) {
            return Err(format!(
                "an orthographic camera's width must be a finite number > 0, not {width}"
            ));
        }
        self.projection = Projection::Orthographic { width };
        Ok(self)
    }

    /// The same camera behind an analyzer (a Jones matrix in the film's
    /// frame).
    pub fn with_analyzer(mut self, analyzer: Option<Jones>) -> Camera {
        self.analyzer = analyzer;
        self
    }

    /// The same camera sampling its pixels as `sampling` says.
    pub fn with_sampling(mut self, sampling: PixelSampling) -> Camera {
        self.sampling = sampling;
        self
    }

    /// The viewing direction (unit).
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// Image right (unit): forward × up.
    pub fn right(&self) -> DVec3 {
        self.right
    }

    /// Image up (unit), orthogonal to the viewing direction.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The ray (origin, unit direction) through film position (`fx`,
    /// `fy`) in pixels, (0, 0) the top-left corner.
    pub fn ray(&self, fx: f64, fy: f64) -> (DVec3, DVec3) {
        match self.projection {
            Projection::Pinhole => (self.eye, self.direction(fx, fy)),
            Projection::Orthographic { width } => {
                let height = width * self.height as f64 / self.width as f64;
                let sx = (fx / self.width as f64 - 0.5) * width;
                let sy = (0.5 - fy / self.height as f64) * height;
                (self.eye + sx * self.right + sy * self.up, self.forward)
            }
        }
    }

    /// The width of one pixel's footprint at `point`, scene units: the
    /// pixel's angular size at the image centre times the distance from the
    /// eye (pinhole), or the pixel's width (orthographic). What a bundle's
    /// tolerance is measured in (`render::bundle`).
    pub fn footprint(&self, point: DVec3) -> f64 {
        match self.projection {
            Projection::Pinhole => {
                2.0 * self.tan_half_fov / self.height as f64 * (point - self.eye).length()
            }
            Projection::Orthographic { width } => width / self.width as f64,
        }
    }

    /// The angle one pixel spans at the image centre, radians (0 for an
    /// orthographic camera, whose rays are parallel).
    pub fn pixel_angle(&self) -> f64 {
        match self.projection {
            Projection::Pinhole => 2.0 * self.tan_half_fov / self.height as f64,
            Projection::Orthographic { .. } => 0.0,
        }
    }

    /// The same camera with another image size (the field of view stays
    /// vertical).
    pub fn with_resolution(mut self, width: u32, height: u32) -> Camera {
        self.width = width.max(1);
        self.height = height.max(1);
        self
    }

    /// Unit direction of a pinhole camera's ray through film position (`fx`, `fy`) in pixels, (0, 0)
    /// the top-left corner of the image, (width, height) the bottom-right.
    pub fn direction(&self, fx: f64, fy: f64) -> DVec3 {
        let aspect = self.width as f64 / self.height as f64;
        let sx = (2.0 * fx / self.width as f64 - 1.0) * self.tan_half_fov * aspect;
        let sy = (1.0 - 2.0 * fy / self.height as f64) * self.tan_half_fov;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// The film's polarization frame (x, y) for a ray of unit direction `d`:
    /// x = unit(d × camera up) (image right), y = x × d (image up), as
    /// Mitsuba 3's `stokes` integrator does (`src/integrators/stokes.cpp`);
    /// checked against Mitsuba by `tools/mitsuba_crosscheck.py`.
    pub fn stokes_frame(&self, d: DVec3) -> (DVec3, DVec3) {
        let x = d.cross(self.up).normalize();
        (x, x.cross(d))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_at_target_and_frame_is_right_handed() {
        let c = Camera::new(
            DVec3::new(0.0, -5.0, 0.0),
            DVec3::ZERO,
            DVec3::Z,
            40.0,
            200,
            100,
        )
        .unwrap();
        let d = c.direction(100.0, 50.0);
        assert!((d - DVec3::Y).length() < 1e-15);
        let (x, y) = c.stokes_frame(d);
        assert!((x - DVec3::X).length() < 1e-15);
        assert!((y - DVec3::Z).length() < 1e-15);
        // (x, y, propagation of the light = −d) is right-handed.
        assert!((x.cross(y) + d).length() < 1e-15);
    }

    #[test]
    fn edges_match_the_field_of_view() {
        let c = Camera::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 60.0, 100, 100).unwrap();
        let top = c.direction(50.0, 0.0);
        assert!((top.angle_between(DVec3::Y).to_degrees() - 30.0).abs() < 1e-12);
        assert!(top.z > 0.0, "image top is world up");
        let right = c.direction(100.0, 50.0);
        assert!(right.x > 0.0, "image right is world right");
        let (x, y) = c.stokes_frame(right);
        assert!(x.dot(right).abs() < 1e-15 && y.dot(right).abs() < 1e-15);
        assert!((x.cross(y) + right).length() < 1e-15);
    }

    #[test]
    fn degenerate_cameras_are_errors() {
        assert!(Camera::new(DVec3::ZERO, DVec3::ZERO, DVec3::Z, 40.0, 1, 1).is_err());
        assert!(Camera::new(DVec3::ZERO, DVec3::Z, DVec3::Z, 40.0, 1, 1).is_err());
        assert!(Camera::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 180.0, 1, 1).is_err());
        assert!(Camera::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 40.0, 0, 1).is_err());
    }
}
