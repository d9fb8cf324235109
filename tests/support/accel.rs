//! What the intersection tests share: the shipped gems, a random triangle
//! soup, ray generators, and an f64 reference for one ray and one triangle.

use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use spar::accel::{Ray, TriangleMesh};
use spar::geometry::Mesh;
use std::path::Path;

/// A mesh with the f32 vertices a backend sees.
pub struct TestMesh {
    pub name: String,
    pub vertices: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// The polygon mesh it came from (facet planes for inside tests), if
    /// any.
    pub mesh: Option<Mesh>,
}

impl TestMesh {
    pub fn view(&self) -> TriangleMesh<'_> {
        TriangleMesh {
            vertices: &self.vertices,
            triangles: &self.triangles,
        }
    }

    pub fn vertex(&self, i: u32) -> DVec3 {
        let v = self.vertices[i as usize];
        DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
    }

    /// The triangle's vertices in f64 (exact: they are f32).
    pub fn corners(&self, prim: u32) -> [DVec3; 3] {
        self.triangles[prim as usize].map(|i| self.vertex(i))
    }

    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| {
                let p = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
                (lo.min(p), hi.max(p))
            },
        )
    }

    /// Length of the bounding box's diagonal: the scale that "relative"
    /// distances are relative to.
    pub fn size(&self) -> f64 {
        let (lo, hi) = self.bounds();
        (hi - lo).length()
    }
}

/// Every gem in `scenes/gems/`, checked closed and convex-or-not by its
/// loader, with f32 vertices.
pub fn gems() -> Vec<TestMesh> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 6, "gems missing from {}", dir.display());
    paths
        .iter()
        .map(|p| {
            let mesh = spar::geometry::load_obj(p).unwrap();
            mesh.check_closed_and_oriented().unwrap();
            TestMesh {
                name: p.file_stem().unwrap().to_string_lossy().into_owned(),
                vertices: mesh.vertices_f32(),
                triangles: mesh.triangles.clone(),
                mesh: Some(mesh),
            }
        })
        .collect()
}

/// `n` small random triangles, one in each cell of a jittered grid over the
/// unit cube (each within the inner 80 % of its cell, so no two touch and
/// no two are hit at nearly the same t), random in size, shape and
/// orientation; a few are slivers.
pub fn triangle_soup(n: usize, seed: u64) -> TestMesh {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let side = (n as f64).cbrt().ceil() as usize;
    let cell = 1.0 / side as f64;
    let mut vertices = Vec::with_capacity(3 * n);
    let mut triangles = Vec::with_capacity(n);
    'cells: for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                if triangles.len() == n {
                    break 'cells;
                }
                let corner = DVec3::new(i as f64, j as f64, k as f64) * cell;
                let base = vertices.len() as u32;
                let sliver = rng.gen_bool(0.05);
                let a = DVec3::new(rng.gen(), rng.gen(), rng.gen());
                let b = DVec3::new(rng.gen(), rng.gen(), rng.gen());
                let c = if sliver {
                    a + (b - a) * rng.gen::<f64>() + DVec3::splat(1e-3 * rng.gen::<f64>())
                } else {
                    DVec3::new(rng.gen(), rng.gen(), rng.gen())
                };
                for p in [a, b, c] {
                    let p = corner
                        + (DVec3::splat(0.1) + 0.8 * p.clamp(DVec3::ZERO, DVec3::ONE)) * cell;
                    vertices.push(p.as_vec3().to_array());
                }
                triangles.push([base, base + 1, base + 2]);
            }
        }
    }
    TestMesh {
        name: format!("soup{n}"),
        vertices,
        triangles,
        mesh: None,
    }
}

/// A uniformly random unit vector.
pub fn random_direction(rng: &mut impl Rng) -> DVec3 {
    loop {
        let d = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        let l2 = d.length_squared();
        if l2 <= 1.0 && l2 > 1e-4 {
            return d / l2.sqrt();
        }
    }
}

/// Rays from a sphere of twice the bounding radius around the mesh toward
/// random points of its bounding box (most hit; those near the silhouette
/// test the edges; some miss).
pub fn rays_from_outside(m: &TestMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let (lo, hi) = m.bounds();
    let center = (lo + hi) / 2.0;
    let radius = (hi - lo).length() / 2.0;
    (0..n)
        .map(|_| {
            let o = center + 2.0 * radius * random_direction(&mut rng);
            let target = lo + (hi - lo) * DVec3::new(rng.gen(), rng.gen(), rng.gen());
            Ray::new(o, target - o)
        })
        .collect()
}

/// Whether `p` is inside the closed convex mesh by at least `margin` from
/// every facet plane.
pub fn inside_convex(mesh: &Mesh, p: DVec3, margin: f64) -> bool {
    mesh.facets
        .iter()
        .all(|f| f.normal.dot(p) <= f.offset - margin)
}

/// Rays from random points inside a closed convex gem (at least 10⁻⁴ of
/// its size from every facet plane) in random directions: every one must
/// hit a back face.
pub fn rays_from_inside(m: &TestMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mesh = m.mesh.as_ref().expect("a gem");
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let (lo, hi) = m.bounds();
    let margin = 1e-4 * m.size();
    let mut rays = Vec::with_capacity(n);
    while rays.len() < n {
        let o = lo + (hi - lo) * DVec3::new(rng.gen(), rng.gen(), rng.gen());
        if inside_convex(mesh, o, margin) {
            // Unnormalized directions of random length: t is in their units.
            let d = random_direction(&mut rng) * rng.gen_range(0.25..4.0);
            rays.push(Ray::new(o, d));
        }
    }
    rays
}

/// The exact-to-f64 intersection of a ray's line with a triangle's plane,
/// and where it falls: `(t, distance from the triangle's boundary, inside)`
/// (Möller–Trumbore in f64 for t and the barycentrics; the distance is
/// measured in 3D from the plane point to the nearest edge segment).
pub fn reference(ray: &Ray, c: [DVec3; 3]) -> Option<(f64, f64, bool)> {
    let e1 = c[1] - c[0];
    let e2 = c[2] - c[0];
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let s = ray.origin - c[0];
    let q = s.cross(e1);
    let u = s.dot(p) / det;
    let v = ray.dir.dot(q) / det;
    let t = e2.dot(q) / det;
    let point = ray.at(t);
    let inside = u >= 0.0 && v >= 0.0 && u + v <= 1.0;
    let edge = (0..3)
        .map(|i| segment_distance(point, c[i], c[(i + 1) % 3]))
        .fold(f64::INFINITY, f64::min);
    Some((t, edge, inside))
}

/// Distance from `p` to the segment `a`–`b`.
pub fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let s = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + s * ab)).length()
}
