//! Scenes: the file format ([`file`]), read and validated into the
//! renderer's input, [`crate::render::world::Scene`] (world-space meshes
//! with their materials, lights, camera, settings). Every error names the
//! file, the line and the field.

pub mod builtin;
pub mod file;
pub mod light;

use crate::geometry::Mesh;
use crate::material::{Absorption, Curve, Dispersion, Material};
use crate::optics::Jones;
use crate::render::approx::{BranchingArg, CoherenceModel, DispersionMode, PolarizationArg};
use crate::render::camera::{Camera, PixelSampling, Projection};
pub use crate::render::light::{
    DistantLight, Environment, EnvironmentMap, Light, Polarization, Texture,
};
use crate::render::settings::{
    resolve, Origin, Set, Settings, SettingsError, SettingsLayer, Wavelengths,
};
pub use crate::render::world::{
    Object, RenderSettings, Scene, DEFAULT_MAX_DEPTH, DEFAULT_PRUNE, DEFAULT_UNIT_NM,
    DEFAULT_WAVELENGTHS,
};
use file::{
    AbsorptionDef, AnalyzerDef, DispersionDef, DispersionModel, ScaleDef, SceneFile, TransformDef,
    WavelengthsDef,
};
use glam::{DAffine3, DMat3, DVec3};
use std::fmt;
use std::path::Path;
use toml::Spanned;

/// A scene error, with where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    pub file: String,
    pub line: Option<usize>,
    pub field: String,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: ", self.file)?,
            None => write!(f, "{}: ", self.file)?,
        }
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneError {}

/// A scene file's refused setting as a scene error: the same file, line,
/// field and message.
fn scene_error(e: SettingsError) -> SceneError {
    match e.origin {
        Origin::File { file, line, field } => SceneError {
            file,
            line,
            field,
            message: e.message,
        },
        // A scene file's layer has file origins only.
        other => SceneError {
            file: String::new(),
            line: None,
            field: String::new(),
            message: SettingsError { origin: other, ..e }.to_string(),
        },
    }
}

/// Turns byte offsets into line numbers for one file.
struct Locator<'a> {
    file: String,
    text: &'a str,
}

impl Locator<'_> {
    fn line(&self, span: std::ops::Range<usize>) -> Option<usize> {
        if span.start == 0 && span.end == 0 {
            return None; // a default value: it has no place in the file
        }
        Some(
            self.text[..span.start.min(self.text.len())]
                .matches('\n')
                .count()
                + 1,
        )
    }

    fn err<T>(
        &self,
        span: std::ops::Range<usize>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Result<T, SceneError> {
        Err(SceneError {
            file: self.file.clone(),
            line: self.line(span),
            field: field.into(),
            message: message.into(),
        })
    }
}

