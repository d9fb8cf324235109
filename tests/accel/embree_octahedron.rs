//! Embree through the `Intersector` trait, against closed forms: the
//! octahedron |x| + |y| + |z| ≤ 1 is the intersection of the eight half-spaces
//! s·x ≤ 1 with s ∈ {±1}³, so the first hit of any ray is a slab-clipping
//! formula, and the face hit has normal s/√3.
#![cfg(feature = "native")]

use glam::DVec3;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use spar::accel::embree::EmbreeAccel;
use spar::accel::{Intersector, Ray, TriangleMesh};

fn octahedron() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut tris = Vec::new();
    for &sx in &[1.0f64, -1.0] {
        for &sy in &[1.0f64, -1.0] {
            for &sz in &[1.0f64, -1.0] {
                let x = if sx > 0.0 { 0 } else { 1 };
                let y = if sy > 0.0 { 2 } else { 3 };
                let z = if sz > 0.0 { 4 } else { 5 };
                // Counter-clockwise seen from outside: (x, y, z) winds
                // around +s when sx·sy·sz > 0.
                if sx * sy * sz > 0.0 {
                    tris.push([x, y, z]);
                } else {
                    tris.push([x, z, y]);
                }
            }
        }
    }
    (v, tris)
}

fn signs() -> Vec<DVec3> {
    let mut s = Vec::new();
    for i in 0..8 {
        s.push(DVec3::new(
            if i & 1 == 0 { 1.0 } else { -1.0 },
            if i & 2 == 0 { 1.0 } else { -1.0 },
            if i & 4 == 0 { 1.0 } else { -1.0 },
        ));
    }
    s
}

/// Closed form: first t > 0 where the ray meets the octahedron's boundary,
/// with the outward normal there.
fn analytic_hit(o: DVec3, d: DVec3) -> Option<(f64, DVec3)> {
    let mut t_in = f64::NEG_INFINITY;
    let mut n_in = DVec3::ZERO;
    let mut t_out = f64::INFINITY;
    let mut n_out = DVec3::ZERO;
    for s in signs() {
        let num = 1.0 - s.dot(o);
        let den = s.dot(d);
        if den.abs() < 1e-300 {
            if num < 0.0 {
                return None;
            }
            continue;
        }
        let t = num / den;
        if den < 0.0 {
            if t > t_in {
                t_in = t;
                n_in = s;
            }
        } else if t < t_out {
            t_out = t;
            n_out = s;
        }
    }
    if t_in > t_out {
        return None;
    }
    if t_in > 0.0 {
        Some((t_in, n_in / 3f64.sqrt()))
    } else if t_out > 0.0 {
        Some((t_out, n_out / 3f64.sqrt()))
    } else {
        None
    }
}

fn accel() -> EmbreeAccel {
    let (v, t) = octahedron();
    EmbreeAccel::build(
        &[TriangleMesh {
            vertices: &v,
            triangles: &t,
        }],
        2,
        None,
    )
    .unwrap()
}

