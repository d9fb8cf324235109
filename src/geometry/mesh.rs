//! Polygon meshes of cut gems: flat facets, each split into triangles that
//! all carry the facet's exact plane normal.
//!
//! A real cut has near-meeting facets whose tiny triangles would get normals
//! off by 1e-4 rad if each triangle's normal came from its own three
//! vertices; a facet's normal comes from all of its vertices (Newell's
//! method), once, and every triangle of the facet uses it. Convex facets are
//! fanned from their first vertex; concave ones are split by ear clipping in
//! the facet's plane (the `earcut` crate), so they are covered exactly; a
//! facet whose outline crosses or touches itself is refused.

use glam::{DAffine3, DVec2, DVec3};
use std::collections::HashMap;

/// One flat facet: a convex or concave polygon, split into triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct Facet {
    /// Unit normal, pointing to the side the vertex order winds
    /// counter-clockwise around (outward for a consistently oriented closed
    /// mesh whose faces are listed counter-clockwise seen from outside).
    pub normal: DVec3,
    /// Plane offset: points x of the facet satisfy `normal · x = offset`.
    pub offset: f64,
    /// The facet's vertex indices, in order.
    pub vertices: Vec<u32>,
    /// Group or object name from the file, if any.
    pub name: Option<String>,
    /// The 1-based line of the file that defines the facet, if it came from
    /// a file (the `f` line of an OBJ face, the tier line of a `.asc` facet).
    pub line: Option<usize>,
}

/// A polygon mesh with its triangulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub positions: Vec<DVec3>,
    pub facets: Vec<Facet>,
    /// Triangles as vertex indices; triangle `i` belongs to facet
    /// `triangle_facet[i]`.
    pub triangles: Vec<[u32; 3]>,
    pub triangle_facet: Vec<u32>,
    /// The number the source file gives each vertex (an OBJ file's 1-based
    /// `v` number), for messages; empty when the vertices are not numbered
    /// by a file (then vertex `i` is called `i + 1`).
    pub vertex_numbers: Vec<u32>,
}

/// A polygon to make a facet of: vertex indices (at least three), and where
/// it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    pub vertices: Vec<u32>,
    pub name: Option<String>,
    pub line: Option<usize>,
}

/// Why a mesh is not a closed, consistently oriented surface, or why a
/// facet cannot be made. Vertices and facets are named as the source file
/// names them (see [`Mesh::vertex_label`] and [`Mesh::facet_label`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TopologyError {
    #[error("open edge between {edge}: only {facet} uses it, so the mesh is not closed")]
    OpenEdge { edge: String, facet: String },
    #[error("edge between {edge} is used in the same direction by {f1} and {f2}: the facets are not consistently oriented")]
    Inconsistent {
        edge: String,
        f1: String,
        f2: String,
    },
    #[error(
        "edge between {edge} is shared by {count} facets ({facets}): the mesh is not a manifold"
    )]
    NonManifold {
        edge: String,
        count: usize,
        facets: String,
    },
    #[error("{facet} is degenerate (its vertices do not span a plane)")]
    DegenerateFacet { facet: String },
    #[error("{facet} {why}, so it cannot be split into triangles")]
    SelfIntersecting { facet: String, why: String },
    #[error("the mesh encloses negative volume ({volume:.3e}): its facets wind clockwise seen from outside")]
    InsideOut { volume: f64 },
}

/// `facet 12 (line 40, crown)`: 1-based index, then the line and the name
/// when known.
pub fn facet_label(index: usize, line: Option<usize>, name: Option<&str>) -> String {
    match (line, name) {
        (Some(l), Some(n)) => format!("facet {} (line {l}, {n})", index + 1),
        (Some(l), None) => format!("facet {} (line {l})", index + 1),
        (None, Some(n)) => format!("facet {} ({n})", index + 1),
        (None, None) => format!("facet {}", index + 1),
    }
}

/// How far a polygon is from being a line segment: the largest distance of
/// a vertex from the line through its first vertex and the vertex farthest
/// from it (0 for coincident or collinear vertices). Within a factor of two
/// of the polygon's narrowest width.
pub fn polygon_width(positions: &[DVec3], vertices: &[u32]) -> f64 {
    let p = |v: u32| positions[v as usize];
    let Some(&first) = vertices.first() else {
        return 0.0;
    };
    let a = p(first);
    let far = vertices
        .iter()
        .map(|&v| p(v))
        .max_by(|x, y| x.distance_squared(a).total_cmp(&y.distance_squared(a)))
        .unwrap_or(a);
    let axis = far - a;
    let len = axis.length();
    if !(len > 0.0) {
        return 0.0;
    }
    let dir = axis / len;
    vertices
        .iter()
        .map(|&v| {
            let d = p(v) - a;
            (d - dir * d.dot(dir)).length()
        })
        .fold(0.0, f64::max)
}

