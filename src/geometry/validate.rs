//! Validation of a gem mesh as it is loaded, for OBJ and `.asc` alike:
//! is it closed and consistently oriented (errors otherwise), is it convex
//! (concave cuts are allowed, and said), and which facets are degenerate:
//! zero area, non-planar beyond a tolerance (the worst is named), or with
//! edges shorter than a tolerance.
//!
//! Convexity is judged per facet plane: each facet's plane against every
//! vertex of the mesh, with a tolerance that grows with the vertex's
//! distance from the facet over the facet's width (a sliver's plane is only
//! known to the vertices' rounding divided by its width), so noisy slivers
//! of a convex cut do not make it concave.
//!
//! Tolerances are relative to the mesh's size (the diagonal of its bounding
//! box), so the same report reads the same for a design in GemCAD units and
//! one in millimetres.

use super::asc::parse_asc;
use super::mesh::{facet_label as label, polygon_width, Mesh, TopologyError};
use super::obj::{read_obj, read_obj_file, ObjMesh, ZERO_AREA_WIDTH};
use glam::DVec3;
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// Tolerances, as fractions of the mesh size (areas of its square).
#[derive(Clone, Copy, Debug)]
pub struct Tolerances {
    /// A vertex farther than this from its facet's plane makes the facet
    /// non-planar.
    pub planarity: f64,
    /// A vertex farther than this above another facet's plane makes the
    /// mesh concave (for a facet as wide as the vertex is far from it; the
    /// tolerance grows as distance over width for narrower facets).
    pub convexity: f64,
    /// Facets whose vertices all lie within this of a line are degenerate.
    pub width: f64,
    /// Edges shorter than this are tiny.
    pub edge: f64,
}

impl Default for Tolerances {
    /// Planarity, convexity, width and edges 1e-6 — mesh files print
    /// coordinates to about 1e-7 relative, so real facets pass.
    fn default() -> Tolerances {
        Tolerances {
            planarity: 1e-6,
            convexity: 1e-6,
            width: ZERO_AREA_WIDTH,
            edge: 1e-6,
        }
    }
}

/// A facet and a measure of what is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct FacetIssue {
    /// 0-based facet index.
    pub facet: usize,
    pub name: Option<String>,
    /// The file's line of the facet, if known.
    pub line: Option<usize>,
    /// Area, or distance from the plane (absolute units).
    pub value: f64,
}

/// An edge (0-based vertex indices, and the file's numbers of them) and its
/// length.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeIssue {
    pub a: u32,
    pub b: u32,
    pub numbers: (u32, u32),
    pub length: f64,
}

/// What [`validate`] found.
#[derive(Clone, Debug)]
pub struct Report {
    pub vertices: usize,
    pub facets: usize,
    pub edges: usize,
    /// Diagonal of the bounding box: the unit of the tolerances.
    pub size: f64,
    /// Why the mesh is not closed and consistently oriented with outward
    /// normals, if it is not.
    pub topology: Option<TopologyError>,
    /// Enclosed volume (divergence theorem).
    pub volume: f64,
    /// The facet with a vertex farthest above its plane, when beyond the
    /// convexity tolerance (value: that height), and the file's number of
    /// that vertex.
    pub concavity: Option<(FacetIssue, u32)>,
    /// Facets with (near) zero area: vertices within the width tolerance
    /// of a line (value: area).
    pub degenerate: Vec<FacetIssue>,
    /// Facets whose vertices leave their plane beyond the tolerance (value:
    /// largest distance), worst first.
    pub nonplanar: Vec<FacetIssue>,
    /// The least planar facet, whatever its deviation.
    pub worst_planarity: Option<FacetIssue>,
    /// Edges below the edge tolerance, shortest first.
    pub tiny_edges: Vec<EdgeIssue>,
    pub shortest_edge: f64,
    pub tolerances: Tolerances,
}

/// Validates with the default tolerances.
pub fn validate(mesh: &Mesh) -> Report {
    validate_with(mesh, Tolerances::default())
}

