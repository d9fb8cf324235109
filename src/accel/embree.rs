//! The Embree 3 backend of [`Intersector`]: meshes go to Embree as f32,
//! hits come back as f64, the winning hit recomputed in f64 against the
//! caller's ray (as the Rust BVH does), so a hit point is as exact far
//! from the ray's origin as near it.

use super::{traceable, validate_meshes, AccelError, Hit, Intersector, Ray, TriangleMesh};
use crate::native::embree::{CommittedScene, Device, RayF32};
use glam::DVec3;

/// One mesh's f32 vertices and triangles.
type StoredMesh = (Vec<[f32; 3]>, Vec<[u32; 3]>);

/// Embree's BVH over a set of triangle meshes.
pub struct EmbreeAccel {
    scene: CommittedScene,
    /// The f32 vertices and triangles Embree was given, per mesh, for the
    /// f64 refinement of hits.
    meshes: Vec<StoredMesh>,
    _device: Device,
}

impl EmbreeAccel {
    /// Builds the acceleration structure. `threads` limits Embree's build
    /// threads (0: Embree's default, all cores) so that Embree and rayon do
    /// not oversubscribe the cores; `isa` pins Embree's instruction set
    /// (e.g. "sse4.2", "avx2") so renders on different machines hit the same
    /// triangles at edges.
    pub fn build(
        meshes: &[TriangleMesh<'_>],
        threads: usize,
        isa: Option<&str>,
    ) -> Result<EmbreeAccel, AccelError> {
        validate_meshes(meshes)?;
        let backend = |e: crate::native::embree::EmbreeError| AccelError::Backend {
            backend: "embree",
            message: e.to_string(),
        };
        let mut config = format!("threads={threads}");
        if let Some(isa) = isa {
            config.push_str(&format!(",isa={isa}"));
        }
        let device = Device::new(&config).map_err(backend)?;
        let mut scene = device.new_scene().map_err(backend)?;
        for mesh in meshes {
            scene
                .add_triangles(mesh.vertices, mesh.triangles)
                .map_err(backend)?;
        }
        let scene = scene.commit().map_err(backend)?;
        Ok(EmbreeAccel {
            scene,
            meshes: meshes
                .iter()
                .map(|m| (m.vertices.to_vec(), m.triangles.to_vec()))
                .collect(),
            _device: device,
        })
    }

    /// t, u, v and the geometric normal of triangle `prim` of mesh `geom`
    /// along `ray`, by Möller & Trumbore (JGT 2(1), 1997) in f64 on the
    /// stored f32 vertices; `None` when they are not finite (a ray in the
    /// triangle's plane).
    fn refine(&self, geom: u32, prim: u32, ray: &Ray) -> Option<(f64, f64, f64, DVec3)> {
        let (vertices, triangles) = self.meshes.get(geom as usize)?;
        let tri = triangles.get(prim as usize)?;
        let p = |i: usize| {
            let v = vertices[tri[i] as usize];
            DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
        };
        let v0 = p(0);
        let e1 = p(1) - v0;
        let e2 = p(2) - v0;
        let ng = e1.cross(e2);
        let pv = ray.dir.cross(e2);
        let inv = 1.0 / e1.dot(pv);
        let s = ray.origin - v0;
        let q = s.cross(e1);
        let (u, v, t) = (s.dot(pv) * inv, ray.dir.dot(q) * inv, e2.dot(q) * inv);
        (u.is_finite() && v.is_finite() && t.is_finite()).then_some((t, u, v, ng))
    }
}

impl Intersector for EmbreeAccel {
    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        // Embree asserts on rays it cannot trace and aborts the process:
        // such a ray has no hit here (the integrator counts it as lost).
        if !traceable(ray) {
            return None;
        }
        let f = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        let tfar = if ray.tmax.is_finite() {
            ray.tmax as f32
        } else {
            f32::INFINITY
        };
        let hit = self.scene.intersect(&RayF32 {
            origin: f(ray.origin),
            dir: f(ray.dir),
            tnear: ray.tmin.max(0.0) as f32,
            tfar,
        })?;
        // Embree's f32 t is good to a few ulps of the distance from the
        // origin: far from the origin that exceeds the offset secondary rays
        // start at. The f64 t is good to f64 rounding at any distance.
        let (t, u, v, ng) = self.refine(hit.geom, hit.prim, ray).unwrap_or((
            hit.t as f64,
            hit.u as f64,
            hit.v as f64,
            DVec3::new(hit.ng[0] as f64, hit.ng[1] as f64, hit.ng[2] as f64),
        ));
        Some(Hit {
            t,
            geom: hit.geom,
            prim: hit.prim,
            u,
            v,
            ng,
        })
    }

    fn name(&self) -> &'static str {
        "embree"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let v: Vec<[f32; 3]> = (0..8)
            .map(|i| {
                [
                    (i & 1) as f32 * 2.0 - 1.0,
                    ((i >> 1) & 1) as f32 * 2.0 - 1.0,
                    ((i >> 2) & 1) as f32 * 2.0 - 1.0,
                ]
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        (v, t)
    }

    #[test]
    fn rays_embree_cannot_trace_miss_instead_of_aborting() {
        // Embree 3 asserts `ray.valid()` (|component| ≤ 1.844e18, finite
        // tnear/tfar) and aborts the process: before this guard each of
        // these rays killed the test binary with SIGABRT.
        let (v, t) = cube();
        let accel = EmbreeAccel::build(
            &[TriangleMesh {
                vertices: &v,
                triangles: &t,
            }],
            1,
            None,
        )
        .unwrap();
        let good = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z);
        assert!((accel.intersect(&good).unwrap().t - 4.0).abs() < 1e-12);
        let bad = [
            Ray::new(DVec3::new(1e30, 0.0, 0.0), DVec3::NEG_X),
            Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1e30)),
            Ray::new(DVec3::new(f64::NAN, 0.0, 5.0), DVec3::NEG_Z),
            Ray::new(DVec3::new(0.0, 0.0, f64::INFINITY), DVec3::NEG_Z),
            Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO),
            Ray {
                tmin: f64::NAN,
                ..good
            },
            Ray {
                tmax: f64::NAN,
                ..good
            },
        ];
        for ray in bad {
            assert!(!traceable(&ray), "{ray:?}");
            assert_eq!(accel.intersect(&ray), None, "{ray:?}");
        }
    }

    #[test]
    fn hits_far_from_the_origin_are_exact_in_f64() {
        // From 1000 units away Embree's f32 t is off by ~1e-4 (a few ulps
        // of 1000): more than the offset a secondary ray starts at. The
        // refined t puts the point on the face to f64 rounding.
        let (v, t) = cube();
        let accel = EmbreeAccel::build(
            &[TriangleMesh {
                vertices: &v,
                triangles: &t,
            }],
            1,
            None,
        )
        .unwrap();
        let dir = DVec3::new(0.0003, 0.6, -0.8).normalize();
        let target = DVec3::new(0.123456, 0.345678, 1.0);
        let origin = target - 1000.0 * dir;
        let hit = accel.intersect(&Ray::new(origin, dir)).unwrap();
        let p = origin + hit.t * dir;
        assert!((p.z - 1.0).abs() < 1e-12, "{} off the face", p.z - 1.0);
    }
}
