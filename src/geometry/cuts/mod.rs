//! Standard gem cuts generated from their proportions.
//!
//! A cut is a set of facet planes; the stone is the intersection of their
//! half-spaces ([`super::convex`]), exactly as for a GemCAD design. Each
//! generator places its planes through the points a cutter would aim for
//! (girdle corners, table corners, star and lower-girdle tips), so the
//! facets meet where the proportions say they do.
//!
//! Coordinates follow GemCAD's: +Z toward the table, the girdle plane at
//! z = 0 (the girdle band spans ±thickness/2), facet number 1 of every
//! tier along +Y, numbers increasing clockwise seen from +Z.
//!
//! In a scene file a cut is a table with its name and any parameters, e.g.
//! `cut = { name = "round-brilliant", table = 0.53, crown_angle = 34.5 }`;
//! on the command line the same parameters are flags
//! (`spar cut round-brilliant --table 0.53 --crown-angle 34.5 -o gem.obj`).
//! Unnamed parameters take the defaults documented on each cut.

mod brilliant;
mod emerald;
mod princess;
mod write;

pub use brilliant::Brilliant;
pub use emerald::Emerald;
pub use princess::Princess;
pub use write::write_obj;

use super::convex::{intersect, HalfSpace, IntersectOptions, Stone};
use super::mesh::Mesh;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// A standard cut and its parameters, as a scene file or the command line
/// names it.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(tag = "name", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Cut {
    /// The round brilliant (57 facets, 58 with a culet, plus the girdle
    /// band): Tolkowsky's proportions by default.
    RoundBrilliant(Brilliant),
    /// The oval brilliant: a round brilliant stretched along +Y.
    Oval(Brilliant),
    /// The princess: a square modified brilliant with a chevron pavilion.
    Princess(Princess),
    /// The emerald: a rectangular step cut with cut corners.
    Emerald(Emerald),
}

/// The names [`Cut`] accepts.
pub const CUT_NAMES: [&str; 4] = ["round-brilliant", "oval", "princess", "emerald"];

impl Cut {
    /// The cut of this name with default parameters.
    pub fn by_name(name: &str) -> Option<Cut> {
        Some(match name {
            "round-brilliant" => Cut::RoundBrilliant(Brilliant::default()),
            "oval" => Cut::Oval(Brilliant::default()),
            "princess" => Cut::Princess(Princess::default()),
            "emerald" => Cut::Emerald(Emerald::default()),
            _ => return None,
        })
    }

    /// The kebab-case name of the cut.
    pub fn name(&self) -> &'static str {
        match self {
            Cut::RoundBrilliant(_) => "round-brilliant",
            Cut::Oval(_) => "oval",
            Cut::Princess(_) => "princess",
            Cut::Emerald(_) => "emerald",
        }
    }

    /// The cut's facet planes, named, after checking its parameters.
    pub fn planes(&self) -> Result<Vec<NamedPlane>, String> {
        match self {
            Cut::RoundBrilliant(b) => {
                if b.ratio.is_some_and(|r| r != 1.0) {
                    return Err("a round brilliant has ratio 1; an oval takes a ratio".into());
                }
                b.planes(1.0)
            }
            Cut::Oval(b) => b.planes(b.ratio.unwrap_or(brilliant::OVAL_RATIO)),
            Cut::Princess(p) => p.planes(),
            Cut::Emerald(e) => e.planes(),
        }
    }

    /// The overall size the cut is scaled to (diameter or width).
    fn size(&self) -> f64 {
        match self {
            Cut::RoundBrilliant(b) | Cut::Oval(b) => b.diameter,
            Cut::Princess(p) => p.width,
            Cut::Emerald(e) => e.width * e.ratio.max(1.0),
        }
    }

    /// The stone: the intersection of the cut's half-spaces.
    pub fn stone(&self) -> Result<Stone, String> {
        let planes = self.planes()?;
        build(&planes, self.size()).map_err(|e| format!("{}: {e}", self.name()))
    }

    /// The cut as a TOML table: `name = "…"` and every parameter, as a
    /// scene file would write it.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| format!("# cannot describe the cut: {e}"))
    }

    /// The cut's mesh (see [`Cut::stone`] for the notes on vanished facets).
    pub fn mesh(&self) -> Result<Mesh, String> {
        self.stone().map(|s| s.mesh)
    }
}

/// What the scene loader calls for `cut = { name = "…", … }`: the mesh of
/// a cut described by a TOML table (or any serde source), with an error
/// message naming the bad parameter.
pub fn mesh_from_spec(spec: &toml::Value) -> Result<Mesh, String> {
    cut_from_spec(spec)?.mesh()
}