/// Validates with the given tolerances.
pub fn validate_with(mesh: &Mesh, tol: Tolerances) -> Report {
    let (lo, hi) = mesh.bounds();
    let size = if mesh.positions.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    };
    let p = |v: u32| mesh.positions[v as usize];
    let issue = |f: usize, value: f64| FacetIssue {
        facet: f,
        name: mesh.facets[f].name.clone(),
        line: mesh.facets[f].line,
        value,
    };

    let mut degenerate = Vec::new();
    let mut nonplanar = Vec::new();
    let mut worst_planarity: Option<FacetIssue> = None;
    for (i, f) in mesh.facets.iter().enumerate() {
        // Newell's area vector: twice the polygon's (projected) area.
        let n = f.vertices.len();
        let area = (0..n)
            .map(|k| p(f.vertices[k]).cross(p(f.vertices[(k + 1) % n])))
            .sum::<glam::DVec3>()
            .length()
            / 2.0;
        if !(polygon_width(&mesh.positions, &f.vertices) > tol.width * size) {
            degenerate.push(issue(i, area));
        }
        let deviation = f
            .vertices
            .iter()
            .map(|&v| (f.normal.dot(p(v)) - f.offset).abs())
            .fold(0.0, f64::max);
        if worst_planarity.as_ref().is_none_or(|w| deviation > w.value) {
            worst_planarity = Some(issue(i, deviation));
        }
        if deviation > tol.planarity * size {
            nonplanar.push(issue(i, deviation));
        }
    }
    nonplanar.sort_by(|a, b| b.value.total_cmp(&a.value));

    let mut edges: HashMap<(u32, u32), ()> = HashMap::new();
    for f in &mesh.facets {
        let n = f.vertices.len();
        for k in 0..n {
            let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
            edges.insert((a.min(b), a.max(b)), ());
        }
    }
    let mut tiny_edges = Vec::new();
    let mut shortest_edge = f64::INFINITY;
    for &(a, b) in edges.keys() {
        let length = p(a).distance(p(b));
        shortest_edge = shortest_edge.min(length);
        if length < tol.edge * size {
            tiny_edges.push(EdgeIssue {
                a,
                b,
                numbers: (mesh.vertex_label(a), mesh.vertex_label(b)),
                length,
            });
        }
    }
    tiny_edges.sort_by(|x, y| {
        x.length
            .total_cmp(&y.length)
            .then((x.a, x.b).cmp(&(y.a, y.b)))
    });

    Report {
        vertices: mesh.positions.len(),
        facets: mesh.facets.len(),
        edges: edges.len(),
        size,
        topology: mesh.check_closed_and_oriented().err(),
        volume: mesh.signed_volume(),
        concavity: concavity(mesh, tol.convexity * size),
        degenerate,
        nonplanar,
        worst_planarity,
        tiny_edges,
        shortest_edge,
        tolerances: tol,
    }
}

/// The facet with a vertex highest above its plane beyond the tolerance,
/// and that vertex. A vertex at distance `r` from a facet of width `w` is
/// above it when higher than `tol · (1 + r / w)`: a facet's plane, fitted to
/// vertices rounded by about `tol`, tilts by up to `tol / w`. Every vertex
/// against every facet for gem-sized meshes; for large ones, each facet
/// against the vertices of the facets sharing its edges (a closed connected
/// surface convex at every edge is convex).
fn concavity(mesh: &Mesh, tol: f64) -> Option<(FacetIssue, u32)> {
    let frames: Vec<(DVec3, f64)> = mesh
        .facets
        .iter()
        .map(|f| {
            let centroid = f
                .vertices
                .iter()
                .map(|&v| mesh.positions[v as usize])
                .sum::<DVec3>()
                / f.vertices.len().max(1) as f64;
            (centroid, polygon_width(&mesh.positions, &f.vertices))
        })
        .collect();
    let mut worst: Option<(FacetIssue, u32)> = None;
    let mut consider = |facet: usize, v: u32| {
        let f = &mesh.facets[facet];
        let p = mesh.positions[v as usize];
        let height = f.normal.dot(p) - f.offset;
        let (centroid, width) = frames[facet];
        let allowed = tol * (1.0 + p.distance(centroid) / width);
        if height > allowed && worst.as_ref().is_none_or(|w| height > w.0.value) {
            worst = Some((
                FacetIssue {
                    facet,
                    name: f.name.clone(),
                    line: f.line,
                    value: height,
                },
                mesh.vertex_label(v),
            ));
        }
    };
    if mesh.facets.len() * mesh.positions.len() <= 20_000_000 {
        for f in 0..mesh.facets.len() {
            for v in 0..mesh.positions.len() as u32 {
                consider(f, v);
            }
        }
    } else {
        let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (i, f) in mesh.facets.iter().enumerate() {
            let n = f.vertices.len();
            for k in 0..n {
                let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
                by_edge.entry((a.min(b), a.max(b))).or_default().push(i);
            }
        }
        for users in by_edge.values() {
            for &f in users {
                for &g in users {
                    if f != g {
                        for &v in &mesh.facets[g].vertices {
                            consider(f, v);
                        }
                    }
                }
            }
        }
    }
    worst
}

