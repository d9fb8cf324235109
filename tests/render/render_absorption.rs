//! Absorption (docs/physics.md §11) against closed forms computed here:
//! the light a slab transmits is exp(−α d) times the two faces' Fresnel
//! transmittance, per wavelength and per eigenwave; a slab in a white
//! furnace gives back what the sum of its multiply reflected paths, each
//! attenuated by Beer–Lambert, gives (incoherent: the geometric series of
//! intensities; physical: the Airy sum of amplitudes, each pass keeping
//! exp(−α d / 2) of its amplitude).
//!
//! Tolerances: path lengths come from single-precision hits, good to
//! about 1e-7 of the length (a 0.8 mm path: 6e-8 of α d), so values agree
//! to 1e-6, not to rounding.

use crate::support::render as common;
use common::*;
use spar::accel::AccelKind;
use spar::render::approx::CoherenceModel;

/// Slab thickness, mm (the scene unit).
const D: f64 = 0.8;

/// An orthographic camera looking straight down (−z) at a slab
/// z ∈ [0, D], 10 mm wide, lit from below by a large light emitting up
/// (`light` its extra keys) or standing in a uniform background
/// (`light = None`). `medium` is the `[media.slab]` table's body.
fn slab_scene(medium: &str, light: Option<&str>, depth: u32, prune: f64, model: &str) -> String {
    let light = match light {
        Some(extra) => format!(
            "[[light]]\ncorners = [[-8.0, -8.0, -2.0], [8.0, -8.0, -2.0], [8.0, 8.0, -2.0], \
             [-8.0, 8.0, -2.0]]\nradiance = 1.0\n{extra}\n"
        ),
        None => "[background]\nradiance = 1.0\n".to_string(),
    };
    format!(
        r#"
[camera]
projection = "orthographic"
width = 2.0
eye = [0.0, 0.0, 6.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [4, 4]
[render]
units = "mm"
max_depth = {depth}
prune = {prune}
coherence = "{model}"
[media.slab]
{medium}
[[object]]
mesh = "slab.obj"
medium = "slab"
{light}"#
    )
}

/// Mean S0 over the image of a slab `d` thick, divided by D65 at
/// `lambda`.
fn relative_intensity(
    toml: &str,
    d: f64,
    lambda: f64,
    accel: AccelKind,
    model: CoherenceModel,
) -> f64 {
    let slab = box_obj([-5.0, -5.0, 0.0], [5.0, 5.0, d]);
    let (scene, _d) = common::scene(toml, &[("slab.obj", slab)]);
    let (film, stats) = render_model(&scene, &[lambda], accel, model);
    assert_eq!(stats.lost, 0, "no ray may be lost");
    let s = mean_stokes(&film, 0, film.width, 0, film.height, 0);
    s[0] / spar::spectrum::cie::d65(lambda)
}

/// Intensity transmittance of one face at normal incidence between air
/// and index `n` (Fresnel: 1 − ((n − 1)/(n + 1))²).
fn face(n: f64) -> f64 {
    4.0 * n / ((n + 1.0) * (n + 1.0))
}

/// The absorption table of the tests, per mm: 0.9 at 380 nm falling
/// linearly to 0.1 at 780 nm.
const TABLE: &str = "{ nm = [380, 780], per_mm = [0.9, 0.1] }";

fn table_alpha(lambda: f64) -> f64 {
    0.9 + (0.1 - 0.9) * (lambda - 380.0) / 400.0
}

const MODELS: [(&str, CoherenceModel); 2] = [
    ("physical", CoherenceModel::Physical),
    ("incoherent", CoherenceModel::Incoherent),
];

/// Glass with a per-wavelength table: depth 2 keeps the straight path
/// only (the camera ray's node, then the back face's), so the image is
/// the two faces' transmittance times exp(−α(λ) d).
fn slab_transmits_beer_lambert_times_fresnel(accel: AccelKind) {
    let n: f64 = 1.5;
    for (name, model) in MODELS {
        for lambda in [420.0, 550.0, 700.0] {
            let toml = slab_scene(
                &format!("n = {n}\nabsorption = {TABLE}"),
                Some(""),
                2,
                0.0,
                name,
            );
            let got = relative_intensity(&toml, D, lambda, accel, model);
            let want = face(n) * face(n) * (-table_alpha(lambda) * D).exp();
            eprintln!("{name} {lambda} nm: {got:.12} against {want:.12}");
            assert!(
                (got / want - 1.0).abs() < 1e-6,
                "{name}, {lambda} nm: {got} against {want}"
            );
        }
        // The same three wavelengths in one render: a constant index makes
        // them one batch sharing its paths (each with its own α).
        let toml = slab_scene(
            &format!("n = {n}\nabsorption = {TABLE}"),
            Some(""),
            2,
            0.0,
            name,
        );
        let slab = box_obj([-5.0, -5.0, 0.0], [5.0, 5.0, D]);
        let (scene, _d) = common::scene(&toml, &[("slab.obj", slab)]);
        assert!(!scene.is_dispersive());
        let lambdas = [420.0, 550.0, 700.0];
        let (film, _) = render_model(&scene, &lambdas, accel, model);
        for (i, lambda) in lambdas.into_iter().enumerate() {
            let s = mean_stokes(&film, 0, film.width, 0, film.height, i);
            let got = s[0] / spar::spectrum::cie::d65(lambda);
            let want = face(n) * face(n) * (-table_alpha(lambda) * D).exp();
            assert!(
                (got / want - 1.0).abs() < 1e-6,
                "{name}, batched, {lambda} nm: {got} against {want}"
            );
        }
    }
}

/// A dichroic crystal, its optic axis along x in the slab's plane: light
/// polarized along the axis crosses as the extraordinary wave and keeps
/// exp(−α_e d), light polarized across it as the ordinary wave and keeps
/// exp(−α_o d), each with its own index's Fresnel factor. Seen down the
/// axis (axis along z) both waves travel along it and keep exp(−α_o d)
/// (a ruby looked at down its c axis shows its ordinary colour only).
fn crystal_slab_absorbs_per_eigenwave(accel: AccelKind) {
    let (n_o, n_e) = (1.768, 1.760);
    let (a_o, a_e) = (1.3, 0.4);
    let crystal = format!("n_o = {n_o}\nn_e = {n_e}\nabsorption_o = {a_o}\nabsorption_e = {a_e}");
    // A linear polarizer in the light halves its unpolarized radiance.
    let cases = [
        ("optic_axis = [1.0, 0.0, 0.0]", "[1.0, 0.0, 0.0]", n_e, a_e),
        ("optic_axis = [1.0, 0.0, 0.0]", "[0.0, 1.0, 0.0]", n_o, a_o),
        ("optic_axis = [0.0, 0.0, 1.0]", "[1.0, 0.0, 0.0]", n_o, a_o),
        ("optic_axis = [0.0, 0.0, 1.0]", "[0.0, 1.0, 0.0]", n_o, a_o),
    ];
    for (name, model) in MODELS {
        for (axis, pol, n, alpha) in cases {
            let toml = slab_scene(
                &crystal,
                Some(&format!("polarization = {{ linear = {pol} }}")),
                2,
                0.0,
                name,
            )
            .replace("medium = \"slab\"", &format!("medium = \"slab\"\n{axis}"));
            let got = relative_intensity(&toml, D, 550.0, accel, model);
            let want = 0.5 * face(n) * face(n) * (-alpha * D).exp();
            eprintln!("{name} {axis}, light along {pol}: {got:.12} against {want:.12}");
            assert!(
                (got / want - 1.0).abs() < 1e-6,
                "{name} {axis}, light along {pol}: {got} against {want}"
            );
        }
    }
}

/// A slab in a white furnace seen from above, the incoherent model: the
/// pixel sums the light reflected from above and transmitted from below
/// over every number of internal passes,
/// R_tot + T_tot = R + (1 − R)² a (R a + 1) / (1 − R² a²), a = exp(−α d)
/// (the geometric series of intensities); the rest, what Beer–Lambert
/// takes out along the traced paths, is missing.
fn absorbing_slab_in_a_white_furnace_keeps_the_geometric_series(accel: AccelKind) {
    let n: f64 = 1.5;
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    for lambda in [420.0, 550.0, 700.0] {
        let toml = slab_scene(
            &format!("n = {n}\nabsorption = {TABLE}"),
            None,
            80,
            0.0,
            "incoherent",
        );
        let got = relative_intensity(&toml, D, lambda, accel, CoherenceModel::Incoherent);
        let a = (-table_alpha(lambda) * D).exp();
        let want = r + (1.0 - r) * (1.0 - r) * a * (r * a + 1.0) / (1.0 - r * r * a * a);
        eprintln!(
            "furnace {lambda} nm: kept {got:.12} against {want:.12} (absorbed {:.6})",
            1.0 - want
        );
        assert!(
            (got - want).abs() < 1e-6,
            "{lambda} nm: {got} against {want}"
        );
    }
}

/// A film 2 µm thick in the physical model at one wavelength (thin, so
/// that its round trips, measured from single-precision hits, are good to
/// 1e-10 mm: 2e-6 rad of phase): every reflected
/// path (and every transmitted one) travels in one direction and adds as
/// an amplitude, each pass through the slab multiplying it by
/// √a e^{iδ/2}, δ = 4π n d / λ: the Airy sums
/// r_tot = r + t t′ r′ a e^{iδ} / (1 − r′² a e^{iδ}),
/// t_tot = t t′ √a e^{iδ/2} / (1 − r′² a e^{iδ}), with r = (1 − n)/(1 + n),
/// r′ = −r, t t′ = 1 − r² (energy-normalized).
fn absorbing_slab_in_a_white_furnace_keeps_the_airy_sum(accel: AccelKind) {
    use num_complex::Complex64 as C;
    let n: f64 = 1.5;
    let r = (1.0 - n) / (1.0 + n);
    for lambda in [420.0, 550.0, 700.0] {
        let toml = slab_scene(
            &format!("n = {n}\nabsorption = {{ nm = [380, 780], per_mm = [300, 100] }}"),
            None,
            80,
            1e-16,
            "physical",
        );
        let d = 0.002;
        let got = relative_intensity(&toml, d, lambda, accel, CoherenceModel::Physical);
        let alpha = 300.0 + (100.0 - 300.0) * (lambda - 380.0) / 400.0;
        let a = (-alpha * d).exp();
        let delta = 4.0 * std::f64::consts::PI * n * d * 1e6 / lambda;
        let round = C::from_polar(a, delta);
        let denom = C::new(1.0, 0.0) - round * r * r;
        let r_tot = C::new(r, 0.0) - round * ((1.0 - r * r) * r) / denom;
        let t_tot = C::from_polar(a.sqrt(), 0.5 * delta) * (1.0 - r * r) / denom;
        let want = r_tot.norm_sqr() + t_tot.norm_sqr();
        eprintln!("Airy furnace {lambda} nm: kept {got:.12} against {want:.12}");
        assert!(
            (got - want).abs() < 1e-6,
            "{lambda} nm: {got} against {want}"
        );
    }
}

on_every_backend!(
    slab_transmits_beer_lambert_times_fresnel,
    crystal_slab_absorbs_per_eigenwave,
    absorbing_slab_in_a_white_furnace_keeps_the_geometric_series,
    absorbing_slab_in_a_white_furnace_keeps_the_airy_sum,
    a_ruby_dichroscope_shows_its_two_colours,
);

/// Scene keys: `absorption` for an isotropic medium or both waves of a
/// crystal, `absorption_o` and `absorption_e` for a dichroic crystal, each
/// a number, a table or a built-in spectrum's name; every misuse is an
/// error naming the file, the line and the field.
#[test]
fn absorption_keys_load_and_misuse_is_named() {
    let with = |medium: &str| slab_scene(medium, Some(""), 2, 0.0, "incoherent");
    let load = |toml: &str| {
        let dir = tempfile::tempdir().unwrap();
        let slab = box_obj([-5.0, -5.0, 0.0], [5.0, 5.0, D]);
        std::fs::write(dir.path().join("slab.obj"), slab).unwrap();
        spar::scene::Scene::parse(toml, "test.toml", dir.path())
    };
    for ok in [
        "n = 1.5\nabsorption = 0.2",
        "n = 1.5\nabsorption = { nm = [380, 500, 780], per_mm = [1, 0.5, 0] }",
        "n_o = 1.768\nn_e = 1.760\nabsorption_o = \"ruby-o\"\nabsorption_e = \"Ruby_E\"",
        "n_o = 1.768\nn_e = 1.760\nabsorption = 0.3",
        "n = 1.5\nabsorption = 0",
        // docs/scenes.md's example.
        "n_o = { sellmeier_poles = { b = [1.4313493, 0.65054713, 5.3414021], poles = [0.0726631, \
         0.1193242, 18.028251] } }\nn_e = { sellmeier_poles = { b = [1.5039759, 0.55069141, \
         6.5927379], poles = [0.0740288, 0.1216529, 20.072248] } }\nabsorption_o = { nm = [380, \
         420, 480, 556, 620, 700, 780], per_mm = [0.8, 0.9, 0.2, 0.8, 0.2, 0.02, 0.0] }\n\
         absorption_e = { nm = [380, 420, 480, 542, 620, 700, 780], per_mm = [0.8, 0.6, 0.2, \
         0.55, 0.1, 0.01, 0.0] }",
    ] {
        let scene = load(&with(ok)).unwrap_or_else(|e| panic!("{ok}: {e}"));
        let absorbs = scene.objects[0].material.absorption().is_some();
        assert_eq!(absorbs, !ok.ends_with("= 0"), "{ok}");
    }
    let bad = [
        ("n = 1.5\nabsorption_o = 0.2", "isotropic"),
        ("n_o = 1.768\nn_e = 1.760\nabsorption_o = 0.2", "both"),
        (
            "n_o = 1.768\nn_e = 1.760\nabsorption = 0.1\nabsorption_e = 0.2",
            "both",
        ),
        ("n = 1.5\nabsorption = -0.2", "≥ 0"),
        ("n = 1.5\nabsorption = \"kryptonite\"", "ruby-o"),
        (
            "n = 1.5\nabsorption = { nm = [400, 780], per_mm = [1, 0] }",
            "cover",
        ),
        (
            "n = 1.5\nabsorption = { nm = [380, 780], per_mm = [1] }",
            "values",
        ),
        (
            "n = 1.5\nabsorption = { nm = [380, 780], per_cm = [1, 2] }",
            "per_cm",
        ),
        (
            "n = 1.5\nabsorption = [1, 2]",
            "absorption coefficient per mm",
        ),
    ];
    for (medium, why) in bad {
        let err = load(&with(medium)).expect_err(medium).to_string();
        assert!(err.contains(why), "{medium}: {err}");
        assert!(
            err.starts_with("test.toml:"),
            "{medium}: {err} names no line"
        );
        if why != "per_cm" && why != "absorption coefficient per mm" {
            assert!(err.contains("media.slab"), "{medium}: {err} names no field");
        }
    }
}

/// The dichroscope (`--mode dichroscope`) on a ruby slab 2 mm thick whose
/// optic axis lies along image right, lit from below by white light and
/// seen straight through (depth 2: the straight path). Its left half,
/// behind a polarizer along the axis, is the extraordinary wave; its right
/// half the ordinary wave. Each half's chromaticity must be that of white
/// light through the slab with its own spectrum, computed here at every
/// nanometre: ½ D65(λ) t(n)² exp(−α(λ) d), t(n) = 4n/(n + 1)² each face
/// (within 2e-3 in x and y: the render integrates 81 wavelengths); and the
/// two must differ (McClure's σ and π spectra: purplish red and orangy
/// red).
fn a_ruby_dichroscope_shows_its_two_colours(accel: AccelKind) {
    use spar::render::output::{develop, OutputMode};
    use spar::spectrum::{cie, Observer};
    let d = 2.0;
    let toml = r#"
[camera]
projection = "orthographic"
width = 2.0
eye = [0.0, 0.0, 6.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
resolution = [4, 4]
[render]
units = "mm"
max_depth = 2
prune = 0.0
wavelengths = 81
coherence = "incoherent"
[[object]]
mesh = "slab.obj"
medium = "ruby"
optic_axis = [1.0, 0.0, 0.0]
[[light]]
corners = [[-8.0, -8.0, -2.0], [8.0, -8.0, -2.0], [8.0, 8.0, -2.0], [-8.0, 8.0, -2.0]]
radiance = 1.0
"#;
    let slab = box_obj([-5.0, -5.0, 0.0], [5.0, 5.0, d]);
    let (scene, _dir) = common::scene(toml, &[("slab.obj", slab)]);
    let set = scene.settings.wavelengths.clone();
    let (film, stats) = render_with(&scene, set.lambdas(), accel);
    assert_eq!(stats.lost, 0);
    let observer = Observer::new(&set).unwrap();
    let ruby = spar::material::Material::parse("ruby").unwrap();
    let a = ruby.absorption().unwrap();
    let half = |angle: u32| -> Vec<f64> {
        (0..set.len())
            .map(|i| {
                let s = mean_stokes(&film, 0, film.width, 0, film.height, i);
                spar::render::output::polarizer(s, angle)
            })
            .collect()
    };
    let predicted = |extraordinary: bool| {
        cie::chromaticity(cie::xyz_1nm(|l| {
            let (n_o, n_e) = ruby.indices(l);
            let (a_o, a_e) = a.per_mm(l);
            let (n, alpha) = if extraordinary {
                (n_e, a_e)
            } else {
                (n_o, a_o)
            };
            0.5 * cie::d65(l) * face(n) * face(n) * (-alpha * d).exp()
        }))
    };
    let (left, right) = (half(0), half(90));
    let got = [
        cie::chromaticity(observer.xyz(&left)),
        cie::chromaticity(observer.xyz(&right)),
    ];
    let want = [predicted(true), predicted(false)];
    for (side, (g, w)) in ["left (e)", "right (o)"].iter().zip(got.iter().zip(&want)) {
        eprintln!("{side}: rendered xy {g:.4?}, predicted {w:.4?}");
        assert!(
            (g[0] - w[0]).abs() < 2e-3 && (g[1] - w[1]).abs() < 2e-3,
            "{side}: {g:?} against {w:?}"
        );
    }
    let apart = ((want[0][0] - want[1][0]).powi(2) + (want[0][1] - want[1][1]).powi(2)).sqrt();
    eprintln!("o and e chromaticities {apart:.4} apart");
    // Distinct far beyond the 2e-3 each half is held to.
    assert!(apart > 0.01, "the two colours differ: {apart}");
    // The developed image: the two halves side by side, each pixel the
    // colour of its half's spectrum.
    let image = develop(&film, OutputMode::Dichroscope, &set, 580.0).unwrap();
    assert_eq!(
        (image.width(), image.height()),
        (2 * film.width as usize, film.height as usize)
    );
    let encode = |rgb: [f64; 3]| rgb.map(|v| spar::spectrum::srgb::encode(v.max(0.0)).min(1.0));
    let pixel = |x: usize| -> Vec<f64> {
        (0..3)
            .map(|c| image.data()[3 * (x + image.width()) + c] as f64)
            .collect()
    };
    let (l, r) = (pixel(1), pixel(film.width as usize + 1));
    let behind = |angle: u32| -> Vec<f64> {
        (0..set.len())
            .map(|i| spar::render::output::polarizer(film.stokes(1, 1, i), angle))
            .collect()
    };
    let (sl, sr) = (
        encode(observer.linear_srgb(&behind(0))),
        encode(observer.linear_srgb(&behind(90))),
    );
    for c in 0..3 {
        assert!(
            (l[c] - sl[c]).abs() < 1e-6,
            "left pixel {l:?} against {sl:?}"
        );
        assert!(
            (r[c] - sr[c]).abs() < 1e-6,
            "right pixel {r:?} against {sr:?}"
        );
    }
}
