//! Coherent light (docs/physics.md §9): the polariscope scenes of
//! `scenes/polariscope/` against closed forms computed here, from
//! textbook optics and the media's indices, never from spar's integrator:
//! normal-incidence Fresnel amplitudes, Airy sums of a plate's multiply
//! reflected waves, the uniaxial eigenwaves' k_z, Jones calculus for the
//! polarizers and plates.

use crate::support::render::render_at;
use num_complex::Complex64;
use spar::optics::{Coherence, Medium};
use spar::render::integrator::{Stats, Tracer, WavelengthMedia};
use spar::render::prepare;
use spar::scene::Scene;
use std::f64::consts::PI;
use std::path::Path;

type C = Complex64;

fn load(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/polariscope")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Indices (n_o, n_e) of an object's medium at `lambda` nm.
fn indices(scene: &Scene, object: usize, lambda: f64) -> (f64, f64) {
    match WavelengthMedia::new(scene, lambda).objects[object] {
        Medium::Uniaxial { n_o, n_e, .. } => (n_o, n_e),
        Medium::Isotropic { n } => (n, n),
        other => panic!("the polariscope scenes have no biaxial objects: {other:?}"),
    }
}

/// Thickness (z extent) of an object, scene units.
fn thickness(scene: &Scene, object: usize) -> f64 {
    let (lo, hi) = scene.objects[object].mesh.bounds();
    hi.z - lo.z
}

/// Energy-normalized amplitude through a plate of index `n`, thickness
/// `d` (nm) at normal incidence, from air to air, as paths: the direct
/// path and `k` round trips, each `(amplitude, optical path in nm)`.
/// t₁₂t₂₁ = 4n/(1+n)² (the two faces' energy-normalized transmissions),
/// each round trip r² = ((n−1)/(n+1))² and 2nd of path.
fn plate_paths(n: f64, d: f64, round_trips: usize) -> Vec<(f64, f64)> {
    let t = 4.0 * n / ((1.0 + n) * (1.0 + n));
    let r2 = ((n - 1.0) / (n + 1.0)).powi(2);
    (0..=round_trips)
        .map(|k| (t * r2.powi(k as i32), (2 * k + 1) as f64 * n * d))
        .collect()
}

/// The Airy transmission amplitude of a plate: Σ over every round trip,
/// 4n/(1+n)² e^{iδ} / (1 − r² e^{2iδ}), δ = 2π n d / λ.
fn airy_t(n: f64, d: f64, lambda: f64) -> C {
    let r2 = ((n - 1.0) / (n + 1.0)).powi(2);
    let delta = 2.0 * PI * n * d / lambda;
    C::from_polar(4.0 * n / ((1.0 + n) * (1.0 + n)), delta)
        / (C::new(1.0, 0.0) - C::from_polar(r2, 2.0 * delta))
}

/// Stokes parameters of a Jones vector (x, y): S3 = 2 Im(Ex Ey*), the
/// convention of docs/physics.md §1.3.
fn stokes_of(e: [C; 2]) -> [f64; 4] {
    let (a, b) = (e[0], e[1]);
    [
        a.norm_sqr() + b.norm_sqr(),
        a.norm_sqr() - b.norm_sqr(),
        2.0 * (a * b.conj()).re,
        2.0 * (a * b.conj()).im,
    ]
}

fn centre_stokes(film: &spar::render::film::Film, i: usize) -> [f64; 4] {
    let (w, h) = (film.width, film.height);
    crate::support::render::mean_stokes(film, w / 2 - 2, w / 2 + 2, h / 2 - 2, h / 2 + 2, i)
}

#[test]
fn light_along_the_optic_axis_keeps_its_polarization() {
    let scene = load("optic-axis.toml");
    let (film, stats) = render_at(&scene, &[580.0]);
    assert_eq!(stats.lost, 0);
    let s = centre_stokes(&film, 0);
    let (dop, azimuth, _) = crate::support::render::polarimetry(s);
    eprintln!("optic axis: DoP {dop:.9}, azimuth {azimuth:.7}°");
    assert!(dop >= 1.0 - 1e-6, "DoP {dop}");
    assert!((azimuth - 30.0).abs() <= 1e-4, "azimuth {azimuth}°");
    // Along the axis both eigenwaves have n_o: the plate is an isotropic
    // Fabry–Perot of index n_o for a monochromatic render. The light seen
    // directly (an image corner, outside the plate) is the reference.
    let direct = film.stokes(0, 0, 0)[0];
    assert!(direct > 0.0);
    let (n_o, _) = indices(&scene, 0, 580.0);
    let d = thickness(&scene, 0) * scene.unit_nm;
    let t = airy_t(n_o, d, 580.0).norm_sqr();
    let ratio = s[0] / direct;
    eprintln!("optic axis: S0/S0_light {ratio:.6}, Airy {t:.6}");
    assert!(
        (ratio - t).abs() <= 1e-4,
        "S0/S0_light {ratio} vs Airy transmission {t} (two faces alone: {})",
        (4.0 * n_o / (1.0 + n_o).powi(2)).powi(2)
    );
}

#[test]
fn the_incoherent_model_depolarizes_along_the_optic_axis() {
    // The seed paper's model on the same scene: the check above is one
    // that model fails (docs/physics.md §5.5).
    let mut scene = load("optic-axis.toml");
    scene.settings.approx.strategy.coherence = spar::render::approx::CoherenceModel::Incoherent;
    let (film, _) = render_at(&scene, &[580.0]);
    let (dop, _, _) = crate::support::render::polarimetry(centre_stokes(&film, 0));
    assert!(dop < 0.999, "DoP {dop}");
}

/// The field after a plate of indices (n_o, n_e) and thickness d (nm)
/// whose optic axis lies in its plane at `axis_deg` from x, for incident
/// light polarized along x, at `lambda` nm, with every internal reflection
/// (monochromatic: fully coherent). The e wave's field lies along the
/// axis, the o wave's across it; each is an Airy sum of its own index.
fn waveplate_field(n_o: f64, n_e: f64, d: f64, axis_deg: f64, lambda: f64) -> [C; 2] {
    let (s, c) = axis_deg.to_radians().sin_cos();
    let e_axis = [c, s];
    let o_axis = [-s, c];
    let (te, to) = (airy_t(n_e, d, lambda), airy_t(n_o, d, lambda));
    // Incident E = (1, 0): its components along e and o.
    let (ae, ao) = (e_axis[0], o_axis[0]);
    [
        te * ae * e_axis[0] + to * ao * o_axis[0],
        te * ae * e_axis[1] + to * ao * o_axis[1],
    ]
}

#[test]
fn a_quarter_wave_plate_makes_circular_light_of_the_predicted_hand() {
    let scene = load("quarter-wave.toml");
    let (film, _) = render_at(&scene, &[580.0]);
    let s = centre_stokes(&film, 0);
    // Derivation of the sign: quartz-like, n_e > n_o, so the e wave
    // (field along the axis at 45°) lags the o wave by δ = π/2. Incident
    // E = (1, 0) = (ê − ô)/√2 with ê = (1, 1)/√2, ô = (−1, 1)/√2; after
    // the plate, up to a common phase, E ∝ e^{iπ/2} ê − ô = ((1+i), (i−1))/2,
    // so Ey = i Ex: E(t) = Re((1, i) e^{−iωt}) = (cos ωt, sin ωt) turns from
    // x to y, counter-clockwise for the camera, which looks back at the
    // light with x right and y up: left-handed, S3 = 2 Im(Ex Ey*) < 0.
    let (n_o, n_e) = indices(&scene, 0, 580.0);
    let d = thickness(&scene, 0) * scene.unit_nm;
    let expected = stokes_of(waveplate_field(n_o, n_e, d, 45.0, 580.0));
    assert!(expected[3] < 0.0);
    eprintln!(
        "quarter wave: S3/S0 {:.5} (closed form {:.5})",
        s[3] / s[0],
        expected[3] / expected[0]
    );
    assert!(s[3] / s[0] <= -0.99, "S3/S0 = {}", s[3] / s[0]);
    for c in 1..4 {
        let (got, want) = (s[c] / s[0], expected[c] / expected[0]);
        assert!(
            (got - want).abs() <= 1e-3,
            "S{c}/S0 {got} vs closed form {want}"
        );
    }
    // And the transmitted intensity relative to the light seen directly.
    let direct = film.stokes(0, 0, 0)[0];
    assert!((s[0] / direct - expected[0]).abs() <= 1e-3);
}

#[test]
fn a_half_wave_plate_rotates_linear_light_by_twice_its_axis_angle() {
    let scene = load("half-wave.toml");
    let (film, _) = render_at(&scene, &[580.0]);
    let s = centre_stokes(&film, 0);
    let (dop, azimuth, _) = crate::support::render::polarimetry(s);
    eprintln!("half wave: DoP {dop:.6}, azimuth {azimuth:.4}°");
    assert!(dop >= 0.999, "DoP {dop}");
    // Linear light at 0° through a half-wave plate at 22.5° leaves at
    // 2 · 22.5° − 0° = 45°.
    assert!((azimuth - 45.0).abs() <= 0.05, "azimuth {azimuth}°");
    let (n_o, n_e) = indices(&scene, 0, 580.0);
    let d = thickness(&scene, 0) * scene.unit_nm;
    let expected = stokes_of(waveplate_field(n_o, n_e, d, 22.5, 580.0));
    for c in 1..4 {
        let (got, want) = (s[c] / s[0], expected[c] / expected[0]);
        assert!((got - want).abs() <= 1e-3, "S{c}/S0 {got} vs {want}");
    }
}

/// Transmission of a plate (axis at 45°, thickness d nm) between crossed
/// polarizers (x, then y) for unit intensity behind the first polarizer,
/// at `lambda` with a band `band` nm wide: the o and e paths (direct and
/// `round_trips` round trips each) add with the band's coherence
/// sinc(π ΔL Δλ/λ²) on every cross term (docs/physics.md §9.4). The y
/// component of path p is ±½ a_p e^{iφ_p} (e: +, o: −).
fn crossed_plate(n_o: f64, n_e: f64, d: f64, lambda: f64, band: f64) -> f64 {
    let mut paths: Vec<(f64, f64)> = Vec::new(); // (signed amplitude, optical path)
    for (a, l) in plate_paths(n_e, d, 3) {
        paths.push((0.5 * a, l));
    }
    for (a, l) in plate_paths(n_o, d, 3) {
        paths.push((-0.5 * a, l));
    }
    let sinc = |x: f64| if x.abs() < 1e-12 { 1.0 } else { x.sin() / x };
    let mut i = 0.0;
    for &(ap, lp) in &paths {
        for &(aq, lq) in &paths {
            let dl = lp - lq;
            i +=
                ap * aq * sinc(PI * dl * band / (lambda * lambda)) * (2.0 * PI * dl / lambda).cos();
        }
    }
    i
}

#[test]
fn the_michel_levy_chart_matches_plates_between_crossed_polarizers() {
    let scene = load("michel-levy.toml");
    let lambdas = scene.settings.wavelengths.lambdas().to_vec();
    assert!(lambdas.len() >= 41);
    let (film, stats) = render_at(&scene, &lambdas);
    assert_eq!(stats.lost, 0);
    let observer = spar::spectrum::Observer::new(&scene.settings.wavelengths).unwrap();
    let width = 54.0; // the camera's width, mm
    let px = |x_mm: f64| ((x_mm / width + 0.5) * film.width as f64) as u32;
    let py = film.height / 2;
    let (mut worst, mut worst_rgb): (f64, f64) = (0.0, 0.0);
    for k in 0..21usize {
        let x = (k as f64 - 10.0) * 2.5;
        let (mut rendered, mut closed) = (Vec::new(), Vec::new());
        for (i, &lambda) in lambdas.iter().enumerate() {
            let band = if i == 0 {
                lambdas[1] - lambdas[0]
            } else if i + 1 == lambdas.len() {
                lambdas[i] - lambdas[i - 1]
            } else {
                0.5 * (lambdas[i + 1] - lambdas[i - 1])
            };
            // Unpolarized light of radiance D65 through the first polarizer.
            let light = 0.5 * spar::spectrum::cie::d65(lambda);
            let t = if k == 0 {
                0.0
            } else {
                // Step k's plate is object k − 1.
                let (n_o, n_e) = indices(&scene, k - 1, lambda);
                let d = thickness(&scene, k - 1) * scene.unit_nm;
                crossed_plate(n_o, n_e, d, lambda, band)
            };
            let s0 = film.stokes(px(x), py, i)[0];
            worst = worst.max((s0 - t * light).abs() / light);
            assert!(
                (s0 - t * light).abs() <= 1e-3 * light,
                "step {k} ({} nm retardation) at {lambda} nm: S0 {s0} vs closed form {}",
                100 * k,
                t * light
            );
            rendered.push(s0);
            closed.push(t * light);
        }
        let (a, b) = (observer.srgb(&rendered), observer.srgb(&closed));
        for c in 0..3 {
            worst_rgb = worst_rgb.max((a[c] - b[c]).abs());
            assert!(
                (a[c] - b[c]).abs() <= 0.01,
                "step {k}: sRGB {a:?} vs closed form {b:?}"
            );
        }
    }
    eprintln!(
        "Michel-Lévy: worst |S0 − closed form| {worst:.2e} of the light, worst sRGB {worst_rgb:.2e}"
    );
}

/// Intensity behind the camera's analyzer of the camera ray through film
/// direction `dir`, at `lambda` nm (one wavelength: fully coherent).
fn analyzed(scene: &Scene, tracer: &Tracer, dir: glam::DVec3, lambda: f64) -> f64 {
    let (x, y) = scene.camera.stokes_frame(dir);
    let media = WavelengthMedia::new(scene, lambda);
    let mut stats = Stats::default();
    let j: Coherence = tracer.camera_ray(scene.camera.eye, dir, [x, y], &media, &mut stats);
    j.transform(scene.camera.analyzer.as_ref().unwrap())
        .intensity()
}

#[test]
fn the_conoscope_shows_a_dark_cross_and_rings_where_the_path_difference_is_whole_waves() {
    let scene = load("conoscope-calcite.toml");
    let accel = prepare::accel(&scene, Default::default(), 1, None).unwrap();
    let tracer = Tracer::new(&scene, accel.as_ref(), prepare::tree(&scene))
        .with_strategy(scene.settings.approx.strategy);
    let lambda = 580.0;
    let (n_o, n_e) = indices(&scene, 0, lambda);
    let d = thickness(&scene, 0) * scene.unit_nm;
    // A ray at polar angle θ from the axis (−z) and azimuth φ from x.
    let ray = |theta: f64, phi: f64| {
        let (st, ct) = theta.sin_cos();
        glam::DVec3::new(st * phi.cos(), st * phi.sin(), -ct)
    };
    // The o/e path difference of a plane wave at θ in air through a plate
    // with its axis along the normal: tangential t = sin θ is shared;
    // k_z,o = √(n_o² − t²); the e wave's normal surface
    // k_t²/n_e² + k_z²/n_o² = 1 gives k_z,e = n_o √(1 − t²/n_e²). Both
    // waves meet at the exit face with the same tangential phase, so
    // Γ(θ) = d (k_z,o − k_z,e).
    let gamma = |theta: f64| {
        let t = theta.sin();
        d * ((n_o * n_o - t * t).sqrt() - n_o * (1.0 - t * t / (n_e * n_e)).sqrt())
    };
    let ring = |m: f64| {
        // Γ grows monotonically with θ: bisect Γ(θ) = m λ.
        let (mut lo, mut hi) = (0.0f64, 0.35f64);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if gamma(mid) < m * lambda {
                lo = mid
            } else {
                hi = mid
            }
        }
        0.5 * (lo + hi)
    };
    // Along the diagonal (azimuth 45°, between the cross's arms) scan θ
    // and find the intensity minima near each predicted ring.
    let phi = PI / 4.0;
    let mut brightest: f64 = 0.0;
    for m in 1..=5 {
        let predicted = ring(m as f64);
        let half_width = 0.25 * (ring(m as f64 + 0.5) - ring(m as f64 - 0.5));
        // Golden-section search for the minimum within ± half_width.
        let (mut a, mut b) = (predicted - half_width, predicted + half_width);
        let g = (5f64.sqrt() - 1.0) / 2.0;
        for _ in 0..60 {
            let (c1, c2) = (b - g * (b - a), a + g * (b - a));
            if analyzed(&scene, &tracer, ray(c1, phi), lambda)
                < analyzed(&scene, &tracer, ray(c2, phi), lambda)
            {
                b = c2
            } else {
                a = c1
            }
        }
        let found = 0.5 * (a + b);
        let rel = (found - predicted).abs() / predicted;
        eprintln!(
            "conoscope ring {m}: dark at {:.4}°, predicted {:.4}°",
            found.to_degrees(),
            predicted.to_degrees()
        );
        assert!(
            rel <= 0.01,
            "ring {m}: dark at {:.4}°, predicted {:.4}° ({:.2} %)",
            found.to_degrees(),
            predicted.to_degrees(),
            100.0 * rel
        );
        // Halfway between rings the light is bright.
        brightest = brightest.max(analyzed(
            &scene,
            &tracer,
            ray(ring(m as f64 + 0.5), phi),
            lambda,
        ));
        let dark = analyzed(&scene, &tracer, ray(found, phi), lambda);
        assert!(
            dark < 0.02 * brightest.max(1e-30),
            "ring {m}: {dark} vs {brightest}"
        );
    }
    assert!(brightest > 0.0);
    // The cross: along the polarizer (x) and analyzer (y) directions the
    // o and e fields lie along them, and the analyzer blocks the light.
    for phi in [0.0, PI / 2.0, PI, 1.5 * PI] {
        for theta_deg in [2.0f64, 5.0, 9.0, 15.0] {
            let i = analyzed(&scene, &tracer, ray(theta_deg.to_radians(), phi), lambda);
            assert!(
                i <= 1e-3 * brightest,
                "cross at azimuth {:.0}°, θ {theta_deg}°: {i} vs {brightest}",
                phi.to_degrees()
            );
        }
    }
}

