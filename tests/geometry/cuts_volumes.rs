//! Every generated cut is a closed, consistently oriented, convex solid
//! whose volume agrees with computations that never look at the mesh:
//! closed-form volumes where the cut is a simple solid, an integral of
//! horizontal cross-sections cut from the planes in 2-D, and a Monte Carlo
//! estimate over the planes.

use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::geometry::convex::HalfSpace;
use spar::geometry::cuts::{Brilliant, Cut, Emerald, Princess};
use spar::geometry::Mesh;

/// The cuts under test, with their expected facet counts (documented in
/// each cut's module).
fn cuts() -> Vec<(Cut, usize)> {
    vec![
        (Cut::RoundBrilliant(Brilliant::default()), 73),
        (
            Cut::RoundBrilliant(Brilliant {
                girdle: 0.0,
                culet: 0.03,
                ..Default::default()
            }),
            58,
        ),
        (Cut::Oval(Brilliant::default()), 73),
        (Cut::Princess(Princess::default()), 33),
        (
            Cut::Princess(Princess {
                chevrons: 5,
                crown_steps: 1,
                angle_step: 3.0,
                ..Default::default()
            }),
            1 + 4 + 4 + 4 * 9,
        ),
        (Cut::Emerald(Emerald::default()), 53),
        (
            Cut::Emerald(Emerald {
                corner: 0.0,
                ..Default::default()
            }),
            1 + 12 + 4 + 12,
        ),
    ]
}

fn planes(cut: &Cut) -> Vec<HalfSpace> {
    cut.planes().unwrap().into_iter().map(|p| p.plane).collect()
}

/// Checks closure, orientation, convexity; returns the mesh.
fn solid(cut: &Cut, facets: usize) -> Mesh {
    let stone = cut.stone().unwrap();
    assert!(stone.notes.is_empty(), "{}: {:?}", cut.name(), stone.notes);
    let mesh = stone.mesh;
    mesh.check_closed_and_oriented().unwrap();
    assert_eq!(mesh.facets.len(), facets, "{cut:?}");
    // Convex: every vertex on or below every facet plane.
    let scale = mesh.bounds().1.length();
    for f in &mesh.facets {
        for p in &mesh.positions {
            assert!(
                f.normal.dot(*p) - f.offset < 1e-12 * scale,
                "{cut:?}: not convex at {:?}",
                f.name
            );
        }
        // Every facet lies in its plane.
        for &v in &f.vertices {
            assert!((f.normal.dot(mesh.positions[v as usize]) - f.offset).abs() < 1e-12 * scale);
        }
    }
    mesh
}

/// Area of the section at height z: a large square clipped by every
/// plane's trace n_x x + n_y y <= d − n_z z (Sutherland–Hodgman in 2-D).
fn section_area(planes: &[HalfSpace], z: f64) -> f64 {
    let big = 1e3;
    let mut poly = vec![
        DVec2::new(-big, -big),
        DVec2::new(big, -big),
        DVec2::new(big, big),
        DVec2::new(-big, big),
    ];
    for p in planes {
        let n = p.normal.truncate();
        let d = p.offset - p.normal.z * z;
        let inside = |q: DVec2| n.dot(q) <= d;
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            if inside(a) {
                out.push(a);
            }
            if inside(a) != inside(b) {
                let t = (d - n.dot(a)) / n.dot(b - a);
                out.push(a + t * (b - a));
            }
        }
        poly = out;
        if poly.is_empty() {
            return 0.0;
        }
    }
    let n = poly.len();
    (0..n)
        .map(|i| poly[i].perp_dot(poly[(i + 1) % n]))
        .sum::<f64>()
        / 2.0
}

/// ∫ A(z) dz by composite Simpson, split at the heights of horizontal
/// planes (table, culet), where A(z) jumps; elsewhere A(z) is continuous
/// and piecewise quadratic.
fn volume_by_sections(planes: &[HalfSpace], lo: f64, hi: f64) -> f64 {
    let mut cuts = vec![lo, hi];
    for p in planes {
        if p.normal.truncate().length() == 0.0 {
            cuts.push(p.offset / p.normal.z);
        }
    }
    cuts.retain(|z| (lo..=hi).contains(z));
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2).map(|w| simpson(planes, w[0], w[1])).sum()
}

fn simpson(planes: &[HalfSpace], lo: f64, hi: f64) -> f64 {
    let n = 10_000;
    let h = (hi - lo) / n as f64;
    // Stay just inside the interval so a jump at its ends is not sampled.
    let at = |z: f64| section_area(planes, z.clamp(lo + 1e-12, hi - 1e-12));
    let mut sum = at(lo) + at(hi);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * at(lo + i as f64 * h);
    }
    sum * h / 3.0
}