impl Scene {
    /// Loads a scene file; relative paths inside it are relative to its
    /// directory.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: file.clone(),
            line: None,
            field: String::new(),
            message: format!("cannot read: {e}"),
        })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Scene::parse(&text, &file, &base)
    }

    /// Parses scene text. `file` names it in errors; `base` resolves
    /// relative paths.
    pub fn parse(text: &str, file: &str, base: &Path) -> Result<Scene, SceneError> {
        let loc = Locator {
            file: file.to_string(),
            text,
        };
        let def: SceneFile = toml::from_str(text).map_err(|e| {
            let line = e.span().and_then(|s| loc.line(s));
            SceneError {
                file: file.to_string(),
                line,
                field: String::new(),
                message: e.message().trim().to_string(),
            }
        })?;

        // Camera.
        let c = def.camera.get_ref();
        let eye = vec3(&loc, &c.eye, "camera.eye")?;
        let look_at = vec3(&loc, &c.look_at, "camera.look_at")?;
        let up = vec3(&loc, &c.up, "camera.up")?;
        let orthographic = match &c.projection {
            None => false,
            Some(p) => match p.get_ref().trim() {
                "pinhole" => false,
                "orthographic" => true,
                other => {
                    return loc.err(
                        p.span(),
                        "camera.projection",
                        format!(
                            "unknown projection `{other}`: use \"pinhole\" (rays from the eye, \
                             `fov`) or \"orthographic\" (parallel rays, `width`)"
                        ),
                    )
                }
            },
        };
        let fov = match (&c.fov, orthographic) {
            (Some(f), _) => *f.get_ref(),
            // An orthographic camera has no field of view: any valid one
            // will do for the unused pinhole part.
            (None, true) => 90.0,
            // serde's own message, from before `fov` became optional.
            (None, false) => return loc.err(def.camera.span(), "", "missing field `fov`"),
        };
        let width = match (&c.width, orthographic) {
            (None, true) => {
                return loc.err(
                    def.camera.span(),
                    "camera.width",
                    "an orthographic camera needs `width`, the scene units across the image",
                )
            }
            (Some(w), false) => {
                return loc.err(
                    w.span(),
                    "camera.width",
                    "is for an orthographic camera (projection = \"orthographic\"); a pinhole \
                     camera's view is set by `fov`",
                )
            }
            (w, _) => w.as_ref(),
        };
        let analyzer = match &c.analyzer {
            None => None,
            Some(a) => Some(analyzer(&loc, a, "camera.analyzer")?),
        };

        // Render settings: the file's values as one layer, checked with
        // every other source's (render::settings).
        let r = &def.render;
        let origin = |span: std::ops::Range<usize>, field: &str| Origin::File {
            file: file.to_string(),
            line: loc.line(span),
            field: field.to_string(),
        };
        let mut layer = SettingsLayer {
            samples: Some(Set::new(
                *c.samples.get_ref(),
                origin(c.samples.span(), "camera.samples"),
            )),
            resolution: Some(Set::new(
                (c.resolution.get_ref()[0], c.resolution.get_ref()[1]),
                origin(c.resolution.span(), "camera.resolution"),
            )),
            wavelengths: r.wavelengths.as_ref().map(|s| {
                Set::new(
                    match s.get_ref() {
                        WavelengthsDef::Count(n) => Wavelengths::Count(*n),
                        WavelengthsDef::List(list) => Wavelengths::List(list.clone()),
                    },
                    origin(s.span(), "render.wavelengths"),
                )
            }),
            max_depth: r
                .max_depth
                .as_ref()
                .map(|d| Set::new(*d.get_ref(), origin(d.span(), "render.max_depth"))),
            prune: r
                .prune
                .as_ref()
                .map(|p| Set::new(*p.get_ref(), origin(p.span(), "render.prune"))),
            seed: r.seed.map(|v| Set::new(v, origin(0..0, "render.seed"))),
            bundle: r
                .bundle
                .as_ref()
                .map(|b| Set::new(*b.get_ref(), origin(b.span(), "render.bundle"))),
            roulette: r
                .roulette
                .as_ref()
                .map(|v| Set::new(*v.get_ref(), origin(v.span(), "render.roulette"))),
            adaptive: r
                .adaptive
                .as_ref()
                .map(|a| Set::new(*a.get_ref(), origin(a.span(), "render.adaptive"))),
            min_samples: r
                .min_samples
                .as_ref()
                .map(|m| Set::new(*m.get_ref(), origin(m.span(), "render.min_samples"))),
            edges: r
                .edges
                .as_ref()
                .map(|e| Set::new(*e.get_ref(), origin(e.span(), "render.edges"))),
            max_samples: r
                .max_samples
                .as_ref()
                .map(|m| Set::new(*m.get_ref(), origin(m.span(), "render.max_samples"))),
            ..SettingsLayer::default()
        };
        if let Some(b) = &r.branching {
            let v = b
                .get_ref()
                .parse::<BranchingArg>()
                .or_else(|e| loc.err(b.span(), "render.branching", e))?
                .0;
            layer.branching = Some(Set::new(v, origin(b.span(), "render.branching")));
        }
        if let Some(b) = &r.polarization {
            let v = b
                .get_ref()
                .parse::<PolarizationArg>()
                .or_else(|e| loc.err(b.span(), "render.polarization", e))?
                .0;
            layer.polarization = Some(Set::new(v, origin(b.span(), "render.polarization")));
        }
        if let Some(b) = &r.coherence {
            let v = b
                .get_ref()
                .parse::<CoherenceModel>()
                .or_else(|e| loc.err(b.span(), "render.coherence", e))?;
            layer.coherence = Some(Set::new(v, origin(b.span(), "render.coherence")));
        }
        let unit_nm = match &r.units {
            None => DEFAULT_UNIT_NM,
            Some(u) => unit_nm(u.get_ref()).map_or_else(
                || {
                    loc.err(
                        u.span(),
                        "render.units",
                        format!(
                            "unknown unit `{}`: one scene unit is nm, um (or µm), mm, cm or m",
                            u.get_ref()
                        ),
                    )
                },
                Ok,
            )?,
        };
        if let Some(b) = &r.spectral {
            let v = b
                .get_ref()
                .parse()
                .or_else(|e: String| loc.err(b.span(), "render.spectral", e))?;
            layer.spectral = Some(Set::new(v, origin(b.span(), "render.spectral")));
        }
        if let Some(d) = &r.dispersion {
            let v = match d.get_ref() {
                toml::Value::Boolean(true) => DispersionMode::On,
                toml::Value::Boolean(false) => DispersionMode::Off,
                toml::Value::String(t) => t
                    .parse()
                    .or_else(|e: String| loc.err(d.span(), "render.dispersion", e))?,
                other => loc.err(
                    d.span(),
                    "render.dispersion",
                    format!(
                        "`{other}`: give true, false, \"on\", \"off\" or \"bands:K\" \
                         (K ≥ 1 bands of wavelength)"
                    ),
                )?,
            };
            layer.dispersion = Some(Set::new(v, origin(d.span(), "render.dispersion")));
        }
        let Settings {
            samples,
            resolution: (w, h),
            render: settings,
        } = resolve(Settings::defaults(), &[&layer]).map_err(scene_error)?;
        let sampling = match &c.sampling {
            None => PixelSampling::Jittered,
            Some(v) => match v.get_ref().as_str() {
                "jittered" => PixelSampling::Jittered,
                "center" | "centre" => PixelSampling::Center,
                other => {
                    return loc.err(
                        v.span(),
                        "camera.sampling",
                        format!(
                            "`{other}`: \"jittered\" (positions spread over each pixel, the \
                             default) or \"center\" (every sample through the pixel's centre)"
                        ),
                    )
                }
            },
        };
        let mut camera = Camera::new(eye, look_at, up, fov, w, h)
            .or_else(|m| loc.err(c.eye.span(), "camera", m))?
            .with_analyzer(analyzer)
            .with_sampling(sampling);
        if let Some(width) = width {
            camera = camera
                .orthographic(*width.get_ref())
                .or_else(|m| loc.err(width.span(), "camera.width", m))?;
        }

        // Objects.
        let mut objects = Vec::new();
        let mut places = Vec::new();
        for (i, o) in def.objects.iter().enumerate() {
            let field = |f: &str| format!("object[{i}].{f}");
            let o_span = o.span();
            let o = o.get_ref();
            let material = resolve_material(&loc, &def, &o.medium, &field("medium"))?;
            let transform = match &o.transform {
                None => DAffine3::IDENTITY,
                Some(t) => transform(&loc, t, &field("transform"))?,
            };
            let material = match (&o.optic_axis, material.is_uniaxial()) {
                (Some(a), false) => {
                    return loc.err(
                        a.span(),
                        field("optic_axis"),
                        if material.is_biaxial() {
                            format!(
                                "medium `{}` is biaxial: it has two optic axes; orient it with \
                                 crystal_axes = {{ z = [..], x = [..] }}",
                                o.medium.get_ref()
                            )
                        } else {
                            format!(
                                "medium `{}` is isotropic: it has no optic axis",
                                o.medium.get_ref()
                            )
                        },
                    );
                }
                (axis, true) => {
                    let object_axis = match axis {
                        Some(a) => vec3(&loc, a, &field("optic_axis"))?,
                        None => DVec3::Z,
                    };
                    let world = transform.matrix3 * object_axis;
                    material.with_axis(world).or_else(|m| {
                        loc.err(
                            axis.as_ref().map_or(o_span.clone(), |a| a.span()),
                            field("optic_axis"),
                            m,
                        )
                    })?
                }
                (None, false) => material,
            };
            let material = match (&o.crystal_axes, material.is_biaxial()) {
                (Some(a), false) => {
                    return loc.err(
                        a.span(),
                        field("crystal_axes"),
                        format!(
                            "medium `{}` is not biaxial: crystal_axes belong to a biaxial \
                             medium (n_x, n_y, n_z); a uniaxial one takes optic_axis",
                            o.medium.get_ref()
                        ),
                    );
                }
                (axes, true) => {
                    let (z, x) = match axes {
                        Some(a) => {
                            let d = a.get_ref();
                            let z = finite3(d.z);
                            // No x: the default orthogonal to z, chosen in
                            // the object's frame.
                            let x = match d.x {
                                Some(x) => finite3(x),
                                None => z.map(crate::optics::medium::default_crystal_x),
                            };
                            match (z, x) {
                                (Some(z), Some(x)) => (z, x),
                                _ => {
                                    return loc.err(
                                        a.span(),
                                        field("crystal_axes"),
                                        "components must be finite numbers",
                                    )
                                }
                            }
                        }
                        None => (DVec3::Z, DVec3::X),
                    };
                    // Both axes go to world space by the object's linear map; x is
                    // orthogonalized against z there (a shear or non-uniform scale
                    // keeps z and moves x only by its part along z).
                    let m = transform.matrix3;
                    material.with_crystal_axes(m * z, m * x).or_else(|e| {
                        loc.err(
                            axes.as_ref().map_or(o_span.clone(), |a| a.span()),
                            field("crystal_axes"),
                            e,
                        )
                    })?
                }
                (None, false) => material,
            };
            let (mesh, name) = match (&o.mesh, &o.cut) {
                (Some(m), None) => (load_mesh(&loc, m, base, &field("mesh"))?, m.get_ref().clone()),
                (None, Some(c)) => {
                    let mesh = crate::geometry::cuts::mesh_from_spec(c.get_ref()).or_else(|e| loc.err(c.span(), field("cut"), e))?;
                    let name = c.get_ref().get("name").and_then(|v| v.as_str()).unwrap_or("cut").to_string();
                    (mesh, name)
                }
                _ => return loc.err(o_span.clone(), format!("object[{i}]"), "give exactly one of `mesh` (a file or builtin:NAME) and `cut` (a standard cut)"),
            };
            let mesh = mesh.transformed(&transform);
            places.push(ObjectPlace {
                span: o_span.clone(),
                transform: o.transform.as_ref().map(|t| {
                    let d = t.get_ref();
                    (t.span(), d.scale.is_some(), d.translate.is_some())
                }),
                source: match (&o.mesh, &o.cut) {
                    (Some(m), _) => (m.span(), field("mesh")),
                    (_, Some(c)) => (c.span(), field("cut")),
                    _ => (o_span.clone(), format!("object[{i}]")),
                },
            });
            objects.push(Object {
                name,
                mesh,
                material,
            });
        }

        let width_span = width.map(|w| w.span());
        check_whole_scene(&loc, &objects, &places, &camera, c.eye.span(), width_span)?;

        // Lights.
        let mut lights = Vec::new();
        let mut distant_lights = Vec::new();
        // The environment, with its light's index and where its
        // `environment` key is.
        let mut environment: Option<(usize, std::ops::Range<usize>, Environment)> = None;
        for (i, l) in def.lights.iter().enumerate() {
            if let (Some((first, first_span, _)), Some(e)) =
                (&environment, &l.get_ref().environment)
            {
                return loc.err(
                    e.span(),
                    format!("light[{i}].environment"),
                    format!(
                        "a scene has at most one environment: light[{first}] (line {}) is one \
                         already",
                        loc.line(first_span.clone())
                            .map_or(String::from("?"), |l| l.to_string())
                    ),
                );
            }
            match light::resolve(&loc_fns(&loc), l, base, i, &camera)? {
                light::AnyLight::Area(l) => lights.push(l),
                light::AnyLight::Distant(l) => distant_lights.push(l),
                light::AnyLight::Rig(rig) => distant_lights.extend(rig),
                light::AnyLight::Environment(e) => {
                    let span = l
                        .get_ref()
                        .environment
                        .as_ref()
                        .map_or(l.span(), |e| e.span());
                    environment = Some((i, span, e));
                }
            }
        }
        let background = match &def.background {
            None => 0.0,
            Some(b) => {
                let v = *b.radiance.get_ref();
                if !(v.is_finite() && v >= 0.0) {
                    return loc.err(
                        b.radiance.span(),
                        "background.radiance",
                        "must be a finite number ≥ 0",
                    );
                }
                if let Some((i, span, _)) = environment.as_ref().filter(|_| v > 0.0) {
                    return loc.err(
                        b.radiance.span(),
                        "background.radiance",
                        format!(
                            "the scene has an environment (light[{i}], line {}), which replaces \
                             the background where rays leave the scene: give one",
                            loc.line(span.clone())
                                .map_or(String::from("?"), |l| l.to_string())
                        ),
                    );
                }
                v
            }
        };
        let environment = environment.map(|(_, _, e)| e);
        if lights.is_empty()
            && distant_lights.is_empty()
            && environment.is_none()
            && background == 0.0
        {
            return Err(SceneError {
                file: file.to_string(),
                line: None,
                field: String::new(),
                message: "the scene has no light and no background: the image would be black"
                    .into(),
            });
        }
        Ok(Scene {
            camera,
            samples,
            settings,
            objects,
            lights,
            distant_lights,
            environment,
            unit_nm,
            background,
            source: text.to_string(),
        })
    }
}

