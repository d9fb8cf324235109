//! The renderer against physics it must reproduce (docs/physics.md §8.5), on small
//! images: direct views of lights, Brewster reflection, calcite double
//! refraction, a Fresnel rhomb. Each checks a number the renderer did not
//! compute itself.
//!
//! Every test runs on each intersection backend of the build
//! (`embree::…`, `rust::…`).

use crate::support::render as common;
use common::*;
use spar::accel::AccelKind;
use spar::render::approx::CoherenceModel;

/// Every check here holds in both ways paths may combine (docs/physics.md
/// §9): the physical model (the default) and the seed paper's incoherent
/// one.
const MODELS: [CoherenceModel; 2] = [CoherenceModel::Physical, CoherenceModel::Incoherent];

on_every_backend!(
    direct_view_of_an_unpolarized_light_is_unpolarized,
    direct_view_of_a_polarizer_shows_its_axis,
    glass_at_brewsters_angle_reflects_s_polarized_light,
    calcite_slab_doubles_a_line_with_the_walk_off_displacement,
    fresnel_rhomb_makes_circular_light,
);

/// A camera looking straight down at a light 5 units below.
fn direct_view(polarization: &str) -> String {
    format!(
        r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [8, 8]
samples = 2
[[light]]
corners = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]]
radiance = 1.0
polarization = {polarization}
"#
    )
}

fn direct_view_of_an_unpolarized_light_is_unpolarized(accel: AccelKind) {
    for model in MODELS {
        direct_view_of_an_unpolarized_light_is_unpolarized_in(accel, model);
    }
}

fn direct_view_of_an_unpolarized_light_is_unpolarized_in(accel: AccelKind, model: CoherenceModel) {
    let (scene, _d) = scene(&direct_view("\"unpolarized\""), &[]);
    let (film, _) = render_model(&scene, &[580.0], accel, model);
    let s = mean_stokes(&film, 0, 8, 0, 8, 0);
    let (p, _, _) = polarimetry(s);
    assert!(p < 1e-12, "P = {p}");
    // Radiance is D65 at 580 nm times the scale. The film stores f32 sums
    // (render::film), and two equal samples add exactly: the mean is D65
    // rounded to f32, bit for bit.
    let d65 = spar::spectrum::cie::d65(580.0);
    assert_eq!(s[0], d65 as f32 as f64, "S0 {} vs D65 {d65}", s[0]);
}

fn direct_view_of_a_polarizer_shows_its_axis(accel: AccelKind) {
    for model in MODELS {
        direct_view_of_a_polarizer_shows_its_axis_in(accel, model);
    }
}

fn direct_view_of_a_polarizer_shows_its_axis_in(accel: AccelKind, model: CoherenceModel) {
    // Camera right is world +x, image up world +y: a polarizer along
    // (1, 1, 0) is at +45° from image right toward image up (S2 > 0), and
    // passes half of the light (Malus, averaged over unpolarized input).
    let (scene, _d) = scene(&direct_view("{ linear = [1.0, 1.0, 0.0] }"), &[]);
    let (film, _) = render_model(&scene, &[580.0], accel, model);
    // Each pixel is fully polarized. Its frame follows its own rays (x is
    // image right made transverse to the ray), so off-axis pixels see the
    // axis a little away from 45°, and samples within a pixel differ by a
    // fraction of the pixel's 1.25° angle: P stays within 1e-6 of 1.
    for y in 0..8 {
        for x in 0..8 {
            let (p, _, _) = polarimetry(film.stokes(x, y, 0));
            assert!(p > 1.0 - 1e-6, "P = {p} at ({x}, {y})");
        }
    }
    // The four centre pixels straddle the optical axis: 45° to 0.05°.
    let s = mean_stokes(&film, 3, 5, 3, 5, 0);
    let (_, psi, _) = polarimetry(s);
    assert!((psi - 45.0).abs() < 0.05, "azimuth {psi}");
    assert!(s[2] > 0.0);
    // Within the f32 rounding of the film's sums (2^-24 relative per
    // rounding; the four-pixel mean adds two more).
    let d65 = spar::spectrum::cie::d65(580.0);
    assert!(
        (s[0] - 0.5 * d65).abs() < 3.0 * f32::EPSILON as f64 * d65,
        "S0 {} vs half of D65 {d65}",
        s[0]
    );
    // Along x: horizontal, S1 > 0, azimuth 0.
    let (scene2, _d2) = common::scene(&direct_view("{ linear = [1.0, 0.0, 0.0] }"), &[]);
    let (film, _) = render_model(&scene2, &[580.0], accel, model);
    let (_, psi, _) = polarimetry(mean_stokes(&film, 3, 5, 3, 5, 0));
    assert!(psi.abs() < 0.05, "azimuth {psi}");
}

