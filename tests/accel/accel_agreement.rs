//! The Rust BVH against Embree, ray by ray: millions of random rays at every
//! shipped gem (from outside, aimed at it, and from inside, where every ray
//! must hit a back face), at a random triangle soup, and at a scene of
//! several meshes. Hit or miss, mesh and triangle must agree, and t must
//! agree to 1e-5, except where the closest hit lies within 1e-6 (relative to
//! the scene's size) of an edge of its triangle: there either neighbour is
//! right, and f32 rounding decides. Those rays are counted and reported.
#![cfg(feature = "native")]

use crate::support::accel as accel_common;

use accel_common::{gems, rays_from_inside, rays_from_outside, reference, triangle_soup, TestMesh};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use spar::accel::{build, AccelKind, Hit, Intersector, Ray, TriangleMesh};

/// Distance from an edge below which f32 rounding may pick either
/// triangle, relative to the scene's size.
const EDGE: f64 = 1e-6;
/// Agreement of t, relative: |t_embree − t_rust| · |cos θ| ≤ T_REL · (t +
/// size/|d|). Two allowances, both from Embree's f32: a grazing ray's t is
/// ill-conditioned by 1/|cos θ| (θ between the ray and the normal), so the
/// difference is measured across the surface; and Embree rounds origin and
/// vertices to f32, an absolute error at the scale of the coordinates, so
/// the hit point is not asked to be better than 1e-5 of the scene's size.
const T_REL: f64 = 1e-6;
/// The Rust backend recomputes t and ng in f64: they must match an
/// independent f64 computation for the triangle it names to this (relative;
/// for t as above but with no allowance for grazing).
const REFERENCE: f64 = 1e-12;
/// u and v are the weights of vertices 1 and 2 in both backends: on rays
/// that are not grazing (|cos θ| > 0.1) they agree to this. Embree's f32
/// barycentrics of slivers are off by up to 2.4e-3 here; a different
/// convention would be off by O(1).
const UV: f64 = 1e-2;

#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    hits: usize,
    /// Rays whose closest hit is within EDGE of its triangle's boundary.
    near_edge: usize,
    /// Of those, how many the backends answered differently.
    near_edge_differing: usize,
    /// Rays that must hit (from inside a closed mesh) but missed.
    embree_lost: usize,
    rust_lost: usize,
    disagreements: Vec<String>,
    worst_t: f64,
    worst_t_rel_to_t: f64,
    worst_rust_vs_reference: f64,
    worst_uv: f64,
    worst_ng: f64,
    worst_rust_ng: f64,
}

impl Tally {
    fn merge(mut self, o: Tally) -> Tally {
        self.rays += o.rays;
        self.hits += o.hits;
        self.near_edge += o.near_edge;
        self.near_edge_differing += o.near_edge_differing;
        self.embree_lost += o.embree_lost;
        self.rust_lost += o.rust_lost;
        self.disagreements.extend(o.disagreements);
        self.worst_t = self.worst_t.max(o.worst_t);
        self.worst_t_rel_to_t = self.worst_t_rel_to_t.max(o.worst_t_rel_to_t);
        self.worst_rust_vs_reference = self.worst_rust_vs_reference.max(o.worst_rust_vs_reference);
        self.worst_uv = self.worst_uv.max(o.worst_uv);
        self.worst_ng = self.worst_ng.max(o.worst_ng);
        self.worst_rust_ng = self.worst_rust_ng.max(o.worst_rust_ng);
        self
    }
}

/// The scene's meshes, for the reference computation.
struct Scene<'a> {
    meshes: Vec<&'a TestMesh>,
    size: f64,
}

impl Scene<'_> {
    /// Reference t and edge distance of the triangle a hit names.
    fn reference(&self, ray: &Ray, hit: &Hit) -> (f64, f64) {
        let tri = self.meshes[hit.geom as usize].corners(hit.prim);
        match reference(ray, tri) {
            Some((t, edge, _)) => (t, edge),
            // The ray lies in the triangle's plane: an edge case by
            // definition.
            None => (hit.t, 0.0),
        }
    }
}