/// Where an object is defined, for errors found once the whole scene is
/// known: its table, its transform (span, has a scale, has a translation)
/// and its mesh or cut (span and field name).
struct ObjectPlace {
    span: std::ops::Range<usize>,
    transform: Option<(std::ops::Range<usize>, bool, bool)>,
    source: (std::ops::Range<usize>, String),
}

/// Largest coordinate, in scene units, of any object or the camera.
/// Embree traces in f32 and aborts on coordinates beyond 1.8e18; its
/// triangle test multiplies three coordinates, and the Rust BVH's test
/// likewise (a gem scaled by 1e-20 made the Rust BVH loop for minutes).
/// A conservative range, not a measured edge: tests/accel/accel_scale.rs checks
/// the Rust BVH from 1e-5 to 1e5 and 1000 sizes away.
pub const MAX_COORDINATE: f64 = 1e6;

/// Smallest size (largest side of its bounding box) of an object, in scene
/// units; with [`MAX_COORDINATE`] nine decades of scale.
pub const MIN_OBJECT_SIZE: f64 = 1e-3;

/// Smallest size of an object relative to the scene's extent (the largest
/// coordinate of any object). f32 coordinates are good to a few 1e-7 of
/// the scene's extent, and secondary rays start 1e-5 of the reach of the
/// object they leave (its size or its distance from the origin) from its
/// surface: an object smaller than 1e-3 of the extent, far from the
/// origin, would be stepped over by 1 % of its size or more.
pub const MIN_RELATIVE_SIZE: f64 = 1e-3;

