//! `[[light]]` tables: validated into the renderer's rectangular area
//! lights, lights at infinity and environments
//! ([`crate::render::light`]), textures and environment maps loaded from
//! image files or built in.

use super::file::{FilterDef, LightDef, PolarizationDef, V3};
use super::{finite3, LocFns, SceneError};
use crate::render::camera::Camera;
use crate::render::light::{
    DistantLight, Environment, EnvironmentMap, Light, PlateWave, Polarization, Texture,
};
use crate::render::rig::{LightRig, RIG_NAMES};
use glam::DVec3;
use std::path::Path;
use toml::Spanned;

/// A validated `[[light]]` table: a rectangle, a light at infinity or
/// an environment.
#[derive(Debug)]
pub(crate) enum AnyLight {
    Area(Light),
    Distant(DistantLight),
    Environment(Environment),
    /// A built-in rig's lights at infinity (render::rig).
    Rig(Vec<DistantLight>),
}

/// Validates a `[[light]]` table: exactly one of `corners` (a rectangle),
/// `direction` (a light at infinity), `environment` (light from every
/// direction) and `rig` (a built-in rig relative to `camera`).
pub(crate) fn resolve(
    loc: &LocFns<'_>,
    l: &Spanned<LightDef>,
    base: &Path,
    index: usize,
    camera: &Camera,
) -> Result<AnyLight, SceneError> {
    let def = l.get_ref();
    match (&def.corners, &def.direction, &def.environment, &def.rig) {
        (Some(corners), None, None, None) => {
            area(loc, def, corners, base, index).map(AnyLight::Area)
        }
        (None, Some(direction), None, None) => {
            distant(loc, def, direction, index).map(AnyLight::Distant)
        }
        (None, None, Some(env), None) => {
            environment(loc, def, env, base, index).map(AnyLight::Environment)
        }
        (None, None, None, Some(r)) => rig(loc, def, r, index, camera).map(AnyLight::Rig),
        (c, d, e, r) => {
            let given: Vec<&str> = [
                (c.is_some(), "`corners`"),
                (d.is_some(), "`direction`"),
                (e.is_some(), "`environment`"),
                (r.is_some(), "`rig`"),
            ]
            .into_iter()
            .filter_map(|(has, name)| has.then_some(name))
            .collect();
            loc.err(
                l.span(),
                format!("light[{index}]"),
                format!(
                    "give exactly one of `corners` (a rectangle), `direction` (a light at \
                     infinity, the direction its light travels), `environment` (light from \
                     every direction: \"uniform\" or a latitude–longitude image) and `rig` (a \
                     built-in rig: {}); this light has {}",
                    RIG_NAMES.join(", "),
                    match given.as_slice() {
                        [] => "none of them".to_string(),
                        [a, b] => format!("both {a} and {b}"),
                        [a, b, c] => format!("all three of {a}, {b} and {c}"),
                        _ => "all four".to_string(),
                    }
                ),
            )
        }
    }
}

/// A built-in rig (render::rig) for `camera`, its radiances scaled by
/// `radiance`; it takes no texture, polarization or angular diameter.
fn rig(
    loc: &LocFns<'_>,
    def: &LightDef,
    name: &Spanned<String>,
    index: usize,
    camera: &Camera,
) -> Result<Vec<DistantLight>, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    let rig: LightRig = name
        .get_ref()
        .parse()
        .or_else(|e| loc.err(name.span(), field("rig"), e))?;
    let refuse = |span: std::ops::Range<usize>, key: &str| {
        loc.err(
            span,
            field(key),
            format!(
                "a rig (`rig = \"{rig}\"`) has its own directions, sizes and polarization \
                 (unpolarized): it takes only `radiance`, a scale"
            ),
        )
    };
    if let Some(p) = &def.polarization {
        return refuse(p.span(), "polarization");
    }
    if let Some(t) = &def.texture {
        return refuse(t.span(), "texture");
    }
    if let Some(a) = &def.angular_diameter {
        return refuse(a.span(), "angular_diameter");
    }
    let scale = radiance(loc, def, index)?;
    Ok(rig.lights(camera, scale))
}

/// `radiance`: finite and ≥ 0.
fn radiance(loc: &LocFns<'_>, def: &LightDef, index: usize) -> Result<f64, SceneError> {
    let radiance = *def.radiance.get_ref();
    if !(radiance.is_finite() && radiance >= 0.0) {
        return loc.err(
            def.radiance.span(),
            format!("light[{index}].radiance"),
            "must be a finite number ≥ 0",
        );
    }
    Ok(radiance)
}