/// A thick glass plate seen at Brewster's angle, reflecting a light.
fn glass_at_brewsters_angle_reflects_s_polarized_light(accel: AccelKind) {
    for model in MODELS {
        glass_at_brewsters_angle_reflects_s_polarized_light_in(accel, model);
    }
}

fn glass_at_brewsters_angle_reflects_s_polarized_light_in(accel: AccelKind, model: CoherenceModel) {
    let n: f64 = 1.5;
    let theta = n.atan(); // Brewster's angle from air
    let (s, c) = theta.sin_cos();
    let toml = format!(
        r#"
[camera]
eye = [0.0, {ey}, {ez}]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 0.5
resolution = [6, 6]
samples = 4
[render]
max_depth = 6
prune = 0.0
[[object]]
mesh = "plate.obj"
medium = "iso:{n}"
[[light]]
corners = [[{lx0}, {ly0}, {lz0}], [{lx1}, {ly0}, {lz0}], [{lx1}, {ly1}, {lz1}], [{lx0}, {ly1}, {lz1}]]
radiance = 1.0
"#,
        ey = -10.0 * s,
        ez = 10.0 * c,
        // A light square facing the mirror direction, centred on it.
        lx0 = 3.0,
        lx1 = -3.0,
        ly0 = 10.0 * s - 3.0 * c,
        lz0 = 10.0 * c + 3.0 * s,
        ly1 = 10.0 * s + 3.0 * c,
        lz1 = 10.0 * c - 3.0 * s,
    );
    let plate = box_obj([-20.0, -20.0, -1.0], [20.0, 20.0, 0.0]);
    let (scene, _d) = scene(&toml, &[("plate.obj", plate)]);
    let (film, stats) = render_model(&scene, &[580.0], accel, model);
    assert_eq!(stats.lost, 0);
    let st = mean_stokes(&film, 0, 6, 0, 6, 0);
    let (p, psi, _) = polarimetry(st);
    eprintln!("brewster: P = {p}, azimuth {psi}°");
    // Every path to the light reflects at Brewster's angle at least once
    // (inside too: the internal angle is Brewster's for n2 → n1), and
    // rp = 0 there: s-polarized, perpendicular to the plane of incidence,
    // which is horizontal in the image.
    assert!(p > 0.999, "P = {p}");
    assert!(psi.abs() < 0.1, "azimuth {psi}");
    // Reflected intensity: Rs of unpolarized light (half of it is s) at the
    // top surface, plus the paths through the plate (checked loosely: the
    // first-surface term alone is the lower bound).
    let rs = {
        let ct = (1.0 - (s / n).powi(2)).sqrt();
        ((c - n * ct) / (c + n * ct)).powi(2)
    };
    let d65 = spar::spectrum::cie::d65(580.0);
    let first = 0.5 * rs * d65;
    assert!(
        st[0] >= first * (1.0 - 1e-9) && st[0] < 2.5 * first,
        "S0 {} vs first-surface {first}",
        st[0]
    );
}

/// A calcite slab, axis at 45° to its faces, over a thin bright line: two
/// images, displaced by d·tan ρ = 0.1091 d (ρ the walk-off, docs/physics.md §8.3),
/// each fully polarized, the polarizations orthogonal.
fn calcite_slab_doubles_a_line_with_the_walk_off_displacement(accel: AccelKind) {
    for model in MODELS {
        calcite_slab_doubles_a_line_with_the_walk_off_displacement_in(accel, model);
    }
}

