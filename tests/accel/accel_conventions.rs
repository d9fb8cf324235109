//! What every backend promises through the `Intersector` trait, checked on
//! each backend this build has (Embree only with `native`): closed forms,
//! the meaning of `t`, `prim`, `geom`, `u`, `v` and `ng`, the ray interval,
//! two-sided triangles, degenerate input, and the `build` selector.

use crate::support::accel as accel_common;

use accel_common::random_direction;
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use spar::accel::{build, AccelError, AccelKind, Intersector, Ray, TriangleMesh};

fn available() -> Vec<AccelKind> {
    AccelKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .collect()
}

/// How close a backend's numbers are to exact: the Rust BVH recomputes
/// hits in f64; Embree reports f32.
fn tolerance(accel: &dyn Intersector) -> f64 {
    if accel.name() == "rust" {
        1e-12
    } else {
        1e-5
    }
}

/// The octahedron |x| + |y| + |z| = 1, counter-clockwise seen from outside.
fn octahedron() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut t = Vec::new();
    for s in 0..8u32 {
        let (x, y, z) = (s & 1, 2 + ((s >> 1) & 1), 4 + ((s >> 2) & 1));
        // The face normal is (±1, ±1, ±1); an odd number of minus signs
        // flips the winding of (x, y, z).
        if (s.count_ones()) % 2 == 0 {
            t.push([x, y, z]);
        } else {
            t.push([x, z, y]);
        }
    }
    (v, t)
}

/// First t > 0 at which the ray meets the octahedron (the half-spaces
/// s·x ≤ 1, s ∈ {±1}³), by slab clipping.
fn octahedron_hit(o: DVec3, d: DVec3) -> Option<f64> {
    let (mut t_in, mut t_out) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..8 {
        let s = DVec3::new(
            if i & 1 == 0 { 1.0 } else { -1.0 },
            if i & 2 == 0 { 1.0 } else { -1.0 },
            if i & 4 == 0 { 1.0 } else { -1.0 },
        );
        let (num, den) = (1.0 - s.dot(o), s.dot(d));
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
        } else if den < 0.0 {
            t_in = t_in.max(num / den);
        } else {
            t_out = t_out.min(num / den);
        }
    }
    if t_in > t_out {
        None
    } else if t_in > 0.0 {
        Some(t_in)
    } else if t_out > 0.0 {
        Some(t_out)
    } else {
        None
    }
}

#[test]
fn octahedron_against_its_closed_form() {
    let (v, t) = octahedron();
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    for kind in available() {
        let accel = build(kind, &mesh, 0).unwrap();
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let (mut hits, mut misses) = (0, 0);
        for i in 0..200_000 {
            let o = if i % 2 == 0 {
                // Inside: |o|₁ < 0.9.
                let p = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 2.0 - DVec3::ONE;
                p * (0.9 * rng.gen::<f64>() / (p.x.abs() + p.y.abs() + p.z.abs()))
            } else {
                3.0 * random_direction(&mut rng)
            };
            let target = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 2.4 - DVec3::splat(1.2);
            let d = (target - o) * rng.gen_range(0.1..10.0);
            let got = accel.intersect(&Ray::new(o, d));
            match (octahedron_hit(o, d), got) {
                (Some(t), Some(h)) => {
                    hits += 1;
                    let p = o + t * d;
                    // Hit point on the right plane, to the backend's
                    // precision, in units of the ray's extent.
                    let n = h.ng.normalize();
                    let off = ((h.t - t) * d.dot(n)).abs() / (o.length() + t * d.length());
                    assert!(
                        off < tolerance(&*accel),
                        "{kind}: o={o} d={d}: t {} vs {t}",
                        h.t
                    );
                    // The face hit is the one the point is on.
                    let s = n * 3f64.sqrt();
                    let margin = (s.dot(p) - 1.0).abs();
                    assert!(margin < 1e-5, "{kind}: wrong face at {p}: {s}");
                }
                (None, None) => misses += 1,
                (e, g) => {
                    // Only rays that graze an edge may disagree.
                    let p = o + e.unwrap_or(g.map_or(0.0, |h| h.t)) * d;
                    // (The octahedron's edges lie in the coordinate planes.)
                    let near = [p.x, p.y, p.z].iter().any(|c| c.abs() < 1e-5);
                    assert!(near, "{kind}: o={o} d={d}: exact {e:?}, got {g:?}");
                }
            }
        }
        assert!(
            hits > 120_000 && misses > 10_000,
            "{kind}: {hits} hits, {misses} misses"
        );
    }
}