/// Parses a cut description (`name` and parameters) from a TOML value.
pub fn cut_from_spec(spec: &toml::Value) -> Result<Cut, String> {
    let name = spec
        .get("name")
        .and_then(toml::Value::as_str)
        .ok_or_else(|| {
            format!(
                "a cut needs a name: one of {}",
                CUT_NAMES.map(|n| format!("\"{n}\"")).join(", ")
            )
        })?;
    if Cut::by_name(name).is_none() {
        return Err(format!(
            "unknown cut \"{name}\"; cuts: {}",
            CUT_NAMES.join(", ")
        ));
    }
    Cut::deserialize(spec.clone()).map_err(|e| format!("cut \"{name}\": {}", e.message()))
}

/// A facet plane and the facet's name.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedPlane {
    pub plane: HalfSpace,
    pub name: String,
}

/// Builds the stone from named planes; `size` sets the weld tolerance
/// (1e-9 of it: generated planes meet exactly up to rounding).
pub fn build(planes: &[NamedPlane], size: f64) -> Result<Stone, super::convex::ConvexError> {
    let halves: Vec<HalfSpace> = planes.iter().map(|p| p.plane).collect();
    let polytope = intersect(&halves, IntersectOptions { weld: 1e-9 * size })?;
    let mesh = polytope.to_mesh(|i| Some(planes[i].name.clone()));
    let notes = polytope.fate_notes(|i| format!("facet {}", planes[i].name));
    Ok(Stone {
        mesh,
        notes,
        polytope,
    })
}

/// The horizontal unit vector at `azimuth` degrees clockwise from +Y seen
/// from +Z (GemCAD's index direction).
pub(crate) fn horizontal(azimuth: f64) -> DVec3 {
    let a = azimuth.to_radians();
    DVec3::new(a.sin(), a.cos(), 0.0)
}

/// The facet plane at `azimuth` tilted `angle` degrees from the girdle plane
/// (positive: crown, outward normal up; negative: pavilion) through `point`.
pub(crate) fn tilted(azimuth: f64, angle: f64, point: DVec3) -> HalfSpace {
    let t = angle.abs().to_radians();
    let up = if angle < 0.0 { -1.0 } else { 1.0 };
    let normal = horizontal(azimuth) * t.sin() + DVec3::Z * (up * t.cos());
    HalfSpace::new(normal, normal.dot(point))
}

/// The plane through three points, oriented so that `inside` is inside.
pub(crate) fn through(a: DVec3, b: DVec3, c: DVec3, inside: DVec3) -> HalfSpace {
    let mut normal = (b - a).cross(c - a).normalize();
    if normal.dot(inside - a) > 0.0 {
        normal = -normal;
    }
    HalfSpace::new(normal, normal.dot(a))
}

/// A named plane.
pub(crate) fn named(plane: HalfSpace, name: impl Into<String>) -> NamedPlane {
    NamedPlane {
        plane,
        name: name.into(),
    }
}

/// Checks that a parameter lies in an open or closed range, naming it.
pub(crate) fn check(
    name: &str,
    value: f64,
    lo: f64,
    hi: f64,
    closed_lo: bool,
) -> Result<(), String> {
    let ok_lo = if closed_lo { value >= lo } else { value > lo };
    if value.is_finite() && ok_lo && value < hi {
        Ok(())
    } else {
        let open = if closed_lo { "[" } else { "(" };
        Err(format!("{name} = {value} is outside {open}{lo}, {hi})"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilted_planes_follow_the_gemcad_convention() {
        // Azimuth 90° is +X; a 30° crown facet's normal is (sin 30°, 0, cos 30°).
        let p = tilted(90.0, 30.0, DVec3::new(1.0, 0.0, 0.0));
        assert!((p.normal - DVec3::new(0.5, 0.0, 0.75f64.sqrt())).length() < 1e-15);
        assert!((p.offset - 0.5).abs() < 1e-15);
        let q = tilted(0.0, -90.0, DVec3::new(0.0, 2.0, 0.0));
        assert!((q.normal - DVec3::Y).length() < 1e-15 && (q.offset - 2.0).abs() < 1e-15);
    }

    #[test]
    fn specs_name_their_errors() {
        let spec: toml::Value = toml::from_str("name = \"round-brilliant\"\ntable = 0.6").unwrap();
        let cut = cut_from_spec(&spec).unwrap();
        assert!(matches!(cut, Cut::RoundBrilliant(Brilliant { table, .. }) if table == 0.6));
        let bad: toml::Value = toml::from_str("name = \"emerald\"\nstar = 0.5").unwrap();
        let e = cut_from_spec(&bad).unwrap_err();
        assert!(e.contains("star"), "{e}");
        let unknown: toml::Value = toml::from_str("name = \"trillion\"").unwrap();
        assert!(cut_from_spec(&unknown)
            .unwrap_err()
            .contains("round-brilliant"));
    }
}