fn calcite_slab_doubles_a_line_with_the_walk_off_displacement_in(
    accel: AccelKind,
    model: CoherenceModel,
) {
    let d = 1.0;
    let toml = r#"
[camera]
eye = [0.0, 0.0, 200.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 0.1718873385
resolution = [8, 120]
samples = 64
[render]
max_depth = 4
prune = 0.0
[media.slab]
n_o = 1.6584
n_e = 1.4864
[[object]]
mesh = "slab.obj"
medium = "slab"
optic_axis = [0.0, 0.70710678118654752, 0.70710678118654752]
[[light]]
corners = [[-5.0, -0.005, -3.0], [5.0, -0.005, -3.0], [5.0, 0.005, -3.0], [-5.0, 0.005, -3.0]]
radiance = 1.0
"#;
    // The image spans 2·200·tan(0.0859437°) = 0.6 units over 120 rows:
    // 0.005 units per row.
    let slab = box_obj([-10.0, -10.0, -d], [10.0, 10.0, 0.0]);
    let (scene, _dir) = scene(toml, &[("slab.obj", slab)]);
    let (film, _) = render_model(&scene, &[589.3], accel, model);
    let rows: Vec<[f64; 4]> = (0..120)
        .map(|y| mean_stokes(&film, 0, 8, y, y + 1, 0))
        .collect();
    let profile: Vec<f64> = rows.iter().map(|s| s[0]).collect();
    // The two brightest separated peaks, by their intensity centroids.
    let peak = |skip: Option<usize>| -> usize {
        (0..120)
            .filter(|&y| skip.is_none_or(|p: usize| (y as i64 - p as i64).abs() > 6))
            .max_by(|&a, &b| profile[a].total_cmp(&profile[b]))
            .unwrap()
    };
    let p1 = peak(None);
    let p2 = peak(Some(p1));
    let centroid = |p: usize| -> f64 {
        let (mut m, mut w) = (0.0, 0.0);
        let lo = p.saturating_sub(4);
        for (y, v) in profile.iter().enumerate().take((p + 5).min(120)).skip(lo) {
            m += y as f64 * v;
            w += v;
        }
        m / w
    };
    let (c1, c2) = (centroid(p1), centroid(p2));
    let separation = (c1 - c2).abs() * 0.005;
    eprintln!("slab: separation {separation}, peaks at rows {p1} {p2}");
    // tan ρ for the wave normal at 45° to the axis (docs/physics.md §4.3).
    let (no, ne) = (1.6584f64, 1.4864f64);
    let inv_n2 = 0.5 / (no * no) + 0.5 / (ne * ne);
    let tan_rho = 0.5 / inv_n2 * (1.0 / (ne * ne) - 1.0 / (no * no));
    let expected = d * tan_rho;
    assert!((expected - 0.1091).abs() < 5e-4, "tan ρ = {tan_rho}");
    // Rows are 0.005 units at the look-at plane (200 units from the eye);
    // the two ray bundles are displaced at the line, 203 units away, so
    // the image shows d·tan ρ · 200/203. The centroids are good to a
    // fraction of a row: allow 0.2 row.
    let in_image = expected * 200.0 / 203.0;
    assert!(
        (separation - in_image).abs() < 0.001,
        "separation {separation} vs {in_image}"
    );
    // Each image fully polarized, the two orthogonal (azimuths 90° apart).
    let s1 = mean_stokes(&film, 0, 8, p1 as u32, p1 as u32 + 1, 0);
    let s2 = mean_stokes(&film, 0, 8, p2 as u32, p2 as u32 + 1, 0);
    let (pa, psia, _) = polarimetry(s1);
    let (pb, psib, _) = polarimetry(s2);
    assert!(pa > 0.99 && pb > 0.99, "P {pa} {pb}");
    let diff = (psia - psib).abs();
    assert!((diff - 90.0).abs() < 1.0, "azimuths {psia} {psib}");
    // Each carries about half an unpolarized beam's transmitted power
    // (0.4405 and 0.4526 of it through a slab, docs/physics.md §8.3): equal powers
    // within 5 %. The power of an image is its sum over the rows around its
    // peak; a peak row alone depends on where the 2-row-wide line falls
    // within it, and at 8 samples per pixel the sums still vary by several
    // percent with the sample positions, hence 64.
    let power = |p: usize| -> f64 { profile[p.saturating_sub(4)..(p + 5).min(120)].iter().sum() };
    eprintln!("slab: powers {} {}", power(p1), power(p2));
    assert!(
        (power(p1) / power(p2) - 1.0).abs() < 0.05,
        "powers {} {}",
        power(p1),
        power(p2)
    );
}

/// A Fresnel rhomb of n = 1.51 with 54.6° angles: two total internal
/// reflections turn light linear at 45° to the plane of incidence into
/// circular light (docs/physics.md §8.2).
fn fresnel_rhomb_makes_circular_light(accel: AccelKind) {
    for model in MODELS {
        fresnel_rhomb_makes_circular_light_in(accel, model);
    }
}

fn fresnel_rhomb_makes_circular_light_in(accel: AccelKind, model: CoherenceModel) {
    let theta = 54.6f64.to_radians();
    // Cross-section in the x–z plane: a parallelogram whose long faces are
    // horizontal (z = 0 and z = h) and whose end faces make angle θ with
    // them. Light enters the left end face at normal incidence, meets the
    // long faces at incidence θ.
    let h = 1.0;
    let run = h / theta.tan(); // horizontal run of an end face
    let length = 2.0 * h * theta.tan() + run; // enough for two reflections
    let (sx, sz) = (theta.sin(), theta.cos());
    let poly = [[0.0, 0.0], [length, 0.0], [length + run, h], [run, h]];
    // The end face from (0,0) to (run, h) has outward normal (−sin θ, cos θ)·…:
    // a ray entering it normally travels along (sin θ, −cos θ)·(−1)…
    // Build the rays from geometry instead of hand algebra:
    let end_dir = [run, h];
    let len = (run * run + h * h).sqrt();
    let inward = [end_dir[1] / len, -end_dir[0] / len]; // normal into the prism
    let _ = (sx, sz);
    let mid_in = [0.5 * run, 0.5 * h];
    let mid_out = [length + 0.5 * run, 0.5 * h];
    // The exit face is parallel to the entry face; after two reflections
    // the ray leaves along `inward` again.
    let light_c = [mid_in[0] - 3.0 * inward[0], mid_in[1] - 3.0 * inward[1]];
    let eye = [mid_out[0] + 50.0 * inward[0], mid_out[1] + 50.0 * inward[1]];
    // The light: a square facing along `inward`, its plane spanned by y and
    // the in-plane perpendicular of `inward`; polarizer at 45° between them.
    let perp = [-inward[1], inward[0]];
    let hw = 1.0;
    let c = |a: f64, b: f64| [light_c[0] + a * perp[0], b, light_c[1] + a * perp[1]];
    let (c0, c1, c2, c3) = (c(-hw, -hw), c(hw, -hw), c(hw, hw), c(-hw, hw));
    // Emitting side is (c1 − c0) × (c3 − c0) = perp × y; flip if needed.
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let u = [c1[0] - c0[0], c1[1] - c0[1], c1[2] - c0[2]];
    let v = [c3[0] - c0[0], c3[1] - c0[1], c3[2] - c0[2]];
    let nrm = cross(u, v);
    let facing = nrm[0] * inward[0] + nrm[2] * inward[1] > 0.0;
    let corners = if facing {
        [c0, c1, c2, c3]
    } else {
        [c0, c3, c2, c1]
    };
    let pol = [perp[0] + 0.0, 1.0, perp[1]];
    let fmt3 = |p: [f64; 3]| format!("[{}, {}, {}]", p[0], p[1], p[2]);
    let toml = format!(
        r#"
[camera]
eye = [{ex}, 0.0, {ez}]
look_at = [{lx}, 0.0, {lz}]
up = [0.0, 1.0, 0.0]
fov = 0.2
resolution = [4, 4]
samples = 1
[render]
max_depth = 8
prune = 0.0
[[object]]
mesh = "rhomb.obj"
medium = "iso:1.51"
[[light]]
corners = [{a}, {b}, {cc}, {dd}]
radiance = 1.0
polarization = {{ linear = {pol} }}
"#,
        ex = eye[0],
        ez = eye[1],
        lx = mid_out[0],
        lz = mid_out[1],
        a = fmt3(corners[0]),
        b = fmt3(corners[1]),
        cc = fmt3(corners[2]),
        dd = fmt3(corners[3]),
        pol = fmt3(pol),
    );
    let rhomb = prism_obj(&poly, -1.0, 1.0);
    let (scene, _d) = scene(&toml, &[("rhomb.obj", rhomb)]);
    let (film, stats) = render_model(&scene, &[589.3], accel, model);
    assert_eq!(stats.lost, 0);
    let s = mean_stokes(&film, 0, 4, 0, 4, 0);
    assert!(s[0] > 0.0, "the camera sees the light through the rhomb");
    let (_, _, b_over_a) = polarimetry(s);
    eprintln!("rhomb: b/a = {b_over_a}, Stokes {s:?}");
    assert!(b_over_a > 0.99, "b/a = {b_over_a}, Stokes {s:?}");
}
