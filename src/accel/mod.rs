//! Ray–triangle intersection: the trait the integrator traces through, and
//! the backends behind it: Embree 3 when built with the `native` feature,
//! and spar's own BVH in pure Rust ([`bvh`]) in every build; [`build`]
//! makes the one `--accel` names. docs/accel.md compares them.
//!
//! Geometry is handed to a backend as triangle meshes in world space. A hit
//! reports which mesh (`geom`) and which triangle (`prim`) was hit and the
//! ray parameter `t`; the integrator looks up exact (f64) facet normals and
//! media from those ids, so backends may work in f32 internally.

use glam::DVec3;

pub mod bvh;
pub mod convex;
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

/// Largest coordinate magnitude of a ray's origin and direction that every
/// backend takes: Embree 3 asserts `|x| ≤ 1.844e18` (its `FLT_LARGE`) on
/// every component and aborts the process otherwise; spar stays well below.
pub const MAX_RAY_COMPONENT: f64 = 1e18;

/// Whether a ray can be handed to a backend: origin and direction finite
/// and within [`MAX_RAY_COMPONENT`] after rounding to f32, the direction
/// not zero, and `tmin ≤ tmax` with neither NaN. Backends answer `None` for
/// any other ray instead of tracing it; the integrator counts such a ray as
/// lost.
#[inline]
pub fn traceable(ray: &Ray) -> bool {
    let ok = |v: DVec3| v.is_finite() && v.abs().max_element() <= MAX_RAY_COMPONENT;
    ok(ray.origin) && ok(ray.dir) && (ray.dir.as_vec3() != glam::Vec3::ZERO) && ray.tmin <= ray.tmax
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

/// Which intersection backend to build: `--accel embree|rust`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum AccelKind {
    /// Embree 3 (only in builds with the `native` feature).
    Embree,
    /// spar's own BVH, in pure Rust (every build).
    Rust,
}

impl AccelKind {
    /// Every kind, in the order `--help` lists them.
    pub const ALL: [AccelKind; 2] = [AccelKind::Embree, AccelKind::Rust];

    /// The kind named `name` ("embree" or "rust", any case), or an error
    /// that lists the names.
    pub fn parse(name: &str) -> Result<AccelKind, String> {
        AccelKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| {
                format!("unknown intersection backend {name:?}: expected \"embree\" or \"rust\"")
            })
    }

    /// The name used on the command line and by [`Intersector::name`].
    pub fn name(self) -> &'static str {
        match self {
            AccelKind::Embree => "embree",
            AccelKind::Rust => "rust",
        }
    }

    /// Whether this build can make this backend (Embree needs `native`).
    pub fn available(self) -> bool {
        match self {
            AccelKind::Embree => cfg!(feature = "native"),
            AccelKind::Rust => true,
        }
    }
}

impl Default for AccelKind {
    /// Embree where it is built in, else the Rust BVH.
    fn default() -> AccelKind {
        if AccelKind::Embree.available() {
            AccelKind::Embree
        } else {
            AccelKind::Rust
        }
    }
}

impl std::fmt::Display for AccelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for AccelKind {
    type Err = String;
    fn from_str(s: &str) -> Result<AccelKind, String> {
        AccelKind::parse(s)
    }
}

/// Builds the chosen backend over `meshes` with `threads` build threads (0:
/// all cores). Both backends reject the same invalid meshes
/// ([`validate_meshes`]); asking for Embree in a build without the `native`
/// feature is an [`AccelError::Backend`] that says so.
pub fn build(
    kind: AccelKind,
    meshes: &[TriangleMesh<'_>],
    threads: usize,
) -> Result<Box<dyn Intersector>, AccelError> {
    match kind {
        #[cfg(feature = "native")]
        AccelKind::Embree => Ok(Box::new(embree::EmbreeAccel::build(meshes, threads, None)?)),
        #[cfg(not(feature = "native"))]
        AccelKind::Embree => {
            let _ = (meshes, threads);
            Err(AccelError::Backend {
                backend: "embree",
                message: "this spar was built without the `native` feature, so Embree is not \
                          available; use `--accel rust`"
                    .into(),
            })
        }
        AccelKind::Rust => Ok(Box::new(bvh::RustBvh::build(meshes, threads)?)),
    }
}
