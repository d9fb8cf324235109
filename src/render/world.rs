//! What the renderer renders: the validated scene (world-space meshes with
//! their materials, lights, camera, settings). `spar::scene` reads it
//! from scene files; the renderer only reads it.

use super::adaptive::Adaptive;
use super::approx::Approximations;
use super::camera::Camera;
use super::light::{DistantLight, Environment, Light};
use crate::geometry::Mesh;
use crate::material::Material;
use crate::spectrum::WavelengthSet;

/// Render settings from the scene's `[render]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub wavelengths: WavelengthSet,
    pub max_depth: u32,
    /// A subtree is skipped when it can contribute less than this fraction
    /// of the brightest emitter's radiance; 0 disables pruning.
    pub prune: f64,
    pub seed: u64,
    /// Branch strategy, polarization model, spectral sampling and
    /// dispersion (exact by default).
    pub approx: Approximations,
    /// Adaptive sampling (off by default: every pixel takes every sample).
    pub adaptive: Adaptive,
}

/// Defaults: 21 wavelengths, depth 30, pruning at 1e-4 of the brightest
/// emitter, seed 0. Depth 30, not the seed paper's 13: at 512×512 depth 13
/// loses 0.011 colour RMSE on the glass gem (light trapped by total
/// internal reflection needs more bounces), depth 30 0.00002, for 9 % more
/// rays; with pruning at 1e-4 deeper trees stay bounded
/// (docs/speed-vs-error.md, "What each shortcut costs").
pub const DEFAULT_WAVELENGTHS: usize = 21;
/// Default largest number of surface interactions along a path.
pub const DEFAULT_MAX_DEPTH: u32 = 30;
/// Default pruning threshold, a fraction of the brightest emitter.
pub const DEFAULT_PRUNE: f64 = 1e-4;

/// Nanometres per scene unit unless a scene says otherwise: millimetres.
pub const DEFAULT_UNIT_NM: f64 = 1e6;

/// One solid object: a closed mesh in world space and its material (a
/// crystal's optic axis already in world space).
#[derive(Clone, Debug)]
pub struct Object {
    pub name: String,
    pub mesh: Mesh,
    pub material: Material,
}

/// A validated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    pub samples: u32,
    pub settings: RenderSettings,
    pub objects: Vec<Object>,
    pub lights: Vec<Light>,
    /// Lights at infinity.
    pub distant_lights: Vec<DistantLight>,
    /// Light from every direction at infinity (replaces the background
    /// where a ray escapes; a scene has at most one).
    pub environment: Option<Environment>,
    /// The length of one scene unit in nanometres (`[render] units`;
    /// millimetres by default): propagation phases need it.
    pub unit_nm: f64,
    /// Unpolarized background radiance, in units of D65.
    pub background: f64,
    /// The scene file's text, for the render's identity.
    pub source: String,
}

impl Scene {
    /// True when some medium's index depends on wavelength.
    pub fn is_dispersive(&self) -> bool {
        self.objects.iter().any(|o| o.material.is_dispersive())
    }

    /// True when some object is a crystal (uniaxial or biaxial).
    pub fn has_crystals(&self) -> bool {
        self.objects
            .iter()
            .any(|o| o.material.is_uniaxial() || o.material.is_biaxial())
    }
}