/// The Airy reflectance of a free-standing film (air | n, d | air) at
/// incidence θ₀ for one polarization: r = (r₁₂ + r₂₃ e^{2iβ}) / (1 + r₁₂ r₂₃
/// e^{2iβ}) with r₂₃ = −r₁₂ (the same interface from the other side),
/// β = 2π n d cos θ₁ / λ (B&W §1.6.4).
fn airy_r(n: f64, d: f64, theta0: f64, lambda: f64, s_pol: bool) -> f64 {
    let (c0, s0) = (theta0.cos(), theta0.sin());
    let c1 = (1.0 - (s0 / n).powi(2)).sqrt();
    let r12 = if s_pol {
        (c0 - n * c1) / (c0 + n * c1)
    } else {
        (n * c0 - c1) / (n * c0 + c1)
    };
    let e = C::from_polar(1.0, 2.0 * 2.0 * PI * n * d * c1 / lambda);
    let r = (C::new(r12, 0.0) - e * r12) / (C::new(1.0, 0.0) - e * r12 * r12);
    r.norm_sqr()
}

/// One face's reflectance (Fresnel), for comparison.
fn face_r(n: f64, theta0: f64, s_pol: bool) -> f64 {
    let (c0, s0) = (theta0.cos(), theta0.sin());
    let c1 = (1.0 - (s0 / n).powi(2)).sqrt();
    let r = if s_pol {
        (c0 - n * c1) / (c0 + n * c1)
    } else {
        (n * c0 - c1) / (n * c0 + c1)
    };
    r * r
}

