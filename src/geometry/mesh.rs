//! Polygon meshes of cut gems: flat facets, each split into triangles that
//! all carry the facet's exact plane normal.
//!
//! A real cut has near-meeting facets whose tiny triangles would get normals
//! off by 1e-4 rad if each triangle's normal came from its own three
//! vertices; a facet's normal comes from all of its vertices (Newell's
//! method), once, and every triangle of the facet uses it.

use glam::{DAffine3, DVec3};
use std::collections::HashMap;

/// One flat facet: a convex or concave polygon, fanned into triangles.
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
}

/// Why a mesh is not a closed, consistently oriented surface.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TopologyError {
    #[error("open edge between vertices {a} and {b} (1-based, as in the file) at {pa} – {pb}: only one facet uses it, so the mesh is not closed")]
    OpenEdge {
        a: u32,
        b: u32,
        pa: DVec3,
        pb: DVec3,
    },
    #[error("edge between vertices {a} and {b} (1-based) at {pa} – {pb} is used in the same direction by two facets ({f1} and {f2}): the facets are not consistently oriented")]
    Inconsistent {
        a: u32,
        b: u32,
        pa: DVec3,
        pb: DVec3,
        f1: usize,
        f2: usize,
    },
    #[error("edge between vertices {a} and {b} (1-based) is shared by {count} facets: the mesh is not a manifold")]
    NonManifold { a: u32, b: u32, count: usize },
    #[error("facet {facet} is degenerate (its vertices do not span a plane)")]
    DegenerateFacet { facet: usize },
    #[error("the mesh encloses negative volume ({volume:.3e}): its facets wind clockwise seen from outside")]
    InsideOut { volume: f64 },
}

impl Mesh {
    /// Builds a mesh from polygons (each a list of vertex indices, at least
    /// three). Facet normals come from Newell's method over all vertices of
    /// the polygon; polygons are fanned from their first vertex.
    pub fn from_polygons(
        positions: Vec<DVec3>,
        polygons: Vec<(Vec<u32>, Option<String>)>,
    ) -> Result<Mesh, TopologyError> {
        let mut facets = Vec::with_capacity(polygons.len());
        let mut triangles = Vec::new();
        let mut triangle_facet = Vec::new();
        for (index, (vertices, name)) in polygons.into_iter().enumerate() {
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
                return Err(TopologyError::DegenerateFacet { facet: index });
            }
            let normal = area / len;
            let centroid = vertices
                .iter()
                .map(|&v| positions[v as usize])
                .sum::<DVec3>()
                / n as f64;
            for i in 1..n - 1 {
                triangles.push([vertices[0], vertices[i], vertices[i + 1]]);
                triangle_facet.push(index as u32);
            }
            facets.push(Facet {
                normal,
                offset: normal.dot(centroid),
                vertices,
                name,
            });
        }
        Ok(Mesh {
            positions,
            facets,
            triangles,
            triangle_facet,
        })
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
        let p = |i: u32| self.positions[i as usize];
        let mut edges: Vec<_> = directed.iter().collect();
        edges.sort_by_key(|(k, _)| **k);
        for (&(a, b), users) in edges {
            if users.len() > 1 {
                return Err(TopologyError::Inconsistent {
                    a: a + 1,
                    b: b + 1,
                    pa: p(a),
                    pb: p(b),
                    f1: users[0],
                    f2: users[1],
                });
            }
            match directed.get(&(b, a)).map_or(0, Vec::len) {
                0 => {
                    return Err(TopologyError::OpenEdge {
                        a: a + 1,
                        b: b + 1,
                        pa: p(a),
                        pb: p(b),
                    })
                }
                1 => {}
                count => {
                    return Err(TopologyError::NonManifold {
                        a: a + 1,
                        b: b + 1,
                        count: count + 1,
                    })
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