/// A rectangular area light.
fn area(
    loc: &LocFns<'_>,
    def: &LightDef,
    corners: &Spanned<[V3; 4]>,
    base: &Path,
    index: usize,
) -> Result<Light, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    if let Some(a) = &def.angular_diameter {
        return loc.err(
            a.span(),
            field("angular_diameter"),
            "is for a light at infinity (`direction`); a rectangle (`corners`) has its own size",
        );
    }
    let c: Vec<DVec3> = match corners
        .get_ref()
        .iter()
        .map(|&p| finite3(p))
        .collect::<Option<Vec<_>>>()
    {
        Some(c) => c,
        None => {
            return loc.err(
                corners.span(),
                field("corners"),
                "components must be finite numbers",
            )
        }
    };
    let u = c[1] - c[0];
    let v = c[3] - c[0];
    let area = u.cross(v);
    let scale = u.length().max(v.length());
    if !(area.length() > 1e-12 * scale * scale) {
        return loc.err(
            corners.span(),
            field("corners"),
            "the corners do not span a rectangle (zero area)",
        );
    }
    // The fourth corner must close the parallelogram.
    if (c[0] + u + v - c[2]).length() > 1e-6 * scale {
        return loc.err(
            corners.span(),
            field("corners"),
            "corners must be listed around the rectangle (c2 = c1 + c3 − c0) and lie in one plane",
        );
    }
    let normal = area.normalize();
    let radiance = radiance(loc, def, index)?;
    let texture = match &def.texture {
        None => None,
        Some(t) => Some(load_texture(loc, t, base, &field("texture"))?),
    };
    let polarization = polarization(loc, def, normal, "in the light's plane", index)?;
    Ok(Light {
        origin: c[0],
        u,
        v,
        normal,
        radiance,
        texture,
        polarization,
    })
}

/// A light at infinity: a unit direction, an angular diameter in
/// radians, no texture.
fn distant(
    loc: &LocFns<'_>,
    def: &LightDef,
    direction: &Spanned<V3>,
    index: usize,
) -> Result<DistantLight, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    let d = finite3(*direction.get_ref()).map_or(DVec3::ZERO, DVec3::normalize_or_zero);
    if d == DVec3::ZERO {
        return loc.err(
            direction.span(),
            field("direction"),
            "must be a finite non-zero vector (the direction the light travels)",
        );
    }
    let direction = d;
    let angular_diameter = match &def.angular_diameter {
        None => 0.0,
        Some(a) => {
            let deg = *a.get_ref();
            if !(deg.is_finite() && (0.0..=180.0).contains(&deg)) {
                return loc.err(
                    a.span(),
                    field("angular_diameter"),
                    format!(
                        "{deg}: the full angular diameter is a number of degrees from 0 \
                         (collimated) to 180"
                    ),
                );
            }
            deg.to_radians()
        }
    };
    if let Some(t) = &def.texture {
        return loc.err(
            t.span(),
            field("texture"),
            "a light at infinity (`direction`) takes no texture: textures need a rectangle \
             (`corners`) to map them on",
        );
    }
    let radiance = radiance(loc, def, index)?;
    let polarization = polarization(
        loc,
        def,
        direction,
        "perpendicular to the light's direction",
        index,
    )?;
    Ok(DistantLight {
        direction,
        angular_diameter,
        inner_diameter: 0.0,
        radiance,
        polarization,
    })
}

/// Light from every direction at infinity: `"uniform"` or a
/// latitude–longitude map (an image file relative to the scene, or
/// `builtin:NAME`), unpolarized, scaled by `radiance`.
fn environment(
    loc: &LocFns<'_>,
    def: &LightDef,
    env: &Spanned<String>,
    base: &Path,
    index: usize,
) -> Result<Environment, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    if let Some(p) = &def.polarization {
        return loc.err(
            p.span(),
            field("polarization"),
            "an environment is unpolarized: it takes no `polarization` (put a polarizer in the \
             scene, or use a rectangle or a light at infinity, which take one)",
        );
    }
    if let Some(t) = &def.texture {
        return loc.err(
            t.span(),
            field("texture"),
            "an environment's map is its `environment` file: it takes no `texture`",
        );
    }
    if let Some(a) = &def.angular_diameter {
        return loc.err(
            a.span(),
            field("angular_diameter"),
            "is for a light at infinity (`direction`); an environment fills every direction",
        );
    }
    let radiance = radiance(loc, def, index)?;
    let name = env.get_ref();
    let map = if name.trim() == "uniform" {
        None
    } else if name.trim().is_empty() {
        return loc.err(
            env.span(),
            field("environment"),
            "give \"uniform\" or a latitude–longitude image (a file relative to the scene, or \
             builtin:NAME)",
        );
    } else {
        Some(load_environment_map(loc, env, base, &field("environment"))?)
    };
    Ok(Environment { radiance, map })
}

/// An environment's latitude–longitude map from an image's RGB (alpha
/// ignored): every value finite and ≥ 0.
fn load_environment_map(
    loc: &LocFns<'_>,
    t: &Spanned<String>,
    base: &Path,
    field: &str,
) -> Result<EnvironmentMap, SceneError> {
    let (w, h, rgb) = load_rgb(loc, t, base, field, |c| {
        (!c.iter().all(|v| v.is_finite() && *v >= 0.0))
            .then(|| format!("is {c:?}: an environment's radiance must be finite and ≥ 0"))
    })?;
    Ok(EnvironmentMap::from_linear_rgb(w, h, &rgb))
}