fn compare_one(
    scene: &Scene<'_>,
    ray: &Ray,
    embree: &dyn Intersector,
    rust: &dyn Intersector,
    must_hit: bool,
) -> Tally {
    let e = embree.intersect(ray);
    let r = rust.intersect(ray);
    let mut tally = Tally {
        rays: 1,
        hits: r.is_some() as usize,
        ..Tally::default()
    };
    if must_hit {
        tally.embree_lost = e.is_none() as usize;
        tally.rust_lost = r.is_none() as usize;
    }
    // The closest reported hit, by the reference t of the triangles named.
    let closest = [e, r]
        .into_iter()
        .flatten()
        .map(|h| scene.reference(ray, &h))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let same = match (e, r) {
        (None, None) => true,
        (Some(a), Some(b)) => a.geom == b.geom && a.prim == b.prim,
        _ => false,
    };
    if let Some((_, edge)) = closest {
        if edge < EDGE * scene.size {
            tally.near_edge = 1;
            tally.near_edge_differing = !same as usize;
            return tally;
        }
    }
    if !same {
        tally.disagreements.push(format!(
            "o={} d={}: embree {e:?}, rust {r:?}",
            ray.origin, ray.dir
        ));
        return tally;
    }
    if let (Some(a), Some(b)) = (e, r) {
        let tri = scene.meshes[b.geom as usize].corners(b.prim);
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
        let cos = normal.dot(ray.dir.normalize()).abs();
        let scale = b.t + scene.size / ray.dir.length();
        tally.worst_t = (a.t - b.t).abs() * cos / scale;
        tally.worst_t_rel_to_t = (a.t - b.t).abs() / b.t;
        let (t_ref, _) = scene.reference(ray, &b);
        tally.worst_rust_vs_reference = (b.t - t_ref).abs() / scale;
        // Conventions: u, v are the weights of vertices 1 and 2, ng is
        // (v1 − v0) × (v2 − v0). Barycentrics are compared where they are
        // well conditioned (not grazing).
        if cos > 0.1 {
            tally.worst_uv = (a.u - b.u).abs().max((a.v - b.v).abs());
        }
        let exact_ng = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        tally.worst_ng = (a.ng - exact_ng).length() / exact_ng.length();
        tally.worst_rust_ng = (b.ng - exact_ng).length() / exact_ng.length();
    }
    tally
}

fn compare(
    scene: &Scene<'_>,
    rays: &[Ray],
    embree: &dyn Intersector,
    rust: &dyn Intersector,
    must_hit: bool,
) -> Tally {
    rays.par_chunks(4096)
        .map(|chunk| {
            chunk
                .iter()
                .map(|ray| compare_one(scene, ray, embree, rust, must_hit))
                .fold(Tally::default(), Tally::merge)
        })
        .reduce(Tally::default, Tally::merge)
}

