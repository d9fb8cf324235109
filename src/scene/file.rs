//! The scene file format (TOML), as serde reads it. Every value that is
//! checked after parsing keeps its span so that errors name the line.
//!
//! ```toml
//! [camera]
//! eye = [0.0, -4.0, 3.0]
//! look_at = [0.0, 0.0, 0.0]
//! up = [0.0, 0.0, 1.0]         # default +z
//! fov = 30.0                   # vertical, degrees (pinhole only)
//! resolution = [256, 256]
//! samples = 4                  # per pixel, default 1
//! projection = "pinhole"       # or "orthographic", with width = W (scene units across)
//! analyzer = { linear = 90.0 } # optional: a polarizer at DEG from image right toward up,
//! # or { retarder = { fast_axis = 45.0, retardance = 90.0 }, then = { linear = 0.0 } }
//!
//! [render]
//! wavelengths = 21             # a count over 380–780 nm, or a list [450, 550]
//! max_depth = 13
//! prune = 1e-4                 # 0: no pruning
//! seed = 0
//! coherence = "physical"       # or "incoherent" (every path adds as an intensity)
//! bundle = 0                   # o and e as one ray within N pixel footprints (incoherent only)
//! roulette = 0                 # Russian roulette below this fraction of the brightest light; 0: off
//! adaptive = 0                 # a pixel stops at this standard error (display units); 0: off
//! min_samples = 32             # samples before adaptive sampling's first check
//! edges = 0                    # only pixels differing from a neighbour by this take every sample; 0: off
//! max_samples = 0              # with edges: an edge pixel still moving goes on to this many; 0: off
//! units = "mm"                 # one scene unit: nm, um (µm), mm, cm or m
//!
//! [media.my_glass]             # custom media (optional)
//! n = 1.5                      # constant, or { sellmeier = … }, { cauchy = … }
//!
//! [media.my_crystal]
//! n_o = 1.6584
//! n_e = 1.4864
//! absorption_o = 0.3               # per mm: a number, "ruby-o" (a built-in spectrum),
//! absorption_e = { nm = [380, 780], per_mm = [0.5, 0.1] }   # or a table
//!
//! [media.my_biaxial]               # principal indices along crystal x, y, z
//! n_x = 1.6093                     # each a number or a dispersion model
//! n_y = 1.6116
//! n_z = 1.6194
//!
//! [[object]]
//! mesh = "gems/trichecker12.obj"   # .obj or .asc, relative to this file, or "builtin:NAME"
//! # or: cut = { name = "round-brilliant", table = 0.53, crown_angle = 34.5, pavilion_angle = 40.75 }
//! medium = "calcite"               # built-in, iso:N, uniaxial:NO:NE, or a [media] name
//! optic_axis = [0.0, 1.0, 1.0]     # object space; uniaxial crystals only (default +z)
//! # crystal_axes = { z = [0, 0, 1], x = [1, 0, 0] }   # biaxial only (x orthogonalized against z; without x: +x, or +y when z is within 45° of ±x)
//! transform = { scale = 1.0, rotate = [0.0, 0.0, 30.0], translate = [0.0, 0.0, 0.0] }
//!
//! [[light]]
//! corners = [[-2, -2, -1], [2, -2, -1], [2, 2, -1], [-2, 2, -1]]  # emits toward (c1−c0)×(c3−c0)
//! radiance = 1.0
//! texture = "textures/checker.png" # optional
//! polarization = "unpolarized"     # or { linear = [1, 0, 0] } or { calcite_plate = "o", axis = [..] }
//!
//! [[light]]                        # a light at infinity: direction instead of corners
//! direction = [0, 0, -1]           # where the light travels
//! angular_diameter = 0.53          # degrees, default 0 (collimated)
//! radiance = 1.0
//! polarization = { linear = [1, 0, 0] }   # axis projected normal to direction
//!
//! [[light]]                        # light from every direction (at most one; replaces [background])
//! environment = "sky.exr"          # a latitude–longitude image (row 0 the zenith +z), or "uniform"
//! radiance = 1.0                   # scale: radiance × map × D65
//!
//! [[light]]                        # a built-in rig relative to the camera (render::rig)
//! rig = "dome"                     # ring, dome, dome:DEG (head shadow DEG across) or spot
//! radiance = 1.0                   # scales the rig's radiances
//!
//! [background]
//! radiance = 0.0
//! ```

use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::marker::PhantomData;
use toml::Spanned;

pub type V3 = [f64; 3];

/// The name a fixed-length field has in scene files, for its errors.
pub trait FieldName {
    const NAME: &'static str;
}

macro_rules! field_names {
    ($($t:ident = $n:literal,)*) => {
        $(
            #[doc = concat!("`", $n, "` (for its errors).")]
            #[derive(Debug, Clone, Copy)]
            pub struct $t;
            impl FieldName for $t {
                const NAME: &'static str = $n;
            }
        )*
    };
}

