//! The Rust BVH has no absolute epsilon: a gem scaled by 1e-5 or 1e5, and
//! moved 1000 sizes away from the origin, gives the same hits as the gem
//! itself — for rays from outside and from inside, with directions of any
//! length. Pure Rust: runs without the `native` feature.
//!
//! Scaling by a power of two changes no f32 rounding, so there the answers
//! must be identical bit for bit. Scaling by 1e±5 or translating rounds the
//! vertices to different f32 values (by δ, measured here per mesh): then
//! the answers may differ only where the closest hit lies within
//! 1e-6·size + 4δ/|cos θ| of an edge (the in-plane shift a δ move of the
//! vertices and the origin can cause), and t may differ only by the δ move
//! of the triangle's plane.

use crate::support::accel::{gems, rays_from_inside, rays_from_outside, reference, TestMesh};
use glam::DVec3;
use rayon::prelude::*;
use spar::accel::bvh::RustBvh;
use spar::accel::{Intersector, Ray};

/// A gem moved by `x ↦ scale · x + shift`, vertices rounded to f32 once.
struct Placed {
    mesh: TestMesh,
    scale: f64,
    shift: DVec3,
    /// Largest distance between a rounded vertex and the exact one, in the
    /// gem's own units (both meshes' roundings together).
    delta: f64,
}

fn place(gem: &TestMesh, scale: f64, shift: DVec3) -> Placed {
    let exact = &gem.mesh.as_ref().unwrap().positions;
    let vertices: Vec<[f32; 3]> = exact
        .iter()
        .map(|&p| (p * scale + shift).as_vec3().to_array())
        .collect();
    let delta = exact
        .iter()
        .zip(&vertices)
        .zip(&gem.vertices)
        .map(|((&p, moved), base)| {
            let moved = DVec3::new(moved[0] as f64, moved[1] as f64, moved[2] as f64);
            let base = DVec3::new(base[0] as f64, base[1] as f64, base[2] as f64);
            ((moved - shift) / scale - p).length() + (base - p).length()
        })
        .fold(0.0, f64::max);
    Placed {
        mesh: TestMesh {
            name: format!("{}×{scale:e}+{shift}", gem.name),
            vertices,
            triangles: gem.triangles.clone(),
            mesh: None,
        },
        scale,
        shift,
        delta,
    }
}

#[derive(Default)]
struct Tally {
    rays: usize,
    hits: usize,
    near_edge: usize,
    lost: usize,
    identical: usize,
    disagreements: Vec<String>,
    /// Largest t difference across the surface over its allowance.
    worst_t: f64,
}

impl Tally {
    fn merge(mut self, o: Tally) -> Tally {
        self.rays += o.rays;
        self.hits += o.hits;
        self.near_edge += o.near_edge;
        self.lost += o.lost;
        self.identical += o.identical;
        self.disagreements.extend(o.disagreements);
        self.worst_t = self.worst_t.max(o.worst_t);
        self
    }
}

