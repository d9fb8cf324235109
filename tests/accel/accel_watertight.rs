//! No ray leaks through a closed gem: rays aimed exactly at every vertex and
//! at points along every edge (shared by two triangles, or by a whole fan at
//! a vertex) hit, from inside and from outside. This is what the watertight
//! triangle test and the conservative box test are for; a test with an
//! epsilon, or a box test that rounds the wrong way, loses some of these.
//! Runs on the Rust BVH always, and on Embree too when built with it.

use crate::support::accel as accel_common;

use accel_common::{gems, inside_convex, TestMesh};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use spar::accel::{build, AccelKind, Intersector, Ray};

/// A point exactly on the surface, with the outward normals of the
/// triangles that touch it there.
struct Target {
    point: DVec3,
    normals: Vec<DVec3>,
}

/// Points exactly on the surface: every vertex, and points at k/8 along
/// every triangle edge (each edge once).
fn surface_targets(m: &TestMesh) -> Vec<Target> {
    let mesh = m.mesh.as_ref().unwrap();
    let normal = |prim: usize| mesh.triangle_normal(prim as u32);
    let mut at_vertex = vec![Vec::new(); m.vertices.len()];
    let mut edges = std::collections::BTreeMap::<(u32, u32), Vec<DVec3>>::new();
    for (prim, t) in m.triangles.iter().enumerate() {
        for i in 0..3 {
            at_vertex[t[i] as usize].push(normal(prim));
            let (a, b) = (t[i], t[(i + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(normal(prim));
        }
    }
    let mut targets: Vec<Target> = at_vertex
        .into_iter()
        .enumerate()
        .map(|(i, normals)| Target {
            point: m.vertex(i as u32),
            normals,
        })
        .collect();
    for ((a, b), normals) in edges {
        let (pa, pb) = (m.vertex(a), m.vertex(b));
        targets.extend((1..8).map(|k| Target {
            point: pa + (pb - pa) * (k as f64 / 8.0),
            normals: normals.clone(),
        }));
    }
    targets
}

fn backends(m: &TestMesh) -> Vec<Box<dyn Intersector>> {
    AccelKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .map(|k| build(k, &[m.view()], 0).unwrap())
        .collect()
}

#[test]
fn rays_at_vertices_and_edges_from_inside_always_hit() {
    for (g, gem) in gems().iter().enumerate() {
        let mesh = gem.mesh.as_ref().unwrap();
        let targets = surface_targets(gem);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(g as u64);
        let (lo, hi) = gem.bounds();
        let mut origins = Vec::new();
        while origins.len() < 150 {
            let o = lo + (hi - lo) * DVec3::new(rng.gen(), rng.gen(), rng.gen());
            if inside_convex(mesh, o, 1e-3 * gem.size()) {
                origins.push(o);
            }
        }
        let rays: Vec<Ray> = origins
            .iter()
            .flat_map(|&o| targets.iter().map(move |p| Ray::new(o, p.point - o)))
            .collect();
        for accel in backends(gem) {
            let lost: Vec<&Ray> = rays
                .par_iter()
                .filter(|ray| accel.intersect(ray).is_none())
                .collect();
            eprintln!(
                "{} ({}): {} rays at vertices and edges from inside, {} lost",
                gem.name,
                accel.name(),
                rays.len(),
                lost.len()
            );
            check_losses(&*accel, lost.len(), rays.len(), &lost);
        }
    }
}

/// The Rust BVH must lose no ray. Embree in robust mode loses a few in 10⁵
/// of these (3 of 191 700 from inside one gem); without the robust flag it
/// loses thousands, so a looser bound still checks spar sets the flag.
fn check_losses(accel: &dyn Intersector, lost: usize, rays: usize, examples: &[&Ray]) {
    let allowed = match accel.name() {
        "rust" => 0,
        _ => rays / 10_000,
    };
    assert!(
        lost <= allowed,
        "{}: {lost} of {rays} rays leak, e.g. {:?}",
        accel.name(),
        &examples[..examples.len().min(3)]
    );
}

#[test]
fn rays_at_vertices_and_edges_from_outside_hit_no_later_than_the_target() {
    for (g, gem) in gems().iter().enumerate() {
        let targets = surface_targets(gem);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(100 + g as u64);
        let (lo, hi) = gem.bounds();
        let center = (lo + hi) / 2.0;
        let origins: Vec<DVec3> = (0..150)
            .map(|_| center + gem.size() * accel_common::random_direction(&mut rng))
            .collect();
        // Only targets the ray enters the gem through: every triangle at
        // the target faces the origin. (At a silhouette edge the ray only
        // grazes the gem, and f32 rounding may legitimately miss it.)
        let rays: Vec<Ray> = origins
            .iter()
            .flat_map(|&o| targets.iter().map(move |p| Ray::new(o, p.point - o)))
            .filter(|r| {
                let d = r.dir.normalize();
                let target = r.origin + r.dir;
                targets
                    .iter()
                    .find(|p| p.point == target)
                    .is_some_and(|p| p.normals.iter().all(|n| n.dot(d) < -1e-3))
            })
            .collect();
        assert!(
            rays.len() > 10_000,
            "{}: only {} rays",
            gem.name,
            rays.len()
        );
        for accel in backends(gem) {
            // With d = target − o the surface point is at t = 1, so the
            // first hit of the closed convex gem is at t ≤ 1: exactly (to
            // f64 rounding) for the Rust BVH, whose t is recomputed in f64;
            // Embree's f32 t is not checked (it grazes facets here).
            let hits: Vec<Option<f64>> = rays
                .par_iter()
                .map(|ray| accel.intersect(ray).map(|h| h.t))
                .collect();
            let lost: Vec<&Ray> = rays
                .iter()
                .zip(&hits)
                .filter(|(_, h)| h.is_none())
                .map(|(r, _)| r)
                .collect();
            let late = hits.iter().flatten().filter(|&&t| t > 1.0 + 1e-12).count();
            eprintln!(
                "{} ({}): {} rays at vertices and edges from outside, {} lost, {} hit after the target",
                gem.name,
                accel.name(),
                rays.len(),
                lost.len(),
                late
            );
            check_losses(&*accel, lost.len(), rays.len(), &lost);
            if accel.name() == "rust" {
                assert_eq!(late, 0, "rust: hits after the target");
            }
        }
    }
}

#[test]
fn rays_along_a_fan_apex_hit_whatever_the_direction_rounding() {
    // A vertex shared by many triangles: a square pyramid's apex fanned into
    // 32 slivers around it, hit exactly at the apex from every direction in
    // a dense cone. Every ray must hit.
    let n = 32;
    let mut vertices = vec![[0.0f32, 0.0, 1.0]];
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        vertices.push([a.cos() as f32, a.sin() as f32, 0.0]);
    }
    let triangles: Vec<[u32; 3]> = (0..n)
        .map(|i| [0, 1 + i as u32, 1 + ((i + 1) % n) as u32])
        .collect();
    let fan = TestMesh {
        name: "fan".into(),
        vertices,
        triangles,
        mesh: None,
    };
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
    let rays: Vec<Ray> = (0..100_000)
        .map(|_| {
            let o = DVec3::new(rng.gen_range(-0.3..0.3), rng.gen_range(-0.3..0.3), 3.0);
            Ray::new(o, DVec3::new(0.0, 0.0, 1.0) - o)
        })
        .collect();
    for accel in backends(&fan) {
        let lost = rays
            .par_iter()
            .filter(|r| accel.intersect(r).is_none())
            .count();
        assert_eq!(lost, 0, "{}: rays at the apex lost", accel.name());
    }
}