/// Objects closer than this fraction of the scene's extent count as
/// touching (the offset secondary rays start at).
pub const TOUCH_FRACTION: f64 = 1e-5;

/// Checks of the whole scene once every object is placed: coordinates and
/// sizes in the range f32 tracing handles, the camera outside every object
/// (its eye, and an orthographic camera's four image-plane corners, where
/// its rays start; `width_span` is where its `width` is), no two objects
/// overlapping, touching or nested, no mesh intersecting itself.
fn check_whole_scene(
    loc: &Locator<'_>,
    objects: &[Object],
    places: &[ObjectPlace],
    camera: &Camera,
    eye_span: std::ops::Range<usize>,
    width_span: Option<std::ops::Range<usize>>,
) -> Result<(), SceneError> {
    let eye = camera.eye;
    use crate::geometry::overlap;
    let bounds: Vec<(DVec3, DVec3)> = objects.iter().map(|o| o.mesh.bounds()).collect();
    let reach = |(lo, hi): (DVec3, DVec3)| lo.abs().max(hi.abs()).max_element();
    let extent = bounds.iter().map(|&b| reach(b)).fold(0.0, f64::max);
    let line_of = |i: usize| {
        loc.line(places[i].span.clone())
            .map_or(String::from("?"), |l| l.to_string())
    };
    let describe = |i: usize| {
        format!(
            "object[{i}] ({}, {}:{})",
            objects[i].name,
            loc.file,
            line_of(i)
        )
    };
    // Field naming what made object i too large, too small or too far.
    let blame = |i: usize, position: bool| -> (std::ops::Range<usize>, String) {
        let p = &places[i];
        match p.transform {
            Some((ref span, _, true)) if position => {
                (span.clone(), format!("object[{i}].transform.translate"))
            }
            Some((ref span, true, _)) => (span.clone(), format!("object[{i}].transform.scale")),
            _ => p.source.clone(),
        }
    };
    for (i, &(lo, hi)) in bounds.iter().enumerate() {
        let size = (hi - lo).max_element();
        let r = reach((lo, hi));
        if !(r <= MAX_COORDINATE) {
            let (span, field) = blame(i, size <= MAX_COORDINATE);
            return loc.err(
                span,
                field,
                format!(
                    "{} reaches {r:.3e} from the origin: every coordinate must be within \
                     {MAX_COORDINATE:e} units (spar traces in single precision)",
                    objects[i].name
                ),
            );
        }
        if !(size >= MIN_OBJECT_SIZE) {
            let (span, field) = blame(i, false);
            return loc.err(
                span,
                field,
                format!(
                    "{} is {size:.3e} units across: objects must be at least \
                     {MIN_OBJECT_SIZE:e} units (scale the whole scene up)",
                    objects[i].name
                ),
            );
        }
        if !(size >= MIN_RELATIVE_SIZE * extent) {
            let (span, field) = blame(i, true);
            return loc.err(
                span,
                field,
                format!(
                    "{} is {size:.3e} units across, less than {MIN_RELATIVE_SIZE:e} of the \
                     scene's extent {extent:.3e}: single-precision tracing cannot resolve it \
                     (move the scene nearer the origin or the objects nearer each other)",
                    objects[i].name
                ),
            );
        }
    }
    if !(eye.abs().max_element() <= MAX_COORDINATE) {
        return loc.err(
            eye_span,
            "camera.eye",
            format!(
                "{eye} is beyond {MAX_COORDINATE:e} units from the origin (spar traces in \
                 single precision): bring the camera nearer and narrow its field of view"
            ),
        );
    }
    for (i, o) in objects.iter().enumerate() {
        if overlap::point_inside(&o.mesh, eye) {
            return loc.err(
                eye_span,
                "camera.eye",
                format!(
                    "the camera is inside {} (or on its surface): every camera ray would \
                     start inside the stone",
                    describe(i)
                ),
            );
        }
    }
    if let (Projection::Orthographic { .. }, Some(width_span)) = (camera.projection, width_span) {
        let (w, h) = (camera.width as f64, camera.height as f64);
        for (fx, fy) in [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)] {
            let corner = camera.ray(fx, fy).0;
            if !(corner.abs().max_element() <= MAX_COORDINATE) {
                return loc.err(
                    width_span,
                    "camera.width",
                    format!(
                        "the image plane's corner {corner} is beyond {MAX_COORDINATE:e} units \
                         from the origin (spar traces in single precision): narrow the image"
                    ),
                );
            }
            for (i, o) in objects.iter().enumerate() {
                if overlap::point_inside(&o.mesh, corner) {
                    return loc.err(
                        width_span,
                        "camera.width",
                        format!(
                            "the orthographic camera's image-plane corner {corner} is inside {} \
                             (or on its surface): camera rays from there would start inside the \
                             stone (move the eye back or narrow the image)",
                            describe(i)
                        ),
                    );
                }
            }
        }
    }
    let tol = TOUCH_FRACTION * extent;
    for i in 0..objects.len() {
        for j in i + 1..objects.len() {
            let Some(meeting) = overlap::meshes_meet(&objects[i].mesh, &objects[j].mesh, tol)
            else {
                continue;
            };
            let how = match meeting {
                overlap::Meeting::Surfaces(..) => format!(
                    "overlaps or touches (comes within {tol:.1e} units of) {}",
                    describe(j)
                ),
                overlap::Meeting::FirstInside => format!("lies inside {}", describe(j)),
                overlap::Meeting::SecondInside => format!("contains {}", describe(j)),
            };
            return loc.err(
                places[i].span.clone(),
                format!("object[{i}]"),
                format!(
                    "{} {how}: objects must be apart (light inside one cannot enter \
                     another)",
                    describe(i)
                ),
            );
        }
    }
    for (i, o) in objects.iter().enumerate() {
        if let Some((a, b)) = overlap::self_intersection(&o.mesh) {
            let (span, field) = places[i].source.clone();
            return loc.err(
                span,
                field,
                format!(
                    "{}: the mesh intersects itself (triangles {a} and {b} cross): it does \
                     not bound a solid",
                    describe(i)
                ),
            );
        }
    }
    Ok(())
}