/// Random rays from outside (aimed near the solid) and from inside, checked
/// from several threads at once. Rays whose closed-form hit lies within 1e-4
/// of an edge (where two faces tie) are checked for t only.
#[test]
fn hits_match_the_closed_form_from_many_threads() {
    let accel = accel();
    let results: Vec<(usize, usize, f64, f64)> = (0..8u64)
        .into_par_iter()
        .map(|chunk| {
            let mut rng = rand_pcg::Pcg64::seed_from_u64(chunk);
            let (mut hits, mut misses, mut worst_t, mut worst_n) = (0, 0, 0.0f64, 0.0f64);
            for i in 0..25_000 {
                let inside = i % 2 == 0;
                let o = if inside {
                    // A point inside: a random point scaled into the solid.
                    let p = DVec3::new(
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                    );
                    p * (0.9 * rng.gen::<f64>()
                        / p.x.abs().max(1e-9).max(p.x.abs() + p.y.abs() + p.z.abs()))
                } else {
                    DVec3::new(
                        rng.gen_range(-3.0..3.0),
                        rng.gen_range(-3.0..3.0),
                        3.0 * if rng.gen() { 1.0 } else { -1.0 },
                    )
                };
                let target = DVec3::new(
                    rng.gen_range(-1.2..1.2),
                    rng.gen_range(-1.2..1.2),
                    rng.gen_range(-1.2..1.2),
                );
                let d = (target - o).normalize();
                let expected = analytic_hit(o, d);
                let got = accel.intersect(&Ray::new(o, d));
                match (expected, got) {
                    (None, None) => misses += 1,
                    (Some((t, n)), Some(hit)) => {
                        hits += 1;
                        // Distance of Embree's hit point from the true face
                        // plane, in f32 ulps of the ray's extent |o| + t
                        // (along the ray the error grows as 1/|n·d| at
                        // grazing incidence; across the plane it does not).
                        let off_plane = (hit.t - t).abs() * n.dot(d).abs();
                        worst_t = worst_t.max(off_plane / (f32::EPSILON as f64 * (o.length() + t)));
                        let p = o + t * d;
                        let margin = signs()
                            .iter()
                            .map(|s| 1.0 - s.dot(p))
                            .filter(|m| *m > 1e-12)
                            .fold(f64::INFINITY, f64::min);
                        // Away from edges the face is unambiguous.
                        if margin > 1e-4 {
                            let ng = hit.ng.normalize();
                            worst_n = worst_n.max((ng - n).length());
                        }
                    }
                    (e, g) => {
                        // Only grazing rays at the silhouette may disagree.
                        let (t, _) = e.unwrap_or((0.0, DVec3::ZERO));
                        let p = o + t * d;
                        let near_edge = e.is_none()
                            || signs()
                                .iter()
                                .filter(|s| (1.0 - s.dot(p)).abs() < 1e-4)
                                .count()
                                >= 2;
                        assert!(
                            near_edge,
                            "disagreement away from edges: o={o} d={d} expected {e:?} got {g:?}"
                        );
                    }
                }
            }
            (hits, misses, worst_t, worst_n)
        })
        .collect();
    let hits: usize = results.iter().map(|r| r.0).sum();
    let misses: usize = results.iter().map(|r| r.1).sum();
    let worst_t = results.iter().map(|r| r.2).fold(0.0, f64::max);
    let worst_n = results.iter().map(|r| r.3).fold(0.0, f64::max);
    assert!(
        hits > 120_000 && misses > 10_000,
        "hits {hits}, misses {misses}"
    );
    // Embree works in f32: origin and direction are rounded (an ulp each)
    // and its robust triangle test takes a few dozen roundings, so the hit
    // point is good to a few ulps of the ray's extent; 8 ulps still catches
    // any real error (a wrong face or a wrong t is off by ~0.1).
    eprintln!("worst hit-point error: {worst_t:.2} ulps of |o| + t");
    assert!(worst_t < 8.0, "worst hit-point error {worst_t} ulps");
    assert!(worst_n < 1e-6, "worst normal error {worst_n}");
}

#[test]
fn a_miss_is_a_miss_and_tmax_is_respected() {
    let accel = accel();
    // Passing beside the solid.
    assert!(accel
        .intersect(&Ray::new(DVec3::new(2.0, 2.0, 0.0), DVec3::Z))
        .is_none());
    // Pointing away.
    assert!(accel
        .intersect(&Ray::new(DVec3::new(0.0, 0.0, 3.0), DVec3::Z))
        .is_none());
    // Toward the vertex (0,0,1) from above: hit at t = 2 (the vertex); with
    // tmax = 1.9 a miss, with tmin beyond the far side a miss.
    let mut ray = Ray::new(DVec3::new(0.1, 0.1, 3.0), -DVec3::Z);
    let hit = accel.intersect(&ray).unwrap();
    assert!((hit.t - 2.2).abs() < 1e-6, "t = {}", hit.t);
    ray.tmax = 2.1;
    assert!(accel.intersect(&ray).is_none());
    ray.tmax = f64::INFINITY;
    ray.tmin = 3.81;
    assert!(accel.intersect(&ray).is_none());
    ray.tmin = 2.3;
    let far = accel.intersect(&ray).unwrap();
    assert!((far.t - 3.8).abs() < 1e-6, "t = {}", far.t);
    // The far face is hit from inside: its outward normal points along the ray.
    assert!(far.ng.dot(ray.dir) > 0.0);
}

#[test]
fn out_of_range_indices_are_rejected_before_embree_sees_them() {
    let (v, mut t) = octahedron();
    t[3][1] = 6;
    let err = EmbreeAccel::build(
        &[TriangleMesh {
            vertices: &v,
            triangles: &t,
        }],
        1,
        None,
    )
    .err()
    .unwrap();
    assert!(err.to_string().contains("triangle 3"), "{err}");
}