/// Monte Carlo volume over the box [lo, hi]: the estimate and its
/// standard error.
fn volume_monte_carlo(planes: &[HalfSpace], lo: DVec3, hi: DVec3, samples: usize) -> (f64, f64) {
    let mut rng = Pcg64::seed_from_u64(0x5eed);
    let inside = (0..samples)
        .filter(|_| {
            let u = DVec3::new(rng.gen(), rng.gen(), rng.gen());
            let p = lo + u * (hi - lo);
            planes.iter().all(|h| h.normal.dot(p) <= h.offset)
        })
        .count();
    let box_volume = (hi - lo).element_product();
    let f = inside as f64 / samples as f64;
    (
        box_volume * f,
        box_volume * (f * (1.0 - f) / samples as f64).sqrt(),
    )
}

#[test]
fn every_cut_is_closed_oriented_convex_with_its_facet_count() {
    for (cut, facets) in cuts() {
        solid(&cut, facets);
    }
}

#[test]
fn volumes_agree_with_sections_of_the_planes() {
    for (cut, facets) in cuts() {
        let mesh = solid(&cut, facets);
        let (lo, hi) = mesh.bounds();
        let want = volume_by_sections(&planes(&cut), lo.z - 0.01, hi.z + 0.01);
        let got = mesh.signed_volume();
        eprintln!("{}: mesh {got:.9}, sections {want:.9}", cut.name());
        assert!(
            (got - want).abs() < 1e-7 * want,
            "{}: {got} vs {want}",
            cut.name()
        );
    }
}

#[test]
fn princess_volume_agrees_with_monte_carlo() {
    // 10⁶ uniform points in a box around the stone; the estimate's standard
    // error is about 0.1 % of the volume; allow four of them.
    let cut = Cut::Princess(Princess::default());
    let mesh = solid(&cut, 33);
    let (lo, hi) = mesh.bounds();
    let pad = DVec3::splat(0.01);
    let (estimate, sigma) = volume_monte_carlo(&planes(&cut), lo - pad, hi + pad, 1_000_000);
    let got = mesh.signed_volume();
    eprintln!("princess: mesh {got:.6}, Monte Carlo {estimate:.6} ± {sigma:.6}");
    assert!(
        (got - estimate).abs() < 4.0 * sigma,
        "{got} vs {estimate} ± {sigma}"
    );
}

#[test]
fn simple_princess_and_emerald_have_their_closed_form_volumes() {
    // Princess with one crown ring and no chevrons: a square frustum (the
    // crown), a square slab (the girdle) and a square pyramid (the pavilion).
    let p = Princess {
        crown_steps: 1,
        chevrons: 1,
        ..Default::default()
    };
    let (w, t) = (p.width, p.table * p.width);
    let crown_h = (w - t) / 2.0 * p.crown_angle.to_radians().tan();
    let pavilion_h = w / 2.0 * p.pavilion_angle.to_radians().tan();
    let want =
        crown_h / 3.0 * (w * w + w * t + t * t) + w * w * p.girdle * w + w * w * pavilion_h / 3.0;
    let mesh = solid(&Cut::Princess(p), 1 + 4 + 4 + 4);
    assert!(
        (mesh.signed_volume() - want).abs() < 1e-13,
        "{} vs {want}",
        mesh.signed_volume()
    );

    // Emerald with square corners, one ring each: the crown's sections are
    // (L − 2s)(W − 2s) rectangles up to s = (W − T)/2, rising tan θc per
    // unit of s; the pavilion is a hip roof of height W/2 · tan θp, volume
    // tan θp · W² (L/4 − W/12).
    let e = Emerald {
        corner: 0.0,
        crown_steps: 1,
        pavilion_steps: 1,
        ..Default::default()
    };
    let (w, l) = (e.width, e.width * e.ratio);
    let s = w / 2.0 * (1.0 - e.table);
    let crown =
        e.crown_angle.to_radians().tan() * (l * w * s - (l + w) * s * s + 4.0 / 3.0 * s * s * s);
    let pavilion = e.pavilion_angle.to_radians().tan() * w * w * (l / 4.0 - w / 12.0);
    let want = crown + l * w * e.girdle * w + pavilion;
    let mesh = solid(&Cut::Emerald(e), 1 + 4 + 4 + 4);
    assert!(
        (mesh.signed_volume() - want).abs() < 1e-13,
        "{} vs {want}",
        mesh.signed_volume()
    );
}