impl Mesh {
    /// Builds a mesh from polygons (each a list of vertex indices, at least
    /// three). Facet normals come from Newell's method over all vertices of
    /// the polygon; polygons are split into triangles in their plane.
    pub fn from_polygons(
        positions: Vec<DVec3>,
        polygons: Vec<(Vec<u32>, Option<String>)>,
    ) -> Result<Mesh, TopologyError> {
        let polygons = polygons
            .into_iter()
            .map(|(vertices, name)| Polygon {
                vertices,
                name,
                line: None,
            })
            .collect();
        Mesh::build(positions, Vec::new(), polygons, Split::EarClip)
    }

    /// [`Mesh::from_polygons`] for polygons from a file: `vertex_numbers`
    /// gives each vertex the number the file gives it (or is empty), and
    /// each polygon its line.
    pub fn from_file_polygons(
        positions: Vec<DVec3>,
        vertex_numbers: Vec<u32>,
        polygons: Vec<Polygon>,
    ) -> Result<Mesh, TopologyError> {
        Mesh::build(positions, vertex_numbers, polygons, Split::EarClip)
    }

    /// [`Mesh::from_file_polygons`] for polygons known to be convex (the
    /// faces of an intersection of half-spaces): fanned from their first
    /// vertex, which is exact for a convex polygon.
    pub fn from_convex_polygons(
        positions: Vec<DVec3>,
        polygons: Vec<Polygon>,
    ) -> Result<Mesh, TopologyError> {
        Mesh::build(positions, Vec::new(), polygons, Split::Fan)
    }

    fn build(
        positions: Vec<DVec3>,
        vertex_numbers: Vec<u32>,
        polygons: Vec<Polygon>,
        split: Split,
    ) -> Result<Mesh, TopologyError> {
        let mut facets = Vec::with_capacity(polygons.len());
        let mut triangles = Vec::new();
        let mut triangle_facet = Vec::new();
        let number = |v: u32| vertex_numbers.get(v as usize).copied().unwrap_or(v + 1);
        for (index, polygon) in polygons.into_iter().enumerate() {
            let Polygon {
                vertices,
                name,
                line,
            } = polygon;
            let label = || facet_label(index, line, name.as_deref());
            // Newell's method: the polygon's area vector, exact for planar
            // polygons and a least-squares plane normal otherwise.
            let mut area = DVec3::ZERO;
            let n = vertices.len();
            for i in 0..n {
                let a = positions[vertices[i] as usize];
                let b = positions[vertices[(i + 1) % n] as usize];
                area += a.cross(b);
            }
            let len = area.length();
            if n < 3 || !(len > 0.0) || !len.is_finite() {
                return Err(TopologyError::DegenerateFacet { facet: label() });
            }
            let normal = area / len;
            let centroid = vertices
                .iter()
                .map(|&v| positions[v as usize])
                .sum::<DVec3>()
                / n as f64;
            let split_triangles = match split {
                Split::Fan => (1..n - 1)
                    .map(|i| [vertices[0], vertices[i], vertices[i + 1]])
                    .collect(),
                Split::EarClip => triangulate(&positions, &vertices, normal, centroid, number)
                    .map_err(|why| TopologyError::SelfIntersecting {
                        facet: label(),
                        why,
                    })?,
            };
            for t in split_triangles {
                triangles.push(t);
                triangle_facet.push(index as u32);
            }
            facets.push(Facet {
                normal,
                offset: normal.dot(centroid),
                vertices,
                name,
                line,
            });
        }
        Ok(Mesh {
            positions,
            facets,
            triangles,
            triangle_facet,
            vertex_numbers,
        })
    }

    /// The number the source file gives vertex `v` (1-based).
    pub fn vertex_label(&self, v: u32) -> u32 {
        self.vertex_numbers
            .get(v as usize)
            .copied()
            .unwrap_or(v + 1)
    }

    /// `facet 12 (line 40, crown)` for facet `f` (0-based).
    pub fn facet_label(&self, f: usize) -> String {
        let facet = &self.facets[f];
        facet_label(f, facet.line, facet.name.as_deref())
    }