/// `facet 12 (line 40, bezel-3)`, 1-based as a user counts.
fn facet_label(issue: &FacetIssue) -> String {
    label(issue.facet, issue.line, issue.name.as_deref())
}

impl Report {
    /// Closed, consistently oriented, outward normals.
    pub fn is_closed(&self) -> bool {
        self.topology.is_none()
    }

    /// No vertex above any facet's plane beyond the tolerance.
    pub fn is_convex(&self) -> bool {
        self.concavity.is_none()
    }

    /// Problems that make the mesh unusable as a solid: not closed or not
    /// consistently oriented.
    pub fn errors(&self) -> Vec<String> {
        self.topology.iter().map(|t| t.to_string()).collect()
    }

    /// Problems worth telling the user that do not stop a render.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        for d in &self.degenerate {
            out.push(format!(
                "{} is degenerate: area {:.3e}",
                facet_label(d),
                d.value
            ));
        }
        if let Some(worst) = self.nonplanar.first() {
            out.push(format!(
                "{} facet(s) are not planar within {:.1e} of the size; the worst, {}, has a vertex {:.3e} off its plane",
                self.nonplanar.len(),
                self.tolerances.planarity,
                facet_label(worst),
                worst.value
            ));
        }
        if let Some(e) = self.tiny_edges.first() {
            out.push(format!(
                "{} edge(s) are shorter than {:.1e} of the size; the shortest joins vertices {} and {}, length {:.3e}",
                self.tiny_edges.len(),
                self.tolerances.edge,
                e.numbers.0,
                e.numbers.1,
                e.length
            ));
        }
        out
    }

    /// One line: counts, volume, convexity.
    pub fn summary(&self) -> String {
        let shape = match (&self.topology, &self.concavity) {
            (Some(_), _) => "not a closed oriented surface".to_owned(),
            (None, None) => "closed, oriented, convex".to_owned(),
            (None, Some((c, v))) => format!(
                "closed, oriented, concave ({} has vertex {v} {:.3e} above its plane)",
                facet_label(c),
                c.value
            ),
        };
        format!(
            "{} facets, {} vertices, {} edges; {shape}; volume {:.6e}; shortest edge {:.3e}; least planar {}",
            self.facets,
            self.vertices,
            self.edges,
            self.volume,
            self.shortest_edge,
            self.worst_planarity
                .as_ref()
                .map_or_else(|| "-".to_owned(), |w| format!("{} ({:.1e})", facet_label(w), w.value))
        )
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.summary())?;
        for e in self.errors() {
            writeln!(f, "error: {e}")?;
        }
        for w in self.warnings() {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}

/// A mesh file format, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    Asc,
}

impl MeshFormat {
    /// The format of a file name (`.obj` or `.asc`, any case).
    pub fn of(name: &str) -> Option<MeshFormat> {
        let ext = Path::new(name).extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(MeshFormat::Obj),
            "asc" => Some(MeshFormat::Asc),
            _ => None,
        }
    }
}

/// A loaded, validated mesh.
#[derive(Clone, Debug)]
pub struct LoadedMesh {
    pub mesh: Mesh,
    pub report: Report,
    /// What the loader tolerated (for `.asc`: facets without a face, reader
    /// warnings) followed by the report's warnings, each naming the file.
    pub warnings: Vec<String>,
}

/// Loads an `.obj` or `.asc` file and validates it: malformed files give
/// `file:line: message`; a mesh that is not closed and consistently
/// oriented is an error naming the file (and the facets' lines); everything
/// else comes back as warnings. OBJ files are read line by line. The scene
/// loader calls this for `mesh = "…"`.
pub fn load_mesh(path: &Path) -> Result<LoadedMesh, String> {
    let file = path.display().to_string();
    match MeshFormat::of(&file) {
        Some(MeshFormat::Obj) => {
            let read = read_obj_file(path).map_err(|e| e.to_string())?;
            checked(read.mesh, read.warnings, &read.dropped, &file)
        }
        _ => {
            let bytes = std::fs::read(path).map_err(|e| format!("{file}: cannot read: {e}"))?;
            mesh_from_bytes(&bytes, &file)
        }
    }
}