/// Error constructor handed to submodules.
pub(crate) struct LocFns<'a> {
    loc: &'a Locator<'a>,
}

impl LocFns<'_> {
    pub(crate) fn err<T>(
        &self,
        span: std::ops::Range<usize>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Result<T, SceneError> {
        self.loc.err(span, field, message)
    }
}

fn loc_fns<'a>(loc: &'a Locator<'a>) -> LocFns<'a> {
    LocFns { loc }
}

/// Nanometres in one scene unit named `name` (`[render] units`).
pub fn unit_nm(name: &str) -> Option<f64> {
    Some(match name.trim() {
        "nm" => 1.0,
        "um" | "µm" | "μm" => 1e3,
        "mm" => 1e6,
        "cm" => 1e7,
        "m" => 1e9,
        _ => return None,
    })
}

/// A camera's analyzer as one Jones matrix in the film's frame (x image
/// right, y image up): each element of the chain in the order the light
/// meets it, so `{ retarder = R, then = { linear = P } }` is `P · R`.
fn analyzer(loc: &Locator<'_>, a: &Spanned<AnalyzerDef>, field: &str) -> Result<Jones, SceneError> {
    let d = a.get_ref();
    let angle = |v: &Spanned<f64>, f: &str| -> Result<f64, SceneError> {
        let deg = *v.get_ref();
        if !deg.is_finite() {
            return loc.err(
                v.span(),
                format!("{field}.{f}"),
                format!("{deg}: must be a finite number of degrees"),
            );
        }
        Ok(deg.to_radians())
    };
    let element = match (&d.linear, &d.retarder) {
        (Some(theta), None) => Jones::linear_polarizer(angle(theta, "linear")?),
        (None, Some(r)) => {
            let rd = r.get_ref();
            Jones::retarder(
                angle(&rd.fast_axis, "retarder.fast_axis")?,
                angle(&rd.retardance, "retarder.retardance")?,
            )
        }
        _ => {
            return loc.err(
                a.span(),
                field,
                "give exactly one of `linear = DEG` (a polarizer, its axis at DEG from image \
                 right toward image up) and `retarder = { fast_axis = DEG, retardance = DEG }`, \
                 then optionally `then = { … }`, the next element the light meets",
            )
        }
    };
    match &d.then {
        None => Ok(element),
        Some(next) => Ok(analyzer(loc, next, &format!("{field}.then"))?.product(&element)),
    }
}

