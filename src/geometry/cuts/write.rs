//! Writing a mesh as Wavefront OBJ: one `v` line per vertex (shortest text
//! that reads back to the same f64), one n-gon `f` per facet, each facet in
//! its own group `g name` so that names survive a round trip.

use super::super::mesh::Mesh;
use std::fmt::Write;

/// The shortest text that reads back to `x`, in exponent form when tiny
/// (rounding noise such as 6e-17 would otherwise print 17 zeros).
fn number(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-4 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The OBJ text of `mesh`, `comments` first (each line prefixed `# `).
/// Unnamed facets are grouped as `facet-<n>`; whitespace in names becomes
/// `_` (OBJ names are single words).
pub fn write_obj(mesh: &Mesh, comments: &[String]) -> String {
    let mut out = String::new();
    for c in comments {
        for line in c.lines() {
            let _ = writeln!(out, "# {line}");
        }
    }
    for p in &mesh.positions {
        let _ = writeln!(out, "v {} {} {}", number(p.x), number(p.y), number(p.z));
    }
    for (i, f) in mesh.facets.iter().enumerate() {
        let name = f.name.as_deref().map_or_else(
            || format!("facet-{}", i + 1),
            |n| n.split_whitespace().collect::<Vec<_>>().join("_"),
        );
        let name = if name.is_empty() {
            format!("facet-{}", i + 1)
        } else {
            name
        };
        let _ = writeln!(out, "g {name}");
        out.push('f');
        for &v in &f.vertices {
            let _ = write!(out, " {}", v + 1);
        }
        out.push('\n');
    }
    out
}
