//! Ray–triangle intersection: the trait the integrator traces through, and
//! the backends behind it (Embree 3 when built with the `native` feature; a
//! pure-Rust BVH later).
//!
//! Geometry is handed to a backend as triangle meshes in world space. A hit
//! reports which mesh (`geom`) and which triangle (`prim`) was hit and the
//! ray parameter `t`; the integrator looks up exact (f64) facet normals and
//! media from those ids, so backends may work in f32 internally.

use glam::DVec3;

pub mod bvh;
#[cfg(feature = "native")]
pub mod embree;

/// A ray `origin + t * dir` for `t` in `[tmin, tmax]`. `dir` need not be
/// normalized; `t` is in units of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
    pub tmin: f64,
    pub tmax: f64,
}

impl Ray {
    /// A ray over `[0, ∞)`.
    pub fn new(origin: DVec3, dir: DVec3) -> Ray {
        Ray {
            origin,
            dir,
            tmin: 0.0,
            tmax: f64::INFINITY,
        }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.dir
    }
}

/// The closest hit along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, in units of the ray's direction.
    pub t: f64,
    /// Index of the mesh, in the order the meshes were given.
    pub geom: u32,
    /// Index of the triangle within its mesh.
    pub prim: u32,
    /// Barycentric coordinates of the hit (weights of vertices 1 and 2).
    pub u: f64,
    pub v: f64,
    /// Geometric normal as the backend computed it, (v1 − v0) × (v2 − v0)
    /// with the triangle's winding, not normalized.
    pub ng: DVec3,
}

/// A triangle mesh in world space, as handed to a backend.
#[derive(Clone, Copy, Debug)]
pub struct TriangleMesh<'a> {
    pub vertices: &'a [[f32; 3]],
    pub triangles: &'a [[u32; 3]],
}

/// Errors from building an acceleration structure.
#[derive(Debug, thiserror::Error)]
pub enum AccelError {
    #[error("mesh {mesh}: triangle {triangle} refers to vertex {vertex}, but the mesh has {count} vertices")]
    IndexOutOfRange {
        mesh: usize,
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    #[error("mesh {mesh}: vertex {vertex} is not finite")]
    NonFiniteVertex { mesh: usize, vertex: usize },
    #[error("{backend}: {message}")]
    Backend {
        backend: &'static str,
        message: String,
    },
}

/// Something rays can be traced against. Implementations are immutable once
/// built and safe to query from many threads at once.
pub trait Intersector: Send + Sync {
    /// The closest hit with `t` in `[ray.tmin, ray.tmax]`, both faces of
    /// every triangle counted, or `None` for a miss.
    fn intersect(&self, ray: &Ray) -> Option<Hit>;

    /// A short name for tables and logs ("embree", "rust").
    fn name(&self) -> &'static str;
}

/// Checks meshes before a backend sees them: indices in range, vertices
/// finite. Backends call it so that every backend rejects the same input.
pub fn validate_meshes(meshes: &[TriangleMesh<'_>]) -> Result<(), AccelError> {
    for (mesh, m) in meshes.iter().enumerate() {
        if let Some(vertex) = m
            .vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(AccelError::NonFiniteVertex { mesh, vertex });
        }
        for (triangle, tri) in m.triangles.iter().enumerate() {
            if let Some(&vertex) = tri.iter().find(|&&i| i as usize >= m.vertices.len()) {
                return Err(AccelError::IndexOutOfRange {
                    mesh,
                    triangle,
                    vertex,
                    count: m.vertices.len(),
                });
            }
        }
    }
    Ok(())
}