pub(crate) fn finite3(v: [f64; 3]) -> Option<DVec3> {
    let v = DVec3::from_array(v);
    v.is_finite().then_some(v)
}

fn vec3(loc: &Locator<'_>, v: &Spanned<[f64; 3]>, field: &str) -> Result<DVec3, SceneError> {
    finite3(*v.get_ref()).map_or_else(
        || loc.err(v.span(), field, "components must be finite numbers"),
        Ok,
    )
}

fn dispersion(d: &DispersionDef) -> Dispersion {
    match d {
        DispersionDef::Constant(n) => Dispersion::Constant(*n),
        DispersionDef::Model(DispersionModel::Sellmeier { a, b, c }) => Dispersion::sellmeier(
            *a,
            &b.iter().copied().zip(c.iter().copied()).collect::<Vec<_>>(),
        ),
        DispersionDef::Model(DispersionModel::SellmeierPoles { a, b, poles }) => {
            Dispersion::sellmeier_poles(
                *a,
                &b.iter()
                    .copied()
                    .zip(poles.iter().copied())
                    .collect::<Vec<_>>(),
            )
        }
        DispersionDef::Model(DispersionModel::Cauchy { a, b, c }) => Dispersion::Cauchy {
            a: *a,
            b: *b,
            c: *c,
        },
    }
}