fn backends(meshes: &[TriangleMesh<'_>]) -> (Box<dyn Intersector>, Box<dyn Intersector>) {
    let embree = build(AccelKind::Embree, meshes, 0).unwrap();
    let rust = build(AccelKind::Rust, meshes, 0).unwrap();
    assert_eq!((embree.name(), rust.name()), ("embree", "rust"));
    (embree, rust)
}

fn check(what: &str, t: &Tally) {
    eprintln!(
        "{what}: {} rays, {} hits, {} near an edge ({} of them answered differently), \
         {} disagreements, worst t difference {:.2e} across the surface ({:.2e} relative to t alone), \
         rust t and ng vs f64 reference {:.1e} and {:.1e}, u/v {:.1e}, embree ng {:.1e}, \
         lost embree/rust {}/{}",
        t.rays,
        t.hits,
        t.near_edge,
        t.near_edge_differing,
        t.disagreements.len(),
        t.worst_t,
        t.worst_t_rel_to_t,
        t.worst_rust_vs_reference,
        t.worst_rust_ng,
        t.worst_uv,
        t.worst_ng,
        t.embree_lost,
        t.rust_lost
    );
    assert!(
        t.disagreements.is_empty(),
        "{what}: {} disagreements away from edges, e.g.\n{}",
        t.disagreements.len(),
        t.disagreements[..t.disagreements.len().min(5)].join("\n")
    );
    assert!(t.worst_t <= T_REL, "{what}: t differs by {:.3e}", t.worst_t);
    assert!(
        t.worst_rust_vs_reference <= REFERENCE && t.worst_rust_ng <= REFERENCE,
        "{what}: rust t and ng off the f64 reference by {:.3e} and {:.3e}",
        t.worst_rust_vs_reference,
        t.worst_rust_ng
    );
    assert!(
        t.worst_uv <= UV,
        "{what}: u, v differ by {:.3e}",
        t.worst_uv
    );
    assert_eq!(
        (t.embree_lost, t.rust_lost),
        (0, 0),
        "{what}: rays from inside lost"
    );
    // Near-edge rays must stay rare: a wrong edge test would make many.
    assert!(
        t.near_edge * 1000 < t.rays,
        "{what}: {} of {} near edges",
        t.near_edge,
        t.rays
    );
}

#[test]
fn gems_from_outside_and_inside() {
    let mut total = Tally::default();
    for (i, gem) in gems().iter().enumerate() {
        let (embree, rust) = backends(&[gem.view()]);
        let scene = Scene {
            meshes: vec![gem],
            size: gem.size(),
        };
        let seed = 1000 + i as u64;
        let outside = compare(
            &scene,
            &rays_from_outside(gem, 150_000, seed),
            &*embree,
            &*rust,
            false,
        );
        let inside = compare(
            &scene,
            &rays_from_inside(gem, 150_000, seed),
            &*embree,
            &*rust,
            true,
        );
        check(&format!("{} from outside", gem.name), &outside);
        check(&format!("{} from inside", gem.name), &inside);
        assert!(
            outside.hits > outside.rays / 4,
            "{}: too few hits",
            gem.name
        );
        total = total.merge(outside).merge(inside);
    }
    check("all gems", &total);
    assert!(total.rays >= 2_000_000);
}

#[test]
fn triangle_soup_from_everywhere() {
    let soup = triangle_soup(4000, 7);
    let (embree, rust) = backends(&[soup.view()]);
    let scene = Scene {
        meshes: vec![&soup],
        size: soup.size(),
    };
    // Random rays through the soup's box and rays aimed at it from outside.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
    let mut rays: Vec<Ray> = (0..300_000)
        .map(|_| {
            let o = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 1.2 - DVec3::splat(0.1);
            Ray::new(o, accel_common::random_direction(&mut rng))
        })
        .collect();
    rays.extend(rays_from_outside(&soup, 300_000, 9));
    let t = compare(&scene, &rays, &*embree, &*rust, false);
    check("triangle soup", &t);
    assert!(t.hits > t.rays / 10, "too few hits: {}", t.hits);
}

#[test]
fn scene_of_several_meshes_names_the_right_mesh() {
    // Three gems side by side and a soup above them: `geom` must agree.
    let gems = gems();
    let mut placed: Vec<TestMesh> = Vec::new();
    for (k, gem) in gems.iter().take(3).enumerate() {
        let (lo, hi) = gem.bounds();
        let shift = DVec3::new(k as f64 * 1.5 * (hi - lo).max_element(), 0.0, 0.0) - lo;
        let scale = 1.0 / (hi - lo).max_element();
        placed.push(TestMesh {
            name: gem.name.clone(),
            vertices: gem
                .vertices
                .iter()
                .map(|v| {
                    ((DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64) + shift) * scale)
                        .as_vec3()
                        .to_array()
                })
                .collect(),
            triangles: gem.triangles.clone(),
            mesh: None,
        });
    }
    let mut soup = triangle_soup(500, 3);
    for v in &mut soup.vertices {
        v[0] *= 4.0;
        v[2] += 1.2;
    }
    placed.push(soup);
    let views: Vec<TriangleMesh<'_>> = placed.iter().map(TestMesh::view).collect();
    let (embree, rust) = backends(&views);
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for m in &placed {
        let (a, b) = m.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    let scene = Scene {
        meshes: placed.iter().collect(),
        size: (hi - lo).length(),
    };
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(11);
    let rays: Vec<Ray> = (0..200_000)
        .map(|_| {
            let o = lo + (hi - lo) * DVec3::new(rng.gen(), rng.gen(), rng.gen());
            Ray::new(o, accel_common::random_direction(&mut rng))
        })
        .collect();
    let t = compare(&scene, &rays, &*embree, &*rust, false);
    check("several meshes", &t);
    let geoms: std::collections::BTreeSet<u32> = rays
        .iter()
        .filter_map(|r| rust.intersect(r).map(|h| h.geom))
        .collect();
    assert_eq!(geoms.len(), placed.len(), "every mesh is hit by some ray");
}
