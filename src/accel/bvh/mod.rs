//! The pure-Rust backend of [`Intersector`]: an 8-wide SAH BVH over
//! four-triangle f32 packets, built in parallel, traced one ray at a time.
//!
//! Design in brief (docs/accel.md has the reasons and the measurements):
//! a binary tree by binned SAH down to one-packet leaves, collapsed into
//! 8-wide nodes by the SAH-optimal dynamic programme, which also decides
//! the leaves ([`BvhOptions`]: 16 bins, a node visit costing 4 packet
//! tests, at most 4 packets per leaf). Traversal and the triangle test
//! run in f32 with no absolute epsilon anywhere, so a scene scaled by 1e-5
//! or 1e5 finds the same hits; the winning hit is recomputed in f64
//! against the caller's ray, and the f64 `t` decides the ray interval.
//!
//! Pieces, each in its own module:
//! - [`lanes`]: four and eight f32 lanes with element-wise operators
//!   (autovectorized, no `unsafe`).
//! - [`sah`]: the binary tree by binned SAH (Wald 2007), in parallel.
//! - [`wide`]: the 8-wide node layout and the collapse from binary
//!   (Ylitie, Karras & Laine 2017).
//! - [`ray`]: the f64 ray turned into f32 traversal constants.
//! - [`triangle`]: four-triangle packets and the watertight test (Woop,
//!   Benthin & Wald 2013); the winning hit recomputed in f64 (Möller &
//!   Trumbore 1997).
//! - [`traverse`]: the closest-hit traversal with the robust slab test
//!   (Ize 2013).

mod lanes;
mod ray;
mod sah;
mod traverse;
mod triangle;
mod wide;

use super::{validate_meshes, AccelError, Hit, Intersector, Ray, TriangleMesh};
use ray::PreparedRay;
use sah::{Aabb, Primitives, SahConfig};
pub use traverse::TraversalCounts;
use wide::{ChildRef, WideBvh, WideConfig};

/// A BVH over a set of triangle meshes, immutable once built and safe to
/// trace from many threads.
pub struct RustBvh {
    bvh: WideBvh,
    triangles: usize,
}

/// Sizes of a built BVH, for logs and benchmarks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhStats {
    pub triangles: usize,
    pub nodes: usize,
    pub packets: usize,
    /// Bytes of nodes and packets.
    pub bytes: usize,
}

/// How the BVH is built. The defaults are what the benchmark chose
/// (module documentation); the fields are public for tuning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhOptions {
    /// SAH bins per axis in the binary build (2 to 32).
    pub bins: usize,
    /// SAH cost of a node visit relative to a four-triangle packet test,
    /// in the collapse to the wide tree.
    pub node_cost: f64,
    /// Most four-triangle packets in one leaf (1 to 16).
    pub max_leaf_packets: usize,
}

impl Default for BvhOptions {
    fn default() -> BvhOptions {
        BvhOptions {
            bins: 16,
            node_cost: 4.0,
            max_leaf_packets: 4,
        }
    }
}