fn check_terms(
    loc: &Locator<'_>,
    d: &Spanned<DispersionDef>,
    field: &str,
) -> Result<(), SceneError> {
    let lens = match d.get_ref() {
        DispersionDef::Model(DispersionModel::Sellmeier { b, c, .. }) => {
            Some((b.len(), c.len(), "c"))
        }
        DispersionDef::Model(DispersionModel::SellmeierPoles { b, poles, .. }) => {
            Some((b.len(), poles.len(), "poles"))
        }
        _ => None,
    };
    match lens {
        Some((nb, nc, what)) if nb != nc => loc.err(
            d.span(),
            field,
            format!("b has {nb} terms but {what} has {nc}"),
        ),
        _ => Ok(()),
    }
}

fn resolve_material(
    loc: &Locator<'_>,
    def: &SceneFile,
    name: &Spanned<String>,
    field: &str,
) -> Result<Material, SceneError> {
    let key = name.get_ref();
    if let Some(m) = def.media.get(key) {
        let md = m.get_ref();
        let mfield = format!("media.{key}");
        let biaxial = md.n_x.is_some() || md.n_y.is_some() || md.n_z.is_some();
        let material = match (&md.n, &md.n_o, &md.n_e) {
            (None, None, None) if biaxial => match (&md.n_x, &md.n_y, &md.n_z) {
                (Some(nx), Some(ny), Some(nz)) => {
                    check_terms(loc, nx, &format!("{mfield}.n_x"))?;
                    check_terms(loc, ny, &format!("{mfield}.n_y"))?;
                    check_terms(loc, nz, &format!("{mfield}.n_z"))?;
                    Material::biaxial(
                        key.clone(),
                        dispersion(nx.get_ref()),
                        dispersion(ny.get_ref()),
                        dispersion(nz.get_ref()),
                    )
                    .or_else(|e| loc.err(m.span(), mfield.clone(), e))
                }
                _ => loc.err(
                    m.span(),
                    mfield.clone(),
                    "a biaxial medium gives all three of `n_x`, `n_y` and `n_z`",
                ),
            },
            _ if biaxial => loc.err(
                m.span(),
                mfield.clone(),
                "a biaxial medium gives `n_x`, `n_y` and `n_z`, not `n`, `n_o` or `n_e`",
            ),
            (Some(n), None, None) => {
                check_terms(loc, n, &format!("{mfield}.n"))?;
                Material::isotropic(key.clone(), dispersion(n.get_ref()))
                    .or_else(|e| loc.err(n.span(), format!("{mfield}.n"), e))
            }
            (None, Some(no), Some(ne)) => {
                check_terms(loc, no, &format!("{mfield}.n_o"))?;
                check_terms(loc, ne, &format!("{mfield}.n_e"))?;
                Material::uniaxial(
                    key.clone(),
                    dispersion(no.get_ref()),
                    dispersion(ne.get_ref()),
                )
                .or_else(|e| loc.err(m.span(), mfield.clone(), e))
            }
            _ => loc.err(
                m.span(),
                mfield.clone(),
                "give either `n` (isotropic), both `n_o` and `n_e` (uniaxial), or `n_x`, \
                 `n_y` and `n_z` (biaxial)",
            ),
        }?;
        return with_absorption(loc, material, m, &mfield);
    }
    Material::parse(key).or_else(|e| {
        let custom = if def.media.is_empty() {
            String::new()
        } else {
            format!(
                " (media defined in this file: {})",
                def.media.keys().cloned().collect::<Vec<_>>().join(", ")
            )
        };
        loc.err(name.span(), field, format!("{e}{custom}"))
    })
}

/// One absorption key's curve (`field` names it in errors).
fn absorption_curve(
    loc: &Locator<'_>,
    d: &Spanned<AbsorptionDef>,
    field: &str,
) -> Result<Curve, SceneError> {
    let curve = match d.get_ref() {
        AbsorptionDef::Constant(a) => Curve::Constant(*a),
        AbsorptionDef::Table(t) => Curve::Table {
            nm: t.nm.clone(),
            per_mm: t.per_mm.clone(),
        },
        AbsorptionDef::Named(name) => {
            return crate::material::catalog::absorption_spectrum(name).map_or_else(
                || {
                    loc.err(
                        d.span(),
                        field,
                        format!(
                            "no built-in absorption spectrum `{name}`; built-in spectra: {}",
                            crate::material::catalog::SPECTRUM_NAMES.join(", ")
                        ),
                    )
                },
                Ok,
            )
        }
    };
    curve.validate().or_else(|e| loc.err(d.span(), field, e))?;
    Ok(curve)
}

