//! The Embree 3 backend of [`Intersector`]: meshes go to Embree as f32,
//! hits come back as f64.

use super::{validate_meshes, AccelError, Hit, Intersector, Ray, TriangleMesh};
use crate::native::embree::{CommittedScene, Device, RayF32};
use glam::DVec3;

/// Embree's BVH over a set of triangle meshes.
pub struct EmbreeAccel {
    scene: CommittedScene,
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
            _device: device,
        })
    }
}

impl Intersector for EmbreeAccel {
    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
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
        Some(Hit {
            t: hit.t as f64,
            geom: hit.geom,
            prim: hit.prim,
            u: hit.u as f64,
            v: hit.v as f64,
            ng: DVec3::new(hit.ng[0] as f64, hit.ng[1] as f64, hit.ng[2] as f64),
        })
    }

    fn name(&self) -> &'static str {
        "embree"
    }
}