/// An image's linear RGB (alpha ignored), row-major, for a texture or an
/// environment: a built-in (`builtin:NAME`) or a file relative to `base`.
/// `bad` names what is wrong with a texel (after "pixel (x, y) "), if
/// anything; the image must have pixels.
fn load_rgb(
    loc: &LocFns<'_>,
    t: &Spanned<String>,
    base: &Path,
    field: &str,
    bad: impl Fn([f64; 3]) -> Option<String>,
) -> Result<(usize, usize, Vec<[f64; 3]>), SceneError> {
    let name = t.get_ref();
    if let Some(b) = name.strip_prefix("builtin:") {
        return super::builtin::texture_rgb(b).map_or_else(
            || {
                loc.err(
                    t.span(),
                    field,
                    format!(
                        "no built-in texture `{b}`; built-in textures: {}",
                        super::builtin::TEXTURE_NAMES.join(", ")
                    ),
                )
            },
            Ok,
        );
    }
    let path = base.join(name);
    let image = crate::image::read(&path).or_else(|e| loc.err(t.span(), field, e.to_string()))?;
    let (width, height) = (image.width(), image.height());
    if width == 0 || height == 0 {
        return loc.err(
            t.span(),
            field,
            format!("{}: the image has no pixels", path.display()),
        );
    }
    let rgba = image
        .rgba()
        .or_else(|e| loc.err(t.span(), field, e.to_string()))?;
    let mut rgb = Vec::with_capacity(rgba.len());
    for (i, p) in rgba.iter().enumerate() {
        let c = [p[0] as f64, p[1] as f64, p[2] as f64];
        if let Some(why) = bad(c) {
            let (x, y) = (i % width, i / width);
            return loc.err(
                t.span(),
                field,
                format!("{}: pixel ({x}, {y}) {why}", path.display()),
            );
        }
        rgb.push(c);
    }
    Ok((width, height, rgb))
}

/// A light's `polarization`, its filter in the plane of unit `normal`
/// (`plane` says which plane, for errors): a polarizer's axis is stored
/// projected into that plane and normalized.
fn polarization(
    loc: &LocFns<'_>,
    def: &LightDef,
    normal: DVec3,
    plane: &str,
    index: usize,
) -> Result<Polarization, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    let Some(p) = &def.polarization else {
        return Ok(Polarization::Unpolarized);
    };
    Ok(match p.get_ref() {
        PolarizationDef::Named(n) if n == "unpolarized" => Polarization::Unpolarized,
        PolarizationDef::Named(n) => {
            return loc.err(
                p.span(),
                field("polarization"),
                format!("unknown polarization `{n}`: use \"unpolarized\", {{ linear = [x, y, z] }} or {{ calcite_plate = {{ keep = \"o\", axis = [x, y, z] }} }}"),
            )
        }
        PolarizationDef::Filter(FilterDef::Linear(a)) => {
            let a = finite3(*a).unwrap_or(DVec3::ZERO);
            let in_plane = a - a.dot(normal) * normal;
            if !(in_plane.length() > 1e-9 * a.length()) || a == DVec3::ZERO {
                return loc.err(
                    p.span(),
                    field("polarization.linear"),
                    format!("the polarizer's axis must be a finite vector with a component {plane}"),
                );
            }
            Polarization::Linear {
                axis: in_plane.normalize(),
            }
        }
        PolarizationDef::Filter(FilterDef::CalcitePlate(plate)) => {
            let keep = match plate.keep.as_str() {
                "o" | "ordinary" => PlateWave::Ordinary,
                "e" | "extraordinary" => PlateWave::Extraordinary,
                other => {
                    return loc.err(
                        p.span(),
                        field("polarization.calcite_plate.keep"),
                        format!("`{other}`: keep \"o\" or \"e\""),
                    )
                }
            };
            let axis = finite3(plate.axis).and_then(|a| (a.length() > 0.0).then(|| a.normalize()));
            let Some(axis) = axis else {
                return loc.err(
                    p.span(),
                    field("polarization.calcite_plate.axis"),
                    "must be a finite non-zero vector",
                );
            };
            Polarization::CalcitePlate { keep, axis }
        }
    })
}

fn load_texture(
    loc: &LocFns<'_>,
    t: &Spanned<String>,
    base: &Path,
    field: &str,
) -> Result<Texture, SceneError> {
    let (w, h, rgb) = load_rgb(loc, t, base, field, |c| {
        (!c.iter().all(|v| v.is_finite())).then(|| "is not finite".to_string())
    })?;
    Ok(Texture::from_linear_rgb(w, h, &rgb))
}