/// A custom medium's material with the absorption its `absorption`, or
/// `absorption_o` and `absorption_e`, keys give (per mm).
fn with_absorption(
    loc: &Locator<'_>,
    material: Material,
    m: &Spanned<file::MediumDef>,
    mfield: &str,
) -> Result<Material, SceneError> {
    let md = m.get_ref();
    let curve = |d: &Spanned<AbsorptionDef>, key: &str| {
        absorption_curve(loc, d, &format!("{mfield}.{key}"))
    };
    let absorption = match (&md.absorption, &md.absorption_o, &md.absorption_e) {
        (None, None, None) => None,
        _ if material.is_biaxial() => {
            return loc.err(
                m.span(),
                mfield,
                "absorption in a biaxial medium is not modelled: biaxial media are lossless \
                 (docs/materials.md)",
            )
        }
        (Some(a), None, None) => Some(Absorption::isotropic(curve(a, "absorption")?)),
        (None, Some(o), Some(e)) if material.is_uniaxial() => Some(Absorption {
            o: curve(o, "absorption_o")?,
            e: curve(e, "absorption_e")?,
        }),
        (_, o, e) if !material.is_uniaxial() => {
            let span = o.as_ref().or(e.as_ref()).map_or(m.span(), |d| d.span());
            return loc.err(
                span,
                mfield,
                "an isotropic medium absorbs every wave alike: give `absorption` (per mm), \
                 not `absorption_o` or `absorption_e`",
            );
        }
        _ => {
            return loc.err(
                m.span(),
                mfield,
                "a crystal's absorption is either `absorption` (both waves alike) or both \
                 `absorption_o` (field normal to the optic axis) and `absorption_e` (field \
                 along it), per mm",
            )
        }
    };
    material
        .with_absorption(absorption)
        .or_else(|e| loc.err(m.span(), mfield, e))
}

fn transform(
    loc: &Locator<'_>,
    t: &Spanned<TransformDef>,
    field: &str,
) -> Result<DAffine3, SceneError> {
    let d = t.get_ref();
    let scale = match &d.scale {
        None => DVec3::ONE,
        Some(ScaleDef::Uniform(s)) => DVec3::splat(*s),
        Some(ScaleDef::PerAxis(s)) => DVec3::from_array(*s),
    };
    if !scale.is_finite() || scale.x == 0.0 || scale.y == 0.0 || scale.z == 0.0 {
        return loc.err(
            t.span(),
            format!("{field}.scale"),
            "must be finite and non-zero",
        );
    }
    let rot = d.rotate.unwrap_or([0.0; 3]);
    let translate = d.translate.unwrap_or([0.0; 3]);
    if !rot.iter().chain(translate.iter()).all(|v| v.is_finite()) {
        return loc.err(t.span(), field, "rotate and translate must be finite");
    }
    let r = DMat3::from_rotation_z(rot[2].to_radians())
        * DMat3::from_rotation_y(rot[1].to_radians())
        * DMat3::from_rotation_x(rot[0].to_radians());
    Ok(DAffine3::from_mat3_translation(
        r * DMat3::from_diagonal(scale),
        DVec3::from_array(translate),
    ))
}

/// Loads and validates a mesh file (OBJ or GemCAD .asc) or a built-in mesh:
/// it must be closed and consistently oriented; concave or slightly warped
/// meshes load (their warnings are printed).
fn load_mesh(
    loc: &Locator<'_>,
    mesh: &Spanned<String>,
    base: &Path,
    field: &str,
) -> Result<Mesh, SceneError> {
    use crate::geometry::validate::{load_mesh as load_file, mesh_from_bytes_as, MeshFormat};
    let name = mesh.get_ref();
    let loaded = if let Some(builtin) = name.strip_prefix("builtin:") {
        let text = builtin::mesh(builtin).map_or_else(
            || {
                loc.err(
                    mesh.span(),
                    field,
                    format!(
                        "no built-in mesh `{builtin}`; built-in meshes: {}",
                        builtin::MESH_NAMES.join(", ")
                    ),
                )
            },
            Ok,
        )?;
        mesh_from_bytes_as(text.as_bytes(), name, MeshFormat::Obj)
    } else {
        load_file(&base.join(name))
    };
    let loaded = loaded.or_else(|e| loc.err(mesh.span(), field, e))?;
    for w in &loaded.warnings {
        eprintln!("spar: warning: {w}");
    }
    Ok(loaded.mesh)
}