#[test]
fn a_thin_film_reflects_the_airy_reflectance() {
    let scene = load("thin-film.toml");
    let accel = prepare::accel(&scene, Default::default(), 1, None).unwrap();
    let tracer = Tracer::new(&scene, accel.as_ref(), prepare::tree(&scene))
        .with_strategy(scene.settings.approx.strategy);
    let (n, _) = indices(&scene, 0, 550.0);
    let d = thickness(&scene, 0) * scene.unit_nm;
    let theta0 = 30f64.to_radians();
    let dir = scene.camera.forward();
    let (x, y) = scene.camera.stokes_frame(dir);
    let mut spread: f64 = 0.0;
    for lambda in (400..=760).step_by(20).map(f64::from) {
        let media = WavelengthMedia::new(&scene, lambda);
        let mut stats = Stats::default();
        let (origin, _) = scene.camera.ray(
            scene.camera.width as f64 / 2.0,
            scene.camera.height as f64 / 2.0,
        );
        let j = tracer.camera_ray(origin, dir, [x, y], &media, &mut stats);
        assert_eq!(stats.lost, 0);
        let light = spar::spectrum::cie::d65(lambda);
        let r = j.intensity() / light;
        let airy = 0.5 * (airy_r(n, d, theta0, lambda, true) + airy_r(n, d, theta0, lambda, false));
        eprintln!("thin film {lambda} nm: R {r:.6}, Airy {airy:.6}");
        assert!(
            (r - airy).abs() <= 1e-3,
            "{lambda} nm: R {r} vs Airy {airy}"
        );
        spread = spread.max(airy);
    }
    // The film's colour is interference: its reflectance swings far above
    // a single face's.
    let single = 0.5 * (face_r(n, theta0, true) + face_r(n, theta0, false));
    assert!(
        spread > 3.0 * single,
        "largest Airy reflectance {spread}, one face {single}"
    );
    // The rendered film is uniform and agrees with the ray above.
    let (film, stats) = render_at(&scene, &[550.0]);
    assert_eq!(stats.lost, 0);
    let r = centre_stokes(&film, 0)[0] / spar::spectrum::cie::d65(550.0);
    let airy = 0.5 * (airy_r(n, d, theta0, 550.0, true) + airy_r(n, d, theta0, 550.0, false));
    assert!((r - airy).abs() <= 1e-3, "rendered R {r} vs Airy {airy}");
}

