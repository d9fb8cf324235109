//! `[[light]]` tables: validated into the renderer's rectangular area
//! lights ([`crate::render::light`]), textures loaded from image files or
//! built in.

use super::file::{FilterDef, LightDef, PolarizationDef};
use super::{finite3, LocFns, SceneError};
use crate::render::light::{Light, PlateWave, Polarization, Texture};
use glam::DVec3;
use std::path::Path;
use toml::Spanned;

/// Validates a `[[light]]` table.
pub(crate) fn resolve(
    loc: &LocFns<'_>,
    l: &Spanned<LightDef>,
    base: &Path,
    index: usize,
) -> Result<Light, SceneError> {
    let field = |f: &str| format!("light[{index}].{f}");
    let def = l.get_ref();
    let corners = def.corners.get_ref();
    let c: Vec<DVec3> = match corners
        .iter()
        .map(|&p| finite3(p))
        .collect::<Option<Vec<_>>>()
    {
        Some(c) => c,
        None => {
            return loc.err(
                def.corners.span(),
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
            def.corners.span(),
            field("corners"),
            "the corners do not span a rectangle (zero area)",
        );
    }
    // The fourth corner must close the parallelogram.
    if (c[0] + u + v - c[2]).length() > 1e-6 * scale {
        return loc.err(
            def.corners.span(),
            field("corners"),
            "corners must be listed around the rectangle (c2 = c1 + c3 − c0) and lie in one plane",
        );
    }
    let normal = area.normalize();
    let radiance = *def.radiance.get_ref();
    if !(radiance.is_finite() && radiance >= 0.0) {
        return loc.err(
            def.radiance.span(),
            field("radiance"),
            "must be a finite number ≥ 0",
        );
    }
    let texture = match &def.texture {
        None => None,
        Some(t) => Some(load_texture(loc, t, base, &field("texture"))?),
    };
    let polarization = match &def.polarization {
        None => Polarization::Unpolarized,
        Some(p) => match p.get_ref() {
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
                    return loc.err(p.span(), field("polarization.linear"), "the polarizer's axis must be a finite vector with a component in the light's plane");
                }
                Polarization::Linear { axis: in_plane.normalize() }
            }
            PolarizationDef::Filter(FilterDef::CalcitePlate(plate)) => {
                let keep = match plate.keep.as_str() {
                    "o" | "ordinary" => PlateWave::Ordinary,
                    "e" | "extraordinary" => PlateWave::Extraordinary,
                    other => return loc.err(p.span(), field("polarization.calcite_plate.keep"), format!("`{other}`: keep \"o\" or \"e\"")),
                };
                let axis = finite3(plate.axis).and_then(|a| (a.length() > 0.0).then(|| a.normalize()));
                let Some(axis) = axis else {
                    return loc.err(p.span(), field("polarization.calcite_plate.axis"), "must be a finite non-zero vector");
                };
                Polarization::CalcitePlate { keep, axis }
            }
        },
    };
    let _ = l.span();
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

fn load_texture(
    loc: &LocFns<'_>,
    t: &Spanned<String>,
    base: &Path,
    field: &str,
) -> Result<Texture, SceneError> {
    let name = t.get_ref();
    if let Some(b) = name.strip_prefix("builtin:") {
        return super::builtin::texture(b).map_or_else(
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
    let rgba = image
        .rgba()
        .or_else(|e| loc.err(t.span(), field, e.to_string()))?;
    let mut rgb = Vec::with_capacity(rgba.len());
    for (i, p) in rgba.iter().enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            let (x, y) = (i % image.width(), i / image.width());
            return loc.err(
                t.span(),
                field,
                format!("{}: pixel ({x}, {y}) is not finite", path.display()),
            );
        }
        rgb.push([p[0] as f64, p[1] as f64, p[2] as f64]);
    }
    Ok(Texture::from_linear_rgb(
        image.width(),
        image.height(),
        &rgb,
    ))
}