    /// `vertices 21 and 9 (as numbered in the file) at (…) – (…)`.
    fn edge_label(&self, a: u32, b: u32) -> String {
        format!(
            "vertices {} and {}{} at {} – {}",
            self.vertex_label(a),
            self.vertex_label(b),
            if self.vertex_numbers.is_empty() {
                ""
            } else {
                " (as numbered in the file)"
            },
            self.positions[a as usize],
            self.positions[b as usize]
        )
    }

    /// Checks that every edge is shared by exactly two facets that traverse
    /// it in opposite directions (closed and consistently oriented), and
    /// that the facets wind counter-clockwise seen from outside (positive
    /// enclosed volume), so that facet normals point outward.
    pub fn check_closed_and_oriented(&self) -> Result<(), TopologyError> {
        // Directed edge -> facets using it in that direction.
        let mut directed: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (f, facet) in self.facets.iter().enumerate() {
            let n = facet.vertices.len();
            for i in 0..n {
                let a = facet.vertices[i];
                let b = facet.vertices[(i + 1) % n];
                directed.entry((a, b)).or_default().push(f);
            }
        }
        let mut edges: Vec<_> = directed.iter().collect();
        edges.sort_by_key(|(k, _)| **k);
        for (&(a, b), users) in edges {
            if users.len() > 1 {
                return Err(TopologyError::Inconsistent {
                    edge: self.edge_label(a, b),
                    f1: self.facet_label(users[0]),
                    f2: self.facet_label(users[1]),
                });
            }
            match directed.get(&(b, a)).map_or(0, Vec::len) {
                0 => {
                    return Err(TopologyError::OpenEdge {
                        edge: self.edge_label(a, b),
                        facet: self.facet_label(users[0]),
                    })
                }
                1 => {}
                count => {
                    let facets = users
                        .iter()
                        .chain(&directed[&(b, a)])
                        .take(4)
                        .map(|&f| self.facet_label(f))
                        .collect::<Vec<_>>()
                        .join(", ");
                    return Err(TopologyError::NonManifold {
                        edge: self.edge_label(a, b),
                        count: count + 1,
                        facets,
                    });
                }
            }
        }
        let volume = self.signed_volume();
        if volume <= 0.0 {
            return Err(TopologyError::InsideOut { volume });
        }
        Ok(())
    }

    /// Signed enclosed volume (divergence theorem over the triangles);
    /// positive when the facets wind counter-clockwise seen from outside.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }

    /// The plane normal of the facet that triangle `prim` belongs to.
    #[inline]
    pub fn triangle_normal(&self, prim: u32) -> DVec3 {
        self.facets[self.triangle_facet[prim as usize] as usize].normal
    }

    /// The mesh moved by an affine transform (normals by the inverse
    /// transpose, renormalized; a mirroring transform flips the winding so
    /// that normals stay outward).
    pub fn transformed(&self, m: &DAffine3) -> Mesh {
        let positions: Vec<DVec3> = self
            .positions
            .iter()
            .map(|&p| m.transform_point3(p))
            .collect();
        let normal_matrix = m.matrix3.inverse().transpose();
        let mirror = m.matrix3.determinant() < 0.0;
        let facets = self
            .facets
            .iter()
            .map(|f| {
                let normal = (normal_matrix * f.normal).normalize();
                let mut vertices = f.vertices.clone();
                if mirror {
                    vertices.reverse();
                }
                let on_plane = positions[vertices[0] as usize];
                Facet {
                    normal,
                    offset: normal.dot(on_plane),
                    vertices,
                    name: f.name.clone(),
                    line: f.line,
                }
            })
            .collect();
        let triangles = self
            .triangles
            .iter()
            .map(|&[a, b, c]| if mirror { [a, c, b] } else { [a, b, c] })
            .collect();
        Mesh {
            positions,
            facets,
            triangles,
            triangle_facet: self.triangle_facet.clone(),
            vertex_numbers: self.vertex_numbers.clone(),
        }
    }

    /// Vertices as f32 for an intersection backend.
    pub fn vertices_f32(&self) -> Vec<[f32; 3]> {
        self.positions
            .iter()
            .map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect()
    }
}

/// How polygons become triangles.
#[derive(Clone, Copy)]
enum Split {
    /// Ear clipping in the polygon's plane (any simple polygon).
    EarClip,
    /// A fan from the first vertex (convex polygons only).
    Fan,
}