/// A calcite plate 1 mm thick, optic axis at 45° to its normal in the
/// x–z plane, seen from above through an orthographic camera; below it,
/// `light` (a TOML `[[light]]` table). Internal reflections are pruned
/// away (prune 1e-2), leaving one o and one e path per camera ray.
fn walk_off_plate(light: &str) -> String {
    format!(
        r#"
[camera]
projection = "orthographic"
width = 0.02
eye = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [4, 4]
[render]
units = "mm"
wavelengths = [580.0]
prune = 1e-2
[[object]]
mesh = "plate.obj"
medium = "calcite"
optic_axis = [0.7071067811865476, 0.0, 0.7071067811865476]
{light}
"#
    )
}

/// |J_xy| / √(J_xx J_yy) of the film's mean Stokes vector: the degree of
/// coherence between the x and y components.
fn xy_coherence(s: [f64; 4]) -> f64 {
    let (jxx, jyy) = (0.5 * (s[0] + s[1]), 0.5 * (s[0] - s[1]));
    (0.5 * (s[2] * s[2] + s[3] * s[3]).sqrt()) / (jxx * jyy).sqrt()
}

#[test]
fn walked_off_o_and_e_waves_are_as_coherent_as_the_light_is_between_them() {
    let plate = crate::support::render::box_obj([-2.0, -2.0, -0.5], [2.0, 2.0, 0.5]);
    let files = [("plate.obj", plate)];
    // The o wave leaves the plate polarized along y, the e wave along x
    // (its field lies in the plane of the axis), δ apart: the walk-off of
    // a wave normal at α = 45° to the axis, tan ρ = (n_o² − n_e²) tan α /
    // (n_e² + n_o² tan² α), over the 1 mm plate. With light polarized at
    // 45° both carry light; their cross term |J_xy| is γ √(J_xx J_yy).
    let a = 0.3; // the area light's side, mm (both paths land on it)
    let distance = 100.0; // from the plate's lower face, mm
    let area = "[[light]]\ncorners = [[-0.15, -0.15, -100.5], [0.15, -0.15, -100.5], \
                [0.15, 0.15, -100.5], [-0.15, 0.15, -100.5]]\nradiance = 1.0\n\
                polarization = { linear = [1.0, 1.0, 0.0] }\n";
    let (scene, _d) = crate::support::render::scene(&walk_off_plate(area), &files);
    let (n_o, n_e) = indices(&scene, 0, 580.0);
    let tan_rho = (n_o * n_o - n_e * n_e) / (n_e * n_e + n_o * n_o);
    let delta_nm = 1.0 * tan_rho * 1e6;
    // van Cittert–Zernike for a uniform square source of side a at distance
    // D (paraxial): the degree of coherence between points δ apart is the
    // Fourier transform of the square, sinc(π a δx / (λD)) · sinc(π a δy /
    // (λD)) (B&W §10.4.2); here δ lies along x (the axis is in the x–z
    // plane), so the second factor is 1. The square is seen from the
    // plate's lower face, `distance` below it.
    let x = PI * (a / distance) * delta_nm / 580.0;
    let gamma = x.sin() / x;
    assert!(
        gamma > 0.05 && gamma < 0.9,
        "the case tests partial coherence: γ = {gamma}"
    );
    let (film, stats) = render_at(&scene, &[580.0]);
    assert_eq!(stats.lost, 0);
    assert!(stats.coherent > 0);
    let got = xy_coherence(centre_stokes(&film, 0));
    eprintln!(
        "walk-off: degree of coherence {got:.5}, van Cittert–Zernike {gamma:.5} (x = {x:.3})"
    );
    assert!(
        (got - gamma).abs() <= 2e-3,
        "degree of coherence {got} vs van Cittert–Zernike {gamma} (x = {x})"
    );

    // A collimated light: one plane wave, fully coherent whatever δ.
    let collimated = "[[light]]\ndirection = [0.0, 0.0, 1.0]\nradiance = 1.0\n\
                      polarization = { linear = [1.0, 1.0, 0.0] }\n";
    let (scene, _d) = crate::support::render::scene(&walk_off_plate(collimated), &files);
    let (film, _) = render_at(&scene, &[580.0]);
    let got = xy_coherence(centre_stokes(&film, 0));
    // (The film stores f32 sums: 1e-6.)
    assert!((got - 1.0).abs() <= 1e-6, "collimated: {got}");

    // The incoherent model: no cross term at all.
    let (mut scene, _d) = crate::support::render::scene(&walk_off_plate(collimated), &files);
    scene.settings.approx.strategy.coherence = spar::render::approx::CoherenceModel::Incoherent;
    let (film, _) = render_at(&scene, &[580.0]);
    let got = xy_coherence(centre_stokes(&film, 0));
    assert!(got <= 1e-6, "incoherent: {got}");
}