/// The triangle (1,0,0), (3,0,0), (1,4,0) in the plane z = 0.
fn one_triangle() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    (
        vec![[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [1.0, 4.0, 0.0]],
        vec![[0, 1, 2]],
    )
}

#[test]
fn t_u_v_and_ng_mean_what_the_trait_says() {
    let (v, t) = one_triangle();
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    for kind in available() {
        let accel = build(kind, &mesh, 0).unwrap();
        let tol = tolerance(&*accel);
        // From above, direction of length 2: t in units of the direction.
        let h = accel
            .intersect(&Ray::new(
                DVec3::new(1.5, 1.0, 3.0),
                DVec3::new(0.0, 0.0, -2.0),
            ))
            .unwrap();
        assert!((h.t - 1.5).abs() < tol, "{kind}: t = {}", h.t);
        // (1.5, 1) = v0 + u (v1 − v0) + v (v2 − v0): u = 0.25, v = 0.25.
        assert!(
            (h.u - 0.25).abs() < tol && (h.v - 0.25).abs() < tol,
            "{kind}: {h:?}"
        );
        // ng = (v1 − v0) × (v2 − v0) = (2,0,0) × (0,4,0) = (0,0,8).
        assert!(
            (h.ng - DVec3::new(0.0, 0.0, 8.0)).length() < 8.0 * tol,
            "{kind}: {h:?}"
        );
        assert_eq!((h.geom, h.prim), (0, 0));
        // From below: the back face counts too, same normal.
        let h = accel
            .intersect(&Ray::new(DVec3::new(2.0, 0.5, -1.0), DVec3::Z))
            .unwrap();
        assert!((h.t - 1.0).abs() < tol, "{kind}: t = {}", h.t);
        assert!(h.ng.z > 0.0, "{kind}: {h:?}");
        // u, v are the weights of v1 and v2 everywhere.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(1);
        for _ in 0..1000 {
            let (a, b) = (rng.gen::<f64>(), rng.gen::<f64>());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            let p = DVec3::new(1.0, 0.0, 0.0)
                + a * DVec3::new(2.0, 0.0, 0.0)
                + b * DVec3::new(0.0, 4.0, 0.0);
            let o = p + DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 2.0);
            let Some(h) = accel.intersect(&Ray::new(o, p - o)) else {
                continue; // at an edge in f32
            };
            assert!(
                (h.u - a).abs() < 1e-4 && (h.v - b).abs() < 1e-4,
                "{kind}: {a} {b} vs {h:?}"
            );
        }
    }
}

#[test]
fn the_ray_interval_is_closed_and_negative_tmin_counts_as_zero() {
    let (v, t) = one_triangle();
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    // The Rust BVH's interval is exactly [tmin, tmax]; Embree's ends are
    // f32 and its tnear is exclusive, so it is checked away from the ends.
    for kind in available() {
        let accel = build(kind, &mesh, 0).unwrap();
        let exact = accel.name() == "rust";
        let at = |tmin: f64, tmax: f64| {
            accel.intersect(&Ray {
                origin: DVec3::new(1.5, 1.0, 2.0),
                dir: -DVec3::Z,
                tmin,
                tmax,
            })
        };
        assert!(at(0.0, f64::INFINITY).is_some());
        assert!(at(0.0, 1.999).is_none(), "{kind}");
        assert!(at(2.001, f64::INFINITY).is_none(), "{kind}");
        assert!(at(1.999, 2.001).is_some(), "{kind}");
        assert!(at(-5.0, 2.001).is_some(), "{kind}");
        if exact {
            assert_eq!(at(2.0, 2.0).unwrap().t, 2.0);
            assert!(at(0.0, 2.0 - 1e-15).is_none());
            assert!(at(2.0 + 1e-15, 3.0).is_none());
        }
        assert!(at(3.0, 1.0).is_none(), "{kind}: reversed interval");
        if exact {
            // A NaN interval, a zero or non-finite direction or origin: no
            // hit, no panic. (Embree's answers to these are undocumented.)
            assert!(at(f64::NAN, 3.0).is_none());
            assert!(at(0.0, f64::NAN).is_none());
            for (o, d) in [
                (DVec3::new(1.5, 1.0, 2.0), DVec3::ZERO),
                (DVec3::new(1.5, 1.0, 2.0), DVec3::new(0.0, f64::NAN, -1.0)),
                (DVec3::new(1.5, 1.0, 2.0), DVec3::new(0.0, 1e-320, -1e-320)),
                (DVec3::new(f64::NAN, 1.0, 2.0), -DVec3::Z),
                (DVec3::new(1.5, f64::INFINITY, 2.0), -DVec3::Z),
            ] {
                assert!(
                    accel.intersect(&Ray::new(o, d)).is_none(),
                    "{kind}: {o} {d}"
                );
            }
        }
    }
}