field_names! {
    Eye = "camera.eye",
    LookAt = "camera.look_at",
    Up = "camera.up",
    Resolution = "camera.resolution",
    OpticAxis = "object.optic_axis",
    CrystalZ = "object.crystal_axes.z",
    CrystalX = "object.crystal_axes.x",
    Scale = "object.transform.scale",
    Rotate = "object.transform.rotate",
    Translate = "object.transform.translate",
    Corners = "light.corners",
    Direction = "light.direction",
    Corner = "light.corners (one corner)",
    Linear = "light.polarization.linear",
    PlateAxis = "light.polarization.calcite_plate.axis",
}

/// An array of exactly `N` values, for the field `F`. serde's own arrays
/// take the first `N` values of a longer TOML array and drop the rest
/// (`eye = [x, y, z, w]` read as `[x, y, z]`); this one refuses it,
/// naming the field and how many values were given.
#[derive(Debug, Clone)]
pub struct Exact<T, const N: usize, F>(pub [T; N], PhantomData<F>);

impl<'de, T: Deserialize<'de>, const N: usize, F: FieldName> Deserialize<'de> for Exact<T, N, F> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T, const N: usize, F>(PhantomData<(T, F)>);
        impl<'de, T: Deserialize<'de>, const N: usize, F: FieldName> Visitor<'de> for V<T, N, F> {
            type Value = Exact<T, N, F>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of exactly {N} values ({})", F::NAME)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut values = Vec::with_capacity(N);
                while values.len() < N {
                    match seq.next_element()? {
                        Some(v) => values.push(v),
                        None => break,
                    }
                }
                let mut len = values.len();
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    len += 1;
                }
                match values.try_into() {
                    Ok(a) if len == N => Ok(Exact(a, PhantomData)),
                    _ => Err(de::Error::custom(format!(
                        "{}: {len} value(s) given, it takes exactly {N}",
                        F::NAME
                    ))),
                }
            }
        }
        d.deserialize_seq(V(PhantomData))
    }
}

/// `deserialize_with` for `[T; N]` fields: exactly `N` values.
fn exact<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize, F: FieldName>(
    d: D,
) -> Result<[T; N], D::Error> {
    Exact::<T, N, F>::deserialize(d).map(|e| e.0)
}

/// `deserialize_with` for `Option<[T; N]>` fields.
fn opt_exact<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize, F: FieldName>(
    d: D,
) -> Result<Option<[T; N]>, D::Error> {
    Option::<Exact<T, N, F>>::deserialize(d).map(|e| e.map(|e| e.0))
}

/// `deserialize_with` for `Spanned<[T; N]>` fields.
fn spanned<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize, F: FieldName>(
    d: D,
) -> Result<Spanned<[T; N]>, D::Error> {
    let s = Spanned::<Exact<T, N, F>>::deserialize(d)?;
    Ok(Spanned::new(s.span(), s.into_inner().0))
}

/// `deserialize_with` for `Option<Spanned<[T; N]>>` fields.
fn opt_spanned<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize, F: FieldName>(
    d: D,
) -> Result<Option<Spanned<[T; N]>>, D::Error> {
    let s = Option::<Spanned<Exact<T, N, F>>>::deserialize(d)?;
    Ok(s.map(|s| Spanned::new(s.span(), s.into_inner().0)))
}

/// `deserialize_with` for a light's four corners of three coordinates
/// (a light at infinity has none).
fn corners<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Spanned<[V3; 4]>>, D::Error> {
    let s = Option::<Spanned<Exact<Exact<f64, 3, Corner>, 4, Corners>>>::deserialize(d)?;
    Ok(s.map(|s| {
        let span = s.span();
        Spanned::new(span, s.into_inner().0.map(|c| c.0))
    }))
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: Spanned<CameraDef>,
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
    #[serde(deserialize_with = "spanned::<_, _, 3, Eye>")]
    pub eye: Spanned<V3>,
    #[serde(deserialize_with = "spanned::<_, _, 3, LookAt>")]
    pub look_at: Spanned<V3>,
    #[serde(default = "default_up", deserialize_with = "spanned::<_, _, 3, Up>")]
    pub up: Spanned<V3>,
    /// Vertical field of view, degrees (required for a pinhole camera,
    /// unused by an orthographic one).
    pub fov: Option<Spanned<f64>>,
    #[serde(deserialize_with = "spanned::<_, _, 2, Resolution>")]
    pub resolution: Spanned<[u32; 2]>,
    #[serde(default = "default_samples")]
    pub samples: Spanned<u32>,
    /// `pinhole` (default) or `orthographic`.
    pub projection: Option<Spanned<String>>,
    /// Scene units across the image of an orthographic camera.
    pub width: Option<Spanned<f64>>,
    /// Optical elements in front of the film, the first one the light
    /// meets first.
    pub analyzer: Option<Spanned<AnalyzerDef>>,
    /// `jittered` (default: low-discrepancy positions over each pixel) or
    /// `center` (every sample through the pixel's centre).
    pub sampling: Option<Spanned<String>>,
}