#[test]
fn the_seed_scenes_look_the_same_in_both_models_but_where_paths_coincide() {
    // The seed scenes' light is a large rectangle under the gem: its
    // coherence area is about a wavelength across, while o and e leave a
    // gem in different directions or far apart. The models then differ
    // only in pixels where some paths of a sample coincide (Stats::coherent
    // counts them), and there by the cross terms alone.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for name in ["calcite-polarized.toml", "glass-polarized.toml"] {
        let mut scene = Scene::load(&root.join(name)).unwrap();
        scene.camera = scene.camera.clone().with_resolution(40, 40);
        let lambdas = [450.0, 550.0, 650.0];
        let (physical, stats) = render_at(&scene, &lambdas);
        scene.settings.approx.strategy.coherence = spar::render::approx::CoherenceModel::Incoherent;
        let (incoherent, _) = render_at(&scene, &lambdas);
        let (mut differ, mut total, mut sum_diff, mut sum) = (0u64, 0u64, 0.0, 0.0);
        for y in 0..40 {
            for x in 0..40 {
                for i in 0..lambdas.len() {
                    let (a, b) = (physical.stokes(x, y, i), incoherent.stokes(x, y, i));
                    total += 1;
                    let d = (0..4).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max);
                    if d > 1e-6 * (1.0 + b[0]) {
                        differ += 1;
                    }
                    sum_diff += (a[0] - b[0]).abs();
                    sum += b[0];
                }
            }
        }
        eprintln!(
            "{name}: {differ} of {total} pixel-wavelengths differ, mean |ΔS0|/S0 {:.2e}, {} coherent paths",
            sum_diff / sum,
            stats.coherent
        );
        assert!(
            differ as f64 <= 0.01 * total as f64,
            "{name}: {differ} of {total} differ"
        );
        assert!(
            differ == 0 || stats.coherent > 0,
            "{name}: differences without coherent paths"
        );
        assert!(
            sum_diff <= 1e-3 * sum,
            "{name}: mean difference {}",
            sum_diff / sum
        );
    }
}