#[test]
fn prim_is_the_callers_index_and_geom_the_mesh_index() {
    let soup = accel_common::triangle_soup(3000, 21);
    // The same triangles in a shuffled order, as a second mesh placed above.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(22);
    let mut order: Vec<usize> = (0..soup.triangles.len()).collect();
    for i in (1..order.len()).rev() {
        order.swap(i, rng.gen_range(0..=i));
    }
    let shuffled: Vec<[u32; 3]> = order.iter().map(|&i| soup.triangles[i]).collect();
    let lifted: Vec<[f32; 3]> = soup
        .vertices
        .iter()
        .map(|v| [v[0], v[1], v[2] + 10.0])
        .collect();
    let meshes = [
        soup.view(),
        TriangleMesh {
            vertices: &lifted,
            triangles: &shuffled,
        },
    ];
    for kind in available() {
        let accel = build(kind, &meshes, 0).unwrap();
        let (mut checked, mut rng) = (0, rand_pcg::Pcg64Mcg::seed_from_u64(23));
        for _ in 0..20_000 {
            let o = DVec3::new(rng.gen(), rng.gen(), rng.gen());
            let d = random_direction(&mut rng);
            let lower = accel.intersect(&Ray::new(o, d));
            let upper = accel.intersect(&Ray::new(o + DVec3::new(0.0, 0.0, 10.0), d));
            // Rays that leave the unit cube meet nothing else.
            if let (Some(a), Some(b)) = (lower, upper) {
                if (a.t - b.t).abs() < 1e-4 * a.t {
                    assert_eq!((a.geom, b.geom), (0, 1), "{kind}");
                    assert_eq!(order[b.prim as usize], a.prim as usize, "{kind}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 2000, "{kind}: only {checked} checked");
    }
}

#[test]
fn degenerate_triangles_are_never_hit_and_empty_scenes_are_fine() {
    let v = vec![
        [0.0f32, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    // A line, a point, and one proper triangle.
    let t = vec![[0, 1, 2], [3, 3, 3], [3, 4, 5]];
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    for kind in available() {
        let accel = build(kind, &mesh, 0).unwrap();
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(4);
        for _ in 0..10_000 {
            let o = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 3.0 - DVec3::ONE;
            if let Some(h) = accel.intersect(&Ray::new(o, random_direction(&mut rng))) {
                assert_eq!(h.prim, 2, "{kind}: a degenerate triangle was hit");
            }
        }
        let empty = build(kind, &[], 0).unwrap();
        assert!(empty.intersect(&Ray::new(DVec3::ZERO, DVec3::X)).is_none());
        let none: [TriangleMesh<'_>; 1] = [TriangleMesh {
            vertices: &[],
            triangles: &[],
        }];
        let empty = build(kind, &none, 0).unwrap();
        assert!(empty.intersect(&Ray::new(DVec3::ZERO, DVec3::X)).is_none());
    }
}

#[test]
fn invalid_meshes_are_rejected_alike() {
    let (v, mut t) = octahedron();
    t[3][1] = 6;
    let mut bad_v = v.clone();
    bad_v[2][1] = f32::NAN;
    for kind in available() {
        let err = build(
            kind,
            &[TriangleMesh {
                vertices: &v,
                triangles: &t,
            }],
            0,
        )
        .err()
        .unwrap();
        assert!(
            matches!(
                err,
                AccelError::IndexOutOfRange {
                    triangle: 3,
                    vertex: 6,
                    ..
                }
            ),
            "{kind}: {err}"
        );
        let (_, good_t) = octahedron();
        let err = build(
            kind,
            &[TriangleMesh {
                vertices: &bad_v,
                triangles: &good_t,
            }],
            0,
        )
        .err()
        .unwrap();
        assert!(
            matches!(err, AccelError::NonFiniteVertex { vertex: 2, .. }),
            "{kind}: {err}"
        );
    }
}

#[test]
fn kinds_parse_print_and_say_when_they_are_missing() {
    assert_eq!(AccelKind::parse("embree"), Ok(AccelKind::Embree));
    assert_eq!(AccelKind::parse(" Rust "), Ok(AccelKind::Rust));
    assert_eq!("rust".parse::<AccelKind>(), Ok(AccelKind::Rust));
    let err = AccelKind::parse("optix").unwrap_err();
    assert!(
        err.contains("optix") && err.contains("embree") && err.contains("rust"),
        "{err}"
    );
    for kind in AccelKind::ALL {
        assert_eq!(AccelKind::parse(&kind.to_string()), Ok(kind));
        // clap's value names are the same names.
        use clap::ValueEnum;
        assert_eq!(kind.to_possible_value().unwrap().get_name(), kind.name());
    }
    let (v, t) = octahedron();
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    let rust = build(AccelKind::Rust, &mesh, 1).unwrap();
    assert_eq!(rust.name(), "rust");
    if cfg!(feature = "native") {
        assert_eq!(AccelKind::default(), AccelKind::Embree);
        assert_eq!(build(AccelKind::Embree, &mesh, 1).unwrap().name(), "embree");
    } else {
        assert_eq!(AccelKind::default(), AccelKind::Rust);
        let err = build(AccelKind::Embree, &mesh, 1).err().unwrap();
        assert!(
            matches!(
                err,
                AccelError::Backend {
                    backend: "embree",
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("native"), "{err}");
    }
}

#[test]
fn many_threads_see_what_one_thread_sees() {
    let soup = accel_common::triangle_soup(20_000, 31);
    for kind in available() {
        let accel = build(kind, &[soup.view()], 0).unwrap();
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(32);
        let rays: Vec<Ray> = (0..100_000)
            .map(|_| {
                Ray::new(
                    DVec3::new(rng.gen(), rng.gen(), rng.gen()),
                    random_direction(&mut rng),
                )
            })
            .collect();
        let serial: Vec<_> = rays.iter().map(|r| accel.intersect(r)).collect();
        let parallel: Vec<_> = rays.par_iter().map(|r| accel.intersect(r)).collect();
        assert_eq!(serial, parallel, "{kind}");
        assert!(serial.iter().flatten().count() > 10_000);
    }
}

#[test]
fn a_ray_leaving_a_surface_with_tmin_above_zero_skips_it() {
    // From points exactly on the octahedron's faces (in f64), inward, with
    // tmin = 1e-9: the face the ray starts on is at t = 0 and must be
    // skipped; the hit is on the far side. The Rust BVH decides the
    // interval in f64 (tracing again past a hit below tmin), so this holds
    // for any tmin > 0; Embree's f32 decision needs tmin above its
    // rounding, so it is checked with 1e-4.
    let (v, t) = octahedron();
    let mesh = [TriangleMesh {
        vertices: &v,
        triangles: &t,
    }];
    for kind in available() {
        let accel = build(kind, &mesh, 0).unwrap();
        let tmin = if accel.name() == "rust" { 1e-9 } else { 1e-4 };
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(41);
        for _ in 0..20_000 {
            let (a, b) = (rng.gen::<f64>(), rng.gen::<f64>());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            // On x + y + z = 1, inside the face.
            let on_face = DVec3::new(1.0 - a - b, a, b) * 0.9 + DVec3::splat(0.1 / 3.0);
            let inward = -random_direction(&mut rng).abs() - DVec3::splat(0.1);
            let ray = Ray {
                origin: on_face,
                dir: inward,
                tmin,
                tmax: f64::INFINITY,
            };
            // Where the ray leaves through the other faces.
            let exact = (0..8)
                .map(|i| {
                    let s = DVec3::new(
                        if i & 1 == 0 { 1.0 } else { -1.0 },
                        if i & 2 == 0 { 1.0 } else { -1.0 },
                        if i & 4 == 0 { 1.0 } else { -1.0 },
                    );
                    (1.0 - s.dot(on_face)) / s.dot(inward)
                })
                .filter(|&t| t > 1e-6)
                .fold(f64::INFINITY, f64::min);
            let h = accel.intersect(&ray).expect("the far side");
            assert!(
                (h.t - exact).abs() < 1e-4 * exact,
                "{kind}: t {} vs {exact}",
                h.t
            );
            assert!(h.t >= tmin);
        }
    }
}