/// One element of a camera's analyzer: exactly one of `linear` (a sheet
/// polarizer, its transmission axis at DEG from image right toward image
/// up) and `retarder`, then optionally the next element the light meets.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct AnalyzerDef {
    pub linear: Option<Spanned<f64>>,
    pub retarder: Option<Spanned<RetarderDef>>,
    pub then: Option<Box<Spanned<AnalyzerDef>>>,
}

/// A waveplate: its fast axis at DEG from image right toward image up,
/// its retardance in degrees (90: a quarter-wave plate).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct RetarderDef {
    pub fast_axis: Spanned<f64>,
    pub retardance: Spanned<f64>,
}

/// `wavelengths = 21` (a count over 380–780 nm) or a list in nm; at most
/// [`crate::render::settings::MAX_WAVELENGTHS`] either way.
#[derive(Debug, Clone)]
pub enum WavelengthsDef {
    Count(u64),
    List(Vec<f64>),
}

impl<'de> Deserialize<'de> for WavelengthsDef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = WavelengthsDef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(
                    f,
                    "a count of wavelengths (21) or a list of wavelengths in nm ([450, 550, 650])"
                )
            }
            fn visit_i64<E: de::Error>(self, n: i64) -> Result<Self::Value, E> {
                if n < 0 {
                    return Err(E::custom(format!(
                        "{n}: a count of wavelengths is at least 1"
                    )));
                }
                self.visit_u64(n as u64)
            }
            fn visit_u64<E: de::Error>(self, n: u64) -> Result<Self::Value, E> {
                Ok(WavelengthsDef::Count(n))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut list = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    list.push(v);
                }
                Ok(WavelengthsDef::List(list))
            }
        }
        d.deserialize_any(V)
    }
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
    /// `all` or `hero:K`, either optionally followed by `/N`.
    pub spectral: Option<Spanned<String>>,
    /// `true`/`false`, or `"on"`, `"off"`, `"bands:K"` (checked in
    /// `Scene::parse`, which names what it takes).
    pub dispersion: Option<Spanned<toml::Value>>,
    /// `physical` or `incoherent` (render::approx::CoherenceModel).
    pub coherence: Option<Spanned<String>>,
    /// o/e bundle tolerance, pixel footprints (render::bundle).
    pub bundle: Option<Spanned<f64>>,
    /// Russian roulette threshold (render::integrator; 0: off).
    pub roulette: Option<Spanned<f64>>,
    /// Adaptive sampling's noise target (render::adaptive; 0: off).
    pub adaptive: Option<Spanned<f64>>,
    /// Samples before adaptive sampling's first check.
    pub min_samples: Option<Spanned<u32>>,
    /// Edge-adaptive sampling's contrast threshold (render::edges; 0: off).
    pub edges: Option<Spanned<f64>>,
    /// Edge refinement's most samples per pixel (render::edges; 0: off).
    pub max_samples: Option<Spanned<u32>>,
    /// The length of one scene unit: `nm`, `um` (or `µm`), `mm`, `cm`, `m`.
    pub units: Option<Spanned<String>>,
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
    /// Biaxial principal indices along crystal x, y and z.
    pub n_x: Option<Spanned<DispersionDef>>,
    pub n_y: Option<Spanned<DispersionDef>>,
    pub n_z: Option<Spanned<DispersionDef>>,
    /// Absorption per mm for every wave (isotropic media, or a crystal
    /// that absorbs both waves alike).
    pub absorption: Option<Spanned<AbsorptionDef>>,
    /// A crystal's absorption per mm for a field normal to the optic axis
    /// (the ordinary wave) and along it.
    pub absorption_o: Option<Spanned<AbsorptionDef>>,
    pub absorption_e: Option<Spanned<AbsorptionDef>>,
}