impl RustBvh {
    /// Builds the BVH on `threads` threads (0: rayon's current pool, which is
    /// all cores unless the caller configured it).
    pub fn build(meshes: &[TriangleMesh<'_>], threads: usize) -> Result<RustBvh, AccelError> {
        RustBvh::build_with(meshes, threads, &BvhOptions::default())
    }

    /// [`RustBvh::build`] with other build options.
    pub fn build_with(
        meshes: &[TriangleMesh<'_>],
        threads: usize,
        options: &BvhOptions,
    ) -> Result<RustBvh, AccelError> {
        validate_meshes(meshes)?;
        let total: usize = meshes.iter().map(|m| m.triangles.len()).sum();
        // Packets are at most ⌈n/4⌉ plus one partly filled per leaf; a leaf
        // has at least one triangle, so n packets always suffice.
        if total > ChildRef::MAX_TOTAL_PACKETS || total > u32::MAX as usize {
            return Err(AccelError::Backend {
                backend: "rust",
                message: format!(
                    "{total} triangles: at most {} are supported",
                    ChildRef::MAX_TOTAL_PACKETS
                ),
            });
        }
        let work = || build_in_current_pool(meshes, total, options);
        if threads == 0 {
            Ok(work())
        } else {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| AccelError::Backend {
                    backend: "rust",
                    message: format!("cannot start {threads} build threads: {e}"),
                })?;
            Ok(pool.install(work))
        }
    }

    /// Node, packet and byte counts.
    pub fn stats(&self) -> BvhStats {
        BvhStats {
            triangles: self.triangles,
            nodes: self.bvh.nodes.len(),
            packets: self.bvh.packets.len(),
            bytes: std::mem::size_of_val(self.bvh.nodes.as_slice())
                + std::mem::size_of_val(self.bvh.packets.as_slice()),
        }
    }
}

fn build_in_current_pool(
    meshes: &[TriangleMesh<'_>],
    total: usize,
    options: &BvhOptions,
) -> RustBvh {
    use rayon::prelude::*;
    let mut triangles = Vec::with_capacity(total);
    for (geom, mesh) in meshes.iter().enumerate() {
        triangles.par_extend(mesh.triangles.par_iter().enumerate().map(|(prim, t)| {
            let v = t.map(|i| mesh.vertices[i as usize]);
            (geom as u32, prim as u32, v)
        }));
    }
    let boxes: Vec<Aabb> = triangles
        .par_iter()
        .map(|(_, _, v)| Aabb::of_points(v))
        .collect();
    let centroids: Vec<[f32; 3]> = boxes.par_iter().map(Aabb::center).collect();
    let prims = Primitives {
        boxes: &boxes,
        centroids: &centroids,
    };
    let (root, order) = sah::build(&prims, &SahConfig { bins: options.bins });
    let wide = WideConfig {
        node_cost: options.node_cost,
        max_leaf_packets: options.max_leaf_packets,
    };
    let bvh = wide::collapse(&root, &order, &triangles, &wide);
    RustBvh {
        bvh,
        triangles: total,
    }
}

impl RustBvh {
    /// [`Intersector::intersect`], also counting the nodes and packets the
    /// traversal tested (for benchmarks and tuning; a little slower).
    pub fn intersect_counting(&self, ray: &Ray) -> (Option<Hit>, TraversalCounts) {
        let mut counts = TraversalCounts::default();
        let hit = self.intersect_with(ray, &mut counts);
        (hit, counts)
    }

    #[inline(always)]
    fn intersect_with<C: traverse::Counter>(&self, ray: &Ray, counter: &mut C) -> Option<Hit> {
        let mut prepared = PreparedRay::new(ray)?;
        let tmin = ray.tmin.max(0.0);
        loop {
            let (p, lane_hit) = traverse::closest_hit(&self.bvh, &prepared, counter)?;
            let packet = &self.bvh.packets[p];
            let lane = lane_hit.lane;
            let t32 = lane_hit.t as f64 * prepared.t_to_caller;
            let (t, u, v, ng) = packet.refine(lane, ray, t32);
            // The f32 interval was rounded outward; the f64 t decides. A
            // closest hit beyond tmax means no hit; one before tmin (a ray
            // leaving a surface it starts on, say) is skipped by tracing
            // again from just past it.
            if t > ray.tmax {
                return None;
            }
            if t < tmin {
                // Past this hit (whose f32 t may sit just below the f32
                // tmin: the interval test compares t·det, not t).
                prepared.tmin = ray::next_f32_up(lane_hit.t.max(prepared.tmin));
                if !(prepared.tmin <= prepared.tmax) {
                    return None;
                }
                continue;
            }
            return Some(Hit {
                t,
                geom: packet.geom[lane],
                prim: packet.prim[lane],
                u,
                v,
                ng,
            });
        }
    }
}

impl Intersector for RustBvh {
    #[inline]
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_with(ray, &mut ())
    }

    fn name(&self) -> &'static str {
        "rust"
    }
}