/// Traces `rays` at the gem and, moved, at the placed gem (directions
/// multiplied by `dir_scale`), and compares.
fn compare(
    gem: &TestMesh,
    base: &dyn Intersector,
    placed: &Placed,
    moved: &dyn Intersector,
    rays: &[Ray],
    dir_scale: f64,
    must_hit: bool,
) -> Tally {
    let size = gem.size();
    let one = |ray: &Ray| -> Tally {
        let moved_ray = Ray {
            origin: ray.origin * placed.scale + placed.shift,
            dir: ray.dir * dir_scale,
            tmin: ray.tmin,
            tmax: ray.tmax,
        };
        let a = base.intersect(ray);
        // In the gem's units: o' + t'·k·d = s·(o + t·d) + shift ⇒ t = t'·k/s;
        // the normal (v1 − v0) × (v2 − v0) grows by s².
        let b = moved.intersect(&moved_ray).map(|mut h| {
            h.t *= dir_scale / placed.scale;
            h.ng /= placed.scale * placed.scale;
            h
        });
        let mut tally = Tally {
            rays: 1,
            hits: b.is_some() as usize,
            lost: (must_hit && (a.is_none() || b.is_none())) as usize,
            identical: (a == b) as usize,
            ..Tally::default()
        };
        let same = match (a, b) {
            (None, None) => true,
            (Some(x), Some(y)) => x.prim == y.prim && x.geom == y.geom,
            _ => false,
        };
        // The closest hit named by either, with its edge distance and the
        // cosine between the ray and its normal.
        let closest = [a, b]
            .into_iter()
            .flatten()
            .filter_map(|h| {
                let c = gem.corners(h.prim);
                let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
                let cos = n.dot(ray.dir.normalize()).abs();
                reference(ray, c).map(|(t, edge, _)| (t, edge, cos))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((_, edge, cos)) = closest {
            if edge <= 1e-6 * size + 4.0 * placed.delta / cos {
                tally.near_edge = 1;
                return tally;
            }
        }
        if !same {
            tally.disagreements.push(format!(
                "{}: o={} d={}: {a:?} vs {b:?}",
                placed.mesh.name, ray.origin, ray.dir
            ));
            return tally;
        }
        if let (Some(x), Some(y), Some((_, _, cos))) = (a, b, closest) {
            // The plane moved by at most δ; f64 rounding on top.
            let across = (x.t - y.t).abs() * ray.dir.length() * cos;
            let allowed = placed.delta + 1e-12 * (x.t * ray.dir.length() + size);
            tally.worst_t = across / allowed;
        }
        tally
    };
    rays.par_iter()
        .map(one)
        .reduce(Tally::default, Tally::merge)
}

fn rays_for(gem: &TestMesh, seed: u64) -> (Vec<Ray>, Vec<Ray>) {
    (
        rays_from_outside(gem, 40_000, seed),
        rays_from_inside(gem, 40_000, seed + 1),
    )
}

/// Runs every gem through `placements` (scale, shift in sizes, direction
/// scale) and returns the tallies; `exact` demands identical answers.
fn run(placements: &[(f64, f64, f64)], exact: bool) {
    for (g, gem) in gems().iter().enumerate() {
        let base = RustBvh::build(&[gem.view()], 0).unwrap();
        let (outside, inside) = rays_for(gem, 100 + g as u64);
        let size = gem.size();
        for &(scale, shift_sizes, dir_scale) in placements {
            let shift = DVec3::new(1.0, -0.7, 0.4) * shift_sizes * size * scale;
            let placed = place(gem, scale, shift);
            let moved = RustBvh::build(&[placed.mesh.view()], 0).unwrap();
            for (what, rays, must_hit) in [("outside", &outside, false), ("inside", &inside, true)]
            {
                let t = compare(gem, &base, &placed, &moved, rays, dir_scale, must_hit);
                eprintln!(
                    "{} from {what}, dir ×{dir_scale:e}: δ = {:.1e}·size, {} rays, {} hits, \
                     {} identical, {} near an edge, {} disagreements, {} lost, worst t {:.2} of allowed",
                    placed.mesh.name,
                    placed.delta / size,
                    t.rays,
                    t.hits,
                    t.identical,
                    t.near_edge,
                    t.disagreements.len(),
                    t.lost,
                    t.worst_t
                );
                assert_eq!(t.lost, 0, "{}: rays from inside lost", placed.mesh.name);
                assert!(
                    t.disagreements.is_empty(),
                    "{} disagreements, e.g.\n{}",
                    t.disagreements.len(),
                    t.disagreements[..t.disagreements.len().min(5)].join("\n")
                );
                assert!(
                    t.worst_t <= 1.0,
                    "{}: t off by {} of its allowance",
                    placed.mesh.name,
                    t.worst_t
                );
                // The exclusion zone grows with δ, but must leave the
                // comparison most of the rays.
                assert!(
                    t.near_edge * 20 < t.rays,
                    "{}: {} of {} rays near edges",
                    placed.mesh.name,
                    t.near_edge,
                    t.rays
                );
                if exact {
                    assert_eq!(
                        t.identical, t.rays,
                        "{}: not bit-identical",
                        placed.mesh.name
                    );
                }
                if what == "outside" {
                    assert!(t.hits > t.rays / 4, "{}: too few hits", placed.mesh.name);
                }
            }
        }
    }
}

#[test]
fn scaled_by_1e_minus_5_and_1e5_and_moved_far_away() {
    run(
        &[
            (1e-5, 0.0, 1.0),
            (1e5, 0.0, 1.0),
            (1.0, 1e3, 1.0),
            (1e-5, 1e3, 1.0),
            (1e5, 1e3, 1.0),
            // Directions need not be normalized: tiny and huge ones too.
            (1e-5, 1e3, 1e-30),
            (1e5, 0.0, 1e30),
        ],
        false,
    );
}

#[test]
fn power_of_two_scales_change_nothing_at_all() {
    // 2^±17 ≈ 1e∓5.2: every f32 rounding scales exactly, so every hit must
    // be identical — t, u, v and ng scaled exactly, no exclusions.
    run(
        &[
            (2f64.powi(-17), 0.0, 1.0),
            (2f64.powi(17), 0.0, 1.0),
            (2f64.powi(-17), 0.0, 2f64.powi(-90)),
        ],
        true,
    );
}