/// An absorption coefficient: a number (per mm, every wavelength), a
/// built-in spectrum's name, or a table `{ nm = [...], per_mm = [...] }`.
#[derive(Debug, Clone)]
pub enum AbsorptionDef {
    Constant(f64),
    Named(String),
    Table(AbsorptionTable),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct AbsorptionTable {
    pub nm: Vec<f64>,
    pub per_mm: Vec<f64>,
}

impl<'de> Deserialize<'de> for AbsorptionDef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = AbsorptionDef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "an absorption coefficient per mm (0.2), a built-in spectrum's name \
                     (\"ruby-o\") or a table { nm = [380, 780], per_mm = [0.5, 0.1] }",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<AbsorptionDef, E> {
                Ok(AbsorptionDef::Constant(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<AbsorptionDef, E> {
                Ok(AbsorptionDef::Constant(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<AbsorptionDef, E> {
                Ok(AbsorptionDef::Constant(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<AbsorptionDef, E> {
                Ok(AbsorptionDef::Named(v.to_string()))
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<AbsorptionDef, A::Error> {
                AbsorptionTable::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(AbsorptionDef::Table)
            }
        }
        d.deserialize_any(V)
    }
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
    #[serde(default, deserialize_with = "opt_spanned::<_, _, 3, OpticAxis>")]
    pub optic_axis: Option<Spanned<V3>>,
    /// A biaxial crystal's axes in object space: `{ z = [..], x = [..] }`.
    pub crystal_axes: Option<Spanned<CrystalAxesDef>>,
    pub transform: Option<Spanned<TransformDef>>,
}

/// A biaxial crystal's z axis and x axis (x orthogonalized against z).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct CrystalAxesDef {
    #[serde(deserialize_with = "exact::<_, _, 3, CrystalZ>")]
    pub z: V3,
    /// Crystal x; absent: `optics::medium::default_crystal_x(z)`.
    #[serde(default, deserialize_with = "opt_exact::<_, _, 3, CrystalX>")]
    pub x: Option<V3>,
}

/// `scale = 2.0` or `scale = [x, y, z]`.
#[derive(Debug, Clone)]
pub enum ScaleDef {
    Uniform(f64),
    PerAxis(V3),
}

impl<'de> Deserialize<'de> for ScaleDef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = ScaleDef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or [x, y, z] (object.transform.scale)")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ScaleDef, E> {
                Ok(ScaleDef::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ScaleDef, E> {
                Ok(ScaleDef::Uniform(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ScaleDef, E> {
                Ok(ScaleDef::Uniform(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<ScaleDef, A::Error> {
                Exact::<f64, 3, Scale>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(|e| ScaleDef::PerAxis(e.0))
            }
        }
        d.deserialize_any(V)
    }
}

/// Applied as scale, then rotation about x, y, z (degrees, in that order),
/// then translation.
#[derive(Deserialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub struct TransformDef {
    pub scale: Option<ScaleDef>,
    #[serde(default, deserialize_with = "opt_exact::<_, _, 3, Rotate>")]
    pub rotate: Option<V3>,
    #[serde(default, deserialize_with = "opt_exact::<_, _, 3, Translate>")]
    pub translate: Option<V3>,
}

/// `polarization = "unpolarized"` or a filter table.
#[derive(Debug, Clone)]
pub enum PolarizationDef {
    Named(String),
    Filter(FilterDef),
}

impl<'de> Deserialize<'de> for PolarizationDef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = PolarizationDef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "\"unpolarized\", { linear = [x, y, z] } or { calcite_plate = { keep = \"o\", \
                     axis = [x, y, z] } } (light.polarization)",
                )
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<PolarizationDef, E> {
                Ok(PolarizationDef::Named(v.to_string()))
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<PolarizationDef, A::Error> {
                FilterDef::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(PolarizationDef::Filter)
            }
        }
        d.deserialize_any(V)
    }
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum FilterDef {
    /// An ideal linear polarizer whose transmission axis is this direction
    /// (projected into the light's plane).
    Linear(#[serde(deserialize_with = "exact::<_, _, 3, Linear>")] V3),
    /// A virtual calcite plate of this optic axis that keeps one wave.
    CalcitePlate(PlateDef),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct PlateDef {
    pub keep: String,
    #[serde(deserialize_with = "exact::<_, _, 3, PlateAxis>")]
    pub axis: V3,
}

fn default_radiance() -> Spanned<f64> {
    Spanned::new(0..0, 1.0)
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct LightDef {
    /// A rectangle's four corners; exactly one of `corners`, `direction`,
    /// `environment` and `rig` is given.
    #[serde(default, deserialize_with = "corners")]
    pub corners: Option<Spanned<[V3; 4]>>,
    /// A light at infinity: the direction its light travels.
    #[serde(default, deserialize_with = "opt_spanned::<_, _, 3, Direction>")]
    pub direction: Option<Spanned<V3>>,
    /// A light at infinity's full angular diameter, degrees (default 0:
    /// collimated).
    pub angular_diameter: Option<Spanned<f64>>,
    /// Light from every direction at infinity: `"uniform"`, or a
    /// latitude–longitude image (a path relative to the scene file, or
    /// `builtin:NAME`).
    pub environment: Option<Spanned<String>>,
    /// A built-in light rig relative to the camera: `"ring"`, `"dome"`,
    /// `"dome:DEG"` (a head shadow DEG degrees across) or `"spot"`
    /// (render::rig); `radiance` scales it.
    pub rig: Option<Spanned<String>>,
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