#[test]
fn a_thin_film_beside_a_distant_object_keeps_its_rays() {
    // The film of thin-film.toml with a 10 mm plate 80 mm away: secondary
    // rays start 1e-5 of the reach of the object they leave (50 nm for
    // the film), not of the whole scene's (0.8 µm, more than the film is
    // thick: its rays stepped through it and were lost).
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/polariscope/thin-film.toml"),
    )
    .unwrap()
    .replace(
        "[[light]]",
        "[[object]]\nmesh = \"plate.obj\"\nmedium = \"film\"\n\
         transform = { translate = [80.0, 0.0, 0.0] }\n\n[[light]]",
    );
    let plate = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/polariscope/plate.obj"),
    )
    .unwrap();
    let (scene, _d) = crate::support::render::scene(&text, &[("plate.obj", plate)]);
    assert_eq!(scene.objects.len(), 2);
    let (film, stats) = render_at(&scene, &[550.0]);
    assert_eq!(stats.lost, 0, "{}", stats.lost_breakdown());
    let (n, _) = indices(&scene, 0, 550.0);
    let d = thickness(&scene, 0) * scene.unit_nm;
    let r = centre_stokes(&film, 0)[0] / spar::spectrum::cie::d65(550.0);
    let theta0 = 30f64.to_radians();
    let airy = 0.5 * (airy_r(n, d, theta0, 550.0, true) + airy_r(n, d, theta0, 550.0, false));
    assert!((r - airy).abs() <= 1e-3, "R {r} vs Airy {airy}");
}