/// Splits a simple polygon into triangles: a convex one by the fan from its
/// first vertex, any other by ear clipping in its plane, each
/// triangle wound like the polygon around `normal`. Refuses (saying why) a
/// polygon that passes through a vertex twice, whose edges cross or touch,
/// or whose triangles do not cover its area.
fn triangulate(
    positions: &[DVec3],
    vertices: &[u32],
    normal: DVec3,
    centroid: DVec3,
    number: impl Fn(u32) -> u32,
) -> Result<Vec<[u32; 3]>, String> {
    let n = vertices.len();
    if n == 3 {
        return Ok(vec![[vertices[0], vertices[1], vertices[2]]]);
    }
    // In-plane coordinates with u × w = normal, so a polygon winding
    // counter-clockwise around the normal has positive area.
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let pts: Vec<DVec2> = vertices
        .iter()
        .map(|&v| {
            let d = positions[v as usize] - centroid;
            DVec2::new(d.dot(u), d.dot(w))
        })
        .collect();
    let mut first_at: HashMap<u32, usize> = HashMap::with_capacity(n);
    for (i, &v) in vertices.iter().enumerate() {
        if first_at.insert(v, i).is_some() {
            return Err(format!("passes through vertex {} twice", number(v)));
        }
    }
    if let Some((i, j)) = crossing_edges(&pts) {
        let edge = |k: usize| format!("{}–{}", number(vertices[k]), number(vertices[(k + 1) % n]));
        return Err(format!(
            "has edges {} and {} that cross or touch",
            edge(i),
            edge(j)
        ));
    }
    // A simple outline that never turns clockwise is convex: the fan from
    // its first vertex is exact and is what convex faces always got (so
    // their triangles, and every image of a convex cut, stay as they were).
    // The tolerance admits noisy, nearly collinear corners of real cuts.
    // Turning once in all (exterior angles summing to 2π) rules out an
    // outline that winds twice, which crossing_edges skips past 4096 points.
    let mut turning = 0.0;
    let convex = (0..n).all(|i| {
        let (a, b, c) = (pts[i], pts[(i + 1) % n], pts[(i + 2) % n]);
        let (e1, e2) = (b - a, c - b);
        turning += e1.perp_dot(e2).atan2(e1.dot(e2));
        e1.perp_dot(e2) >= -1e-9 * e1.length() * e2.length()
    }) && (turning - std::f64::consts::TAU).abs() < 1e-6;
    if convex {
        return Ok((1..n - 1)
            .map(|i| [vertices[0], vertices[i], vertices[i + 1]])
            .collect());
    }
    let mut out: Vec<usize> = Vec::with_capacity(3 * (n - 2));
    earcut::Earcut::new().earcut(pts.iter().map(|q| [q.x, q.y]), &[] as &[usize], &mut out);
    let shoelace = (0..n)
        .map(|i| pts[i].perp_dot(pts[(i + 1) % n]))
        .sum::<f64>()
        / 2.0;
    let mut covered = 0.0;
    let triangles = out
        .chunks_exact(3)
        .map(|t| {
            let (a, b, c) = (pts[t[0]], pts[t[1]], pts[t[2]]);
            let twice = (b - a).perp_dot(c - a);
            covered += twice.abs() / 2.0;
            if twice >= 0.0 {
                [vertices[t[0]], vertices[t[1]], vertices[t[2]]]
            } else {
                [vertices[t[0]], vertices[t[2]], vertices[t[1]]]
            }
        })
        .collect();
    let extent = pts.iter().map(|q| q.length_squared()).fold(0.0, f64::max);
    if !((covered - shoelace).abs() <= 1e-9 * covered.max(shoelace.abs()) + 1e-15 * extent) {
        return Err(format!(
            "has an outline its triangles do not cover (area {shoelace:.6e}, triangles {covered:.6e})"
        ));
    }
    Ok(triangles)
}

