//! The half-space intersection under stress: thousands of planes, many
//! planes through one point (with and without rounding-sized misses), the
//! same planes in any order.

use glam::DVec3;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::geometry::convex::{intersect, HalfSpace, IntersectOptions, PlaneFate, Polytope};
use spar::geometry::cuts::{Brilliant, Cut};
use std::collections::HashSet;

fn edges(p: &Polytope) -> usize {
    let mut set = HashSet::new();
    for f in &p.faces {
        let n = f.vertices.len();
        for k in 0..n {
            let (a, b) = (f.vertices[k], f.vertices[(k + 1) % n]);
            set.insert((a.min(b), a.max(b)));
        }
    }
    set.len()
}

#[test]
fn two_thousand_tangent_planes_make_a_sphere_like_solid() {
    let mut rng = Pcg64::seed_from_u64(3);
    let planes: Vec<HalfSpace> = (0..2000)
        .map(|_| loop {
            let v = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                // Scaled normals: the intersection normalizes them.
                break HalfSpace::new(v * 3.0 / l, 3.0);
            }
        })
        .collect();
    let p = intersect(&planes, IntersectOptions { weld: 1e-9 }).unwrap();
    let mesh = p.to_mesh(|_| None);
    mesh.check_closed_and_oriented().unwrap();
    // Euler's formula for a convex polyhedron.
    assert_eq!(
        p.positions.len() as i64 - edges(&p) as i64 + p.faces.len() as i64,
        2
    );
    // Circumscribes the unit sphere, so holds more than its volume; with
    // 2000 tangent planes, not much more.
    let sphere = 4.0 / 3.0 * std::f64::consts::PI;
    let v = mesh.signed_volume();
    assert!(v > sphere && v < 1.03 * sphere, "{v}");
    assert!(p.positions.iter().all(|q| q.length() >= 1.0 - 1e-12));
    assert!(p.max_plane_deviation < 1e-12);
}

/// A 64-sided pyramid: base z >= 0, sides through the apex (0, 0, 1), each
/// side missing it by up to `miss`.
fn pyramid(miss: f64) -> Vec<HalfSpace> {
    let mut rng = Pcg64::seed_from_u64(5);
    let mut planes = vec![HalfSpace::new(-DVec3::Z, 0.0)];
    for k in 0..64 {
        let a = k as f64 / 64.0 * std::f64::consts::TAU;
        let n = DVec3::new(a.cos(), a.sin(), 0.8).normalize();
        let d = n.dot(DVec3::Z) + miss * rng.gen_range(-1.0..1.0);
        planes.push(HalfSpace::new(n, d));
    }
    planes
}

#[test]
fn many_planes_through_one_point_make_one_vertex() {
    // Nearly coplanar normals amplify a miss δ in where three sides meet
    // (to ~500 δ here): below the 1e-6 weld for these misses.
    for miss in [0.0, 1e-13, 1e-11, 1e-9] {
        let p = intersect(&pyramid(miss), IntersectOptions { weld: 1e-6 }).unwrap();
        assert_eq!(p.positions.len(), 65, "miss {miss}");
        assert_eq!(p.faces.len(), 65, "miss {miss}");
        assert!(p
            .faces
            .iter()
            .filter(|f| f.plane > 0)
            .all(|f| f.vertices.len() == 3));
        assert!(
            p.max_plane_deviation <= 2.0 * miss + 1e-12,
            "miss {miss}: {}",
            p.max_plane_deviation
        );
        let apex = p
            .positions
            .iter()
            .max_by(|a, b| a.z.total_cmp(&b.z))
            .unwrap();
        assert!((*apex - DVec3::Z).length() < 1e3 * miss + 1e-12, "{apex}");
    }
}

#[test]
fn misses_beyond_the_weld_keep_short_edges_and_flat_facets() {
    // Misses of 1e-7…1e-5 spread the apex over edges longer than the weld
    // (1e-8 already spreads it over 6e-6):
    // they stay, every facet stays flat, the surface stays closed.
    for miss in [1e-7, 1e-6, 1e-5] {
        let p = intersect(&pyramid(miss), IntersectOptions { weld: 1e-6 }).unwrap();
        p.to_mesh(|_| None).check_closed_and_oriented().unwrap();
        assert!(p.positions.len() > 65, "miss {miss}");
        assert!(
            p.max_plane_deviation <= 1e-6,
            "miss {miss}: {}",
            p.max_plane_deviation
        );
        assert!(p.positions.iter().all(|q| q.z < 1.0 + 100.0 * miss));
    }
}

#[test]
fn a_miss_larger_than_the_weld_leaves_real_edges() {
    // Two planes that miss the apex of the other two by 1e-4: kept apart.
    let mut planes = vec![HalfSpace::new(-DVec3::Z, 0.0)];
    for (k, d) in [0.0, 1e-4, 0.0, 1e-4].iter().enumerate() {
        let a = k as f64 * std::f64::consts::FRAC_PI_2;
        let n = DVec3::new(a.cos(), a.sin(), 1.0).normalize();
        planes.push(HalfSpace::new(n, n.dot(DVec3::Z) + d));
    }
    let p = intersect(&planes, IntersectOptions { weld: 1e-6 }).unwrap();
    assert_eq!(p.positions.len(), 6);
    assert!(p.fates.iter().all(|f| *f == PlaneFate::Facet));
}

#[test]
fn plane_order_does_not_change_the_stone() {
    let cut = Cut::RoundBrilliant(Brilliant::default());
    let planes: Vec<HalfSpace> = cut.planes().unwrap().into_iter().map(|p| p.plane).collect();
    let reference = intersect(&planes, IntersectOptions { weld: 1e-9 }).unwrap();
    let key = |p: &Polytope| {
        let mut v: Vec<[i64; 3]> = p
            .positions
            .iter()
            .map(|q| [q.x, q.y, q.z].map(|c| (c * 1e9).round() as i64))
            .collect();
        v.sort_unstable();
        v
    };
    let mut rng = Pcg64::seed_from_u64(9);
    for _ in 0..20 {
        let mut order: Vec<usize> = (0..planes.len()).collect();
        order.shuffle(&mut rng);
        let shuffled: Vec<HalfSpace> = order.iter().map(|&i| planes[i]).collect();
        let p = intersect(&shuffled, IntersectOptions { weld: 1e-9 }).unwrap();
        assert_eq!(p.faces.len(), reference.faces.len());
        assert_eq!(key(&p), key(&reference));
        assert!((p.volume() - reference.volume()).abs() < 1e-14);
    }
}
