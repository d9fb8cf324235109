//! The scene file format (TOML), as serde reads it. Every value that is
//! checked after parsing keeps its span so that errors name the line.
//!
//! ```toml
//! [camera]
//! eye = [0.0, -4.0, 3.0]
//! look_at = [0.0, 0.0, 0.0]
//! up = [0.0, 0.0, 1.0]         # default +z
//! fov = 30.0                   # vertical, degrees
//! resolution = [256, 256]
//! samples = 4                  # per pixel, default 1
//!
//! [render]
//! wavelengths = 21             # a count over 380–780 nm, or a list [450, 550]
//! max_depth = 13
//! prune = 1e-4                 # 0: no pruning
//! seed = 0
//!
//! [media.my_glass]             # custom media (optional)
//! n = 1.5                      # constant, or { sellmeier = … }, { cauchy = … }
//!
//! [media.my_crystal]
//! n_o = 1.6584
//! n_e = 1.4864
//!
//! [[object]]
//! mesh = "gems/trichecker12.obj"   # .obj or .asc, relative to this file, or "builtin:NAME"
//! # or: cut = { name = "round-brilliant", table = 0.53, crown_angle = 34.5, pavilion_angle = 40.75 }
//! medium = "calcite"               # built-in, iso:N, uniaxial:NO:NE, or a [media] name
//! optic_axis = [0.0, 1.0, 1.0]     # object space; crystals only (default +z)
//! transform = { scale = 1.0, rotate = [0.0, 0.0, 30.0], translate = [0.0, 0.0, 0.0] }
//!
//! [[light]]
//! corners = [[-2, -2, -1], [2, -2, -1], [2, 2, -1], [-2, 2, -1]]  # emits toward (c1−c0)×(c3−c0)
//! radiance = 1.0
//! texture = "textures/checker.png" # optional
//! polarization = "unpolarized"     # or { linear = [1, 0, 0] } or { calcite_plate = "o", axis = [..] }
//!
//! [background]
//! radiance = 0.0
//! ```

use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

pub type V3 = [f64; 3];

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: CameraDef,
    #[serde(default)]
    pub render: RenderDef,
    #[serde(default)]
    pub media: BTreeMap<String, Spanned<MediumDef>>,
    #[serde(default, rename = "object")]
    pub objects: Vec<Spanned<ObjectDef>>,
    #[serde(default, rename = "light")]
    pub lights: Vec<Spanned<LightDef>>,
    pub background: Option<BackgroundDef>,
}

fn default_up() -> Spanned<V3> {
    Spanned::new(0..0, [0.0, 0.0, 1.0])
}

fn default_samples() -> Spanned<u32> {
    Spanned::new(0..0, 1)
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct CameraDef {
    pub eye: Spanned<V3>,
    pub look_at: Spanned<V3>,
    #[serde(default = "default_up")]
    pub up: Spanned<V3>,
    /// Vertical field of view, degrees.
    pub fov: Spanned<f64>,
    pub resolution: Spanned<[u32; 2]>,
    #[serde(default = "default_samples")]
    pub samples: Spanned<u32>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum WavelengthsDef {
    Count(u32),
    List(Vec<f64>),
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct RenderDef {
    pub wavelengths: Option<Spanned<WavelengthsDef>>,
    pub max_depth: Option<Spanned<u32>>,
    pub prune: Option<Spanned<f64>>,
    pub seed: Option<u64>,
    /// `full`, `stochastic` or `hybrid:K` (render::approx).
    pub branching: Option<Spanned<String>>,
    /// `full` or `scalar`.
    pub polarization: Option<Spanned<String>>,
    /// `all` or `hero:K`.
    pub spectral: Option<Spanned<String>>,
    /// `true`/`false`, or `"on"`, `"off"`, `"bands:K"` (checked in
    /// `Scene::parse`, which names what it takes).
    pub dispersion: Option<Spanned<toml::Value>>,
}

/// A refractive index model: a number (constant) or one named model.
#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum DispersionDef {
    Constant(f64),
    Model(DispersionModel),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum DispersionModel {
    /// n² = a + Σ B λ²/(λ² − C), C in µm² (Schott's form; a defaults to 1).
    Sellmeier {
        #[serde(default = "one")]
        a: f64,
        b: Vec<f64>,
        c: Vec<f64>,
    },
    /// n² = a + Σ B λ²/(λ² − λ_i²), λ_i in µm (Malitson's form).
    SellmeierPoles {
        #[serde(default = "one")]
        a: f64,
        b: Vec<f64>,
        poles: Vec<f64>,
    },
    /// n = a + b/λ² + c/λ⁴, λ in µm.
    Cauchy {
        a: f64,
        #[serde(default)]
        b: f64,
        #[serde(default)]
        c: f64,
    },
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct MediumDef {
    /// Isotropic index.
    pub n: Option<Spanned<DispersionDef>>,
    /// Uniaxial ordinary and extraordinary indices.
    pub n_o: Option<Spanned<DispersionDef>>,
    pub n_e: Option<Spanned<DispersionDef>>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct ObjectDef {
    /// An OBJ or GemCAD .asc file (relative to the scene file), or
    /// `builtin:NAME`.
    pub mesh: Option<Spanned<String>>,
    /// A generated standard cut: `{ name = "round-brilliant", table = 0.53, … }`.
    pub cut: Option<Spanned<toml::Value>>,
    pub medium: Spanned<String>,
    pub optic_axis: Option<Spanned<V3>>,
    pub transform: Option<Spanned<TransformDef>>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum ScaleDef {
    Uniform(f64),
    PerAxis(V3),
}

/// Applied as scale, then rotation about x, y, z (degrees, in that order),
/// then translation.
#[derive(Deserialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub struct TransformDef {
    pub scale: Option<ScaleDef>,
    pub rotate: Option<V3>,
    pub translate: Option<V3>,
}

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
pub enum PolarizationDef {
    Named(String),
    Filter(FilterDef),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum FilterDef {
    /// An ideal linear polarizer whose transmission axis is this direction
    /// (projected into the light's plane).
    Linear(V3),
    /// A virtual calcite plate of this optic axis that keeps one wave.
    CalcitePlate(PlateDef),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct PlateDef {
    pub keep: String,
    pub axis: V3,
}

fn default_radiance() -> Spanned<f64> {
    Spanned::new(0..0, 1.0)
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct LightDef {
    pub corners: Spanned<[V3; 4]>,
    #[serde(default = "default_radiance")]
    pub radiance: Spanned<f64>,
    pub texture: Option<Spanned<String>>,
    pub polarization: Option<Spanned<PolarizationDef>>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct BackgroundDef {
    pub radiance: Spanned<f64>,
}