/// [`load_mesh`] for bytes already in memory; `file` names them and its
/// extension picks the format.
pub fn mesh_from_bytes(bytes: &[u8], file: &str) -> Result<LoadedMesh, String> {
    match MeshFormat::of(file) {
        Some(format) => mesh_from_bytes_as(bytes, file, format),
        None => Err(format!(
            "{file}: unknown mesh format (expected .obj or .asc)"
        )),
    }
}

/// [`mesh_from_bytes`] with the format given (for names without an
/// extension, such as `builtin:trichecker12`).
pub fn mesh_from_bytes_as(
    bytes: &[u8],
    file: &str,
    format: MeshFormat,
) -> Result<LoadedMesh, String> {
    match format {
        MeshFormat::Obj => {
            let ObjMesh {
                mesh,
                warnings,
                dropped,
            } = read_obj(bytes, file).map_err(|e| e.to_string())?;
            checked(mesh, warnings, &dropped, file)
        }
        MeshFormat::Asc => {
            let stone = parse_asc(bytes, file)
                .and_then(|d| d.stone())
                .map_err(|e| e.to_string())?;
            checked(stone.mesh, stone.notes, &[], file)
        }
    }
}

/// Validates a loaded mesh: a topology error names the file (and the
/// zero-area faces dropped before the check, whose removal may have opened
/// the mesh); the report's warnings join the loader's.
fn checked(
    mesh: Mesh,
    mut warnings: Vec<String>,
    dropped: &[usize],
    file: &str,
) -> Result<LoadedMesh, String> {
    let report = validate(&mesh);
    if let Some(t) = &report.topology {
        let mut message = format!("{file}: {t}");
        if !dropped.is_empty() {
            let lines: Vec<String> = dropped.iter().take(8).map(|l| l.to_string()).collect();
            message += &format!(
                " (after dropping {} zero-area face(s), at line(s) {}{})",
                dropped.len(),
                lines.join(", "),
                if dropped.len() > 8 { ", …" } else { "" }
            );
        }
        return Err(message);
    }
    warnings.extend(
        report
            .warnings()
            .into_iter()
            .map(|w| format!("{file}: {w}")),
    );
    if !report.is_convex() {
        // Said, not refused: concave cuts exist (and render).
        warnings.push(format!("{file}: {}", report.summary()));
    }
    Ok(LoadedMesh {
        mesh,
        report,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube, counter-clockwise from outside, with vertex 6 moved by
    /// `dent` along (−1, −1, −1) (into the cube when positive, making it
    /// concave).
    fn cube(dent: f64) -> Mesh {
        let mut positions: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        positions[7] -= DVec3::splat(dent);
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        Mesh::from_polygons(
            positions,
            faces
                .iter()
                .map(|f| (f.to_vec(), Some(format!("f{}", f[0]))))
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn a_cube_is_clean() {
        let r = validate(&cube(0.0));
        assert!(r.is_closed() && r.is_convex());
        assert!(r.warnings().is_empty(), "{:?}", r.warnings());
        assert_eq!((r.facets, r.vertices, r.edges), (6, 8, 12));
        assert_eq!(r.shortest_edge, 1.0);
    }

    #[test]
    fn a_pushed_in_corner_is_concave_and_non_planar() {
        // Moving one corner 0.1 inward warps its three faces (Newell planes
        // through a non-planar quad) and makes the solid concave there.
        let r = validate(&cube(0.1));
        assert!(r.is_closed());
        assert!(!r.is_convex());
        assert_eq!(r.nonplanar.len(), 3);
        let worst = r.worst_planarity.clone().unwrap();
        assert!(worst.value > 0.01, "{worst:?}");
        assert!(r.warnings()[0].contains("not planar"), "{:?}", r.warnings());
        assert!(r.summary().contains("concave"));
    }

    #[test]
    fn near_zero_area_facets_are_named() {
        // A flat sliver triangle 1e-14 high next to a healthy one.
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1e-14, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let polys = vec![
            (vec![0, 1, 2], Some("sliver".into())),
            (vec![0, 1, 3], None),
        ];
        let r = validate(&Mesh::from_polygons(positions, polys).unwrap());
        assert_eq!(r.degenerate.len(), 1);
        assert_eq!(r.degenerate[0].name.as_deref(), Some("sliver"));
        assert!(
            r.warnings()[0].starts_with("facet 1 (sliver) is degenerate"),
            "{:?}",
            r.warnings()
        );
    }

    #[test]
    fn open_meshes_are_errors() {
        let mut m = cube(0.0);
        m.facets.pop();
        let r = validate(&m);
        assert!(!r.is_closed());
        assert!(r.errors()[0].contains("open edge"));
    }
}