/// The first pair of edges (by index, edge `i` from point `i` to `i + 1`) of
/// a closed 2-D outline that cross or touch, other than neighbours meeting
/// at their shared point; a neighbour folding back along its predecessor
/// counts. Quadratic, so outlines of more than 4096 points are not checked
/// (the area test of [`triangulate`] still is).
fn crossing_edges(pts: &[DVec2]) -> Option<(usize, usize)> {
    let n = pts.len();
    if n > 4096 {
        return None;
    }
    let orient = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let within = |a: DVec2, b: DVec2, p: DVec2| {
        p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
    };
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        for j in i + 1..n {
            let (c, d) = (pts[j], pts[(j + 1) % n]);
            if j == i + 1 || (i == 0 && j == n - 1) {
                // Neighbours: p → q → r through their shared point q.
                let (p, q, r) = if j == i + 1 { (a, b, d) } else { (c, d, b) };
                if orient(p, q, r) == 0.0 && (q - p).dot(r - q) < 0.0 {
                    return Some((i, j));
                }
                continue;
            }
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            let proper = o1 * o2 < 0.0 && o3 * o4 < 0.0;
            let touching = (o1 == 0.0 && within(a, b, c))
                || (o2 == 0.0 && within(a, b, d))
                || (o3 == 0.0 && within(c, d, a))
                || (o4 == 0.0 && within(c, d, b));
            if proper || touching {
                return Some((i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Mesh {
        let positions = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        // Counter-clockwise seen from outside.
        let faces = [
            [0, 2, 3, 1], // z = 0, normal -z
            [4, 5, 7, 6], // z = 1, normal +z
            [0, 1, 5, 4], // y = 0, normal -y
            [2, 6, 7, 3], // y = 1, normal +y
            [0, 4, 6, 2], // x = 0, normal -x
            [1, 3, 7, 5], // x = 1, normal +x
        ];
        Mesh::from_polygons(
            positions,
            faces.iter().map(|f| (f.to_vec(), None)).collect(),
        )
        .unwrap()
    }

    #[test]
    fn cube_is_closed_with_outward_normals_and_unit_volume() {
        let m = cube();
        m.check_closed_and_oriented().unwrap();
        assert!((m.signed_volume() - 1.0).abs() < 1e-15);
        assert_eq!(m.triangles.len(), 12);
        assert_eq!(m.facets[1].normal, DVec3::Z);
        assert_eq!(m.facets[4].normal, -DVec3::X);
        assert!((m.facets[5].offset - 1.0).abs() < 1e-15);
    }

    #[test]
    fn flipped_face_names_the_edge() {
        let mut m = cube();
        m.facets[1].vertices.reverse();
        let err = m.check_closed_and_oriented().unwrap_err();
        assert!(matches!(err, TopologyError::Inconsistent { .. }), "{err}");
    }

    #[test]
    fn missing_face_is_an_open_edge() {
        let mut m = cube();
        m.facets.pop();
        let err = m.check_closed_and_oriented().unwrap_err();
        assert!(matches!(err, TopologyError::OpenEdge { .. }), "{err}");
        assert!(err.to_string().contains("open edge"));
    }

    #[test]
    fn all_faces_reversed_is_inside_out() {
        let m = cube();
        let polys = m
            .facets
            .iter()
            .map(|f| (f.vertices.iter().rev().copied().collect(), None))
            .collect();
        let m = Mesh::from_polygons(m.positions.clone(), polys).unwrap();
        assert!(matches!(
            m.check_closed_and_oriented(),
            Err(TopologyError::InsideOut { .. })
        ));
    }

    #[test]
    fn mirroring_keeps_normals_outward() {
        let m = cube().transformed(&DAffine3::from_scale(DVec3::new(-2.0, 1.0, 1.0)));
        m.check_closed_and_oriented().unwrap();
        assert!((m.signed_volume() - 2.0).abs() < 1e-14);
        // The face that was at x = 1 with normal +x is now at x = -2, normal -x.
        assert!((m.facets[5].normal + DVec3::X).length() < 1e-15);
        assert!((m.facets[5].offset - 2.0).abs() < 1e-15);
    }

    #[test]
    fn newell_normal_of_a_slightly_warped_facet_uses_all_vertices() {
        // A unit square whose fourth vertex is lifted by h. The fan triangle
        // (0,1,2) alone would give exactly +z; Newell's sum of p_i × p_{i+1}
        // is (h, −h, 2) by hand, so the normal is (h, −h, 2)/sqrt(2h² + 4).
        let h = 1e-4;
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, h),
        ];
        let m = Mesh::from_polygons(positions, vec![(vec![0, 1, 2, 3], None)]).unwrap();
        let expected = DVec3::new(h, -h, 2.0) / (2.0 * h * h + 4.0).sqrt();
        assert!((m.facets[0].normal - expected).length() < 1e-15);
        assert_eq!(m.triangle_normal(0), m.triangle_normal(1));
    }
}
