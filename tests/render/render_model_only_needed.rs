//! "Model only what a scene needs" through the render driver: the
//! automatic shortcuts give the image of the general path, and the sampled
//! knobs (hero wavelengths, stochastic branching) are unbiased.

use crate::support::render::*;
use spar::render::approx::Branching;
use spar::render::approx::{DispersionMode, Spectral, NO_DISPERSION_NM};

/// A gem of `medium` over a textured, polarized light, seen at an angle.
fn gem(medium: &str, axis: &str, resolution: u32, samples: u32) -> String {
    format!(
        r#"
[camera]
eye = [0.0, -3.0, 2.2]
look_at = [0.0, 0.0, -0.1]
up = [0.0, 0.0, 1.0]
fov = 30.0
resolution = [{resolution}, {resolution}]
samples = {samples}
[render]
max_depth = 10
prune = 0.0
[[object]]
mesh = "builtin:trichecker12"
medium = "{medium}"
{axis}
[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
texture = "builtin:checker"
polarization = {{ linear = [1.0, 0.4, 0.0] }}
[background]
radiance = 0.3
"#
    )
}

const LAMBDAS: [f64; 5] = [420.0, 480.0, 540.0, 600.0, 700.0];

#[test]
fn a_scene_without_dispersion_traces_each_tree_once_for_all_wavelengths() {
    let (scene, _d) = scene(&gem("iso:1.55", "", 8, 2), &[]);
    let (batched, stats) = render_at(&scene, &LAMBDAS);
    let mut one_rays = None;
    for (i, &l) in LAMBDAS.iter().enumerate() {
        let (alone, s) = render_at(&scene, &[l]);
        one_rays.get_or_insert(s.rays);
        assert_eq!(
            s.rays,
            one_rays.unwrap(),
            "the same trees at every wavelength"
        );
        for y in 0..8 {
            for x in 0..8 {
                assert_eq!(
                    batched.stokes(x, y, i),
                    alone.stokes(x, y, 0),
                    "{l} nm ({x}, {y})"
                );
            }
        }
    }
    // The general path would trace five times as many rays.
    assert_eq!(stats.rays, one_rays.unwrap());
    assert!(stats.rays > 64 * 2 * 3, "trees, not just camera rays");
}

#[test]
fn dispersion_off_traces_every_wavelength_along_the_d_line_paths() {
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (mut scene, _d) = scene(&gem("calcite", axis, 8, 1), &[]);
    let lambdas = [450.0, NO_DISPERSION_NM, 650.0];
    let (dispersive, on) = render_at(&scene, &lambdas);
    scene.settings.approx.dispersion = DispersionMode::Off;
    let (flat, off) = render_at(&scene, &lambdas);
    let (d_line, d) = render_at(&scene, &[NO_DISPERSION_NM]);
    // One tree per camera ray instead of one per wavelength.
    assert_eq!(off.rays, d.rays);
    assert!(on.rays > 2 * off.rays, "{} vs {}", on.rays, off.rays);
    let mut differs = false;
    for y in 0..8 {
        for x in 0..8 {
            // At the d line itself nothing is approximated.
            assert_eq!(flat.stokes(x, y, 1), dispersive.stokes(x, y, 1));
            assert_eq!(flat.stokes(x, y, 1), d_line.stokes(x, y, 0));
            differs |= flat.stokes(x, y, 0) != dispersive.stokes(x, y, 0);
        }
    }
    assert!(differs, "calcite disperses: 450 nm must differ somewhere");
}

#[test]
fn dispersion_bands_trace_one_tree_per_band_along_its_middle() {
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (mut scene, _d) = scene(&gem("calcite", axis, 8, 1), &[]);
    // Two bands of 400-500 nm: 400-450 follows 425 nm, 450-500 follows 475.
    let lambdas = [400.0, 425.0, 450.0, 475.0, 500.0];
    let (exact, on) = render_at(&scene, &lambdas);
    let (middles, m) = render_at(&scene, &[425.0, 475.0]);
    scene.settings.approx.dispersion = DispersionMode::Bands(2);
    let (banded, bands) = render_at(&scene, &lambdas);
    // Exactly the two middles' trees, each serving its band.
    assert_eq!(bands.rays, m.rays);
    assert!(on.rays > 2 * bands.rays, "{} vs {}", on.rays, bands.rays);
    let mut differs = false;
    for y in 0..8 {
        for x in 0..8 {
            // The middles themselves are not approximated.
            assert_eq!(banded.stokes(x, y, 1), exact.stokes(x, y, 1));
            assert_eq!(banded.stokes(x, y, 3), middles.stokes(x, y, 1));
            differs |= banded.stokes(x, y, 0) != exact.stokes(x, y, 0);
        }
    }
    assert!(differs, "calcite disperses: 400 nm must differ somewhere");
}

#[test]
fn dispersion_bands_leave_a_single_wavelength_mode_on_its_own_paths() {
    use spar::render::output::OutputMode;
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (mut scene, _d) = scene(&gem("calcite", axis, 8, 1), &[]);
    let accel = spar::render::prepare::accel(&scene, Default::default(), 2, None).unwrap();
    // Five colour wavelengths in two bands, and 437 nm for a DoP image.
    scene.settings.wavelengths =
        spar::spectrum::WavelengthSet::from_list(&[400.0, 425.0, 450.0, 475.0, 500.0]).unwrap();
    scene.settings.approx.dispersion = DispersionMode::Bands(2);
    let opts =
        spar::render::prepare::options(&scene, &[OutputMode::Color, OutputMode::Dop], 437.0, false);
    assert_eq!(opts.lambdas[5], 437.0);
    let (banded, _) = spar::render::render(&scene, accel.as_ref(), &opts);
    scene.settings.approx.dispersion = DispersionMode::On;
    let (own, _) = render_at(&scene, &[437.0]);
    for y in 0..8 {
        for x in 0..8 {
            assert_eq!(banded.stokes(x, y, 5), own.stokes(x, y, 0), "({x}, {y})");
        }
    }
}

/// As `spar render --mode color,dop` asks: the seed's 21 wavelengths, one
/// of them also the DoP image's 580 nm.
#[test]
fn dispersion_bands_with_colour_and_dop_trace_a_tree_per_band_and_one_for_dop() {
    use spar::render::output::OutputMode;
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (mut scene, _d) = scene(&gem("calcite", axis, 8, 1), &[]);
    let accel = spar::render::prepare::accel(&scene, Default::default(), 2, None).unwrap();
    let modes = [OutputMode::Color, OutputMode::Dop];
    let mut run = |d: DispersionMode| {
        scene.settings.approx.dispersion = d;
        let opts = spar::render::prepare::options(&scene, &modes, 580.0, false);
        let (film, stats) = spar::render::render(&scene, accel.as_ref(), &opts);
        let dop = opts.lambdas.iter().position(|&l| l == 580.0).unwrap();
        (film, stats.rays, dop)
    };
    let (exact, on, dop_on) = run(DispersionMode::On);
    let (_, off, _) = run(DispersionMode::Off);
    let (banded, bands, dop_b) = run(DispersionMode::Bands(3));
    // Three band trees and the DoP wavelength's own: about four times
    // one tree, far from the 21 of full dispersion.
    assert!(bands > 2 * off && bands < 6 * off, "{bands} vs {off}");
    assert!(on > 12 * off, "{on} vs {off}");
    for y in 0..8 {
        for x in 0..8 {
            assert_eq!(banded.stokes(x, y, dop_b), exact.stokes(x, y, dop_on));
        }
    }
}

#[test]
fn scene_files_set_dispersion_as_a_flag_or_bands() {
    let base = gem("calcite", "optic_axis = [0.0, 0.0, 1.0]", 8, 1);
    for (value, mode) in [
        ("false", DispersionMode::Off),
        ("true", DispersionMode::On),
        ("\"bands:4\"", DispersionMode::Bands(4)),
        ("\"off\"", DispersionMode::Off),
    ] {
        let toml = base.replace("[render]\n", &format!("[render]\ndispersion = {value}\n"));
        let (s, _d) = scene(&toml, &[]);
        assert_eq!(s.settings.approx.dispersion, mode, "{value}");
    }
}

/// A slab of glass of constant index, 6 × 6 across and 0.2 thick, centred
/// at z = 1.
fn slab_obj() -> String {
    let mut obj = String::new();
    for z in [0.9, 1.1] {
        for (x, y) in [(-3.0, -3.0), (3.0, -3.0), (3.0, 3.0), (-3.0, 3.0)] {
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    // Bottom, top, then the four sides, wound outwards.
    for f in [
        "1 3 2", "1 4 3", "5 6 7", "5 7 8", "1 2 6", "1 6 5", "2 3 7", "2 7 6", "3 4 8", "3 8 7",
        "4 1 5", "4 5 8",
    ] {
        obj += &format!("f {f}\n");
    }
    obj
}

#[test]
fn hero_wavelengths_are_exact_where_every_sample_sees_the_same_light() {
    // A uniform unpolarized light fills the view, seen straight on by an
    // orthographic camera, directly or through a slab of glass of constant
    // index: every sample of a pixel sees the same spectrum, so each
    // wavelength's estimate is the full spectrum's, for any sample count
    // of at least the stride. Through the slab, hero samples trace their
    // stratum (the mean of the samples that trace it): 14 samples are 2
    // rounds of stride 7, and 9 and 16 are not whole rounds (each
    // wavelength traced 1-2 or 2-3 times: weighting by the stride alone
    // would miss by up to 1/3); 16 and 32 samples trace the strata in runs
    // of 2-3 and 4-5 consecutive samples. Seen directly, every sample
    // traces every wavelength (its camera ray meets no object). With `/2`
    // colour is traced on the first half of the samples (7 or 8 of 14 or
    // 16 for `hero:3/2`, 2 of 3 for `all/2`).
    let hero_every_2 = Spectral {
        every: 2,
        ..Spectral::hero(3)
    };
    let all_every_2 = Spectral {
        every: 2,
        ..Spectral::ALL
    };
    for slab in [false, true] {
        for (spectral, samples) in [
            (Spectral::hero(3), 14u32),
            (Spectral::hero(3), 9),
            (Spectral::hero(3), 16),
            (Spectral::hero(3), 32),
            (hero_every_2, 14),
            (hero_every_2, 16),
            (all_every_2, 3),
        ] {
            let object = if slab {
                "[[object]]\nmesh = \"slab.obj\"\nmedium = \"iso:1.5\"\n"
            } else {
                ""
            };
            let toml = format!(
                r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
projection = "orthographic"
width = 1.0
resolution = [4, 4]
samples = {samples}
{object}
[[light]]
corners = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]]
radiance = 1.0
"#
            );
            let (mut scene, _d) = scene(&toml, &[("slab.obj", slab_obj())]);
            let lambdas: Vec<f64> = (0..21).map(|i| 380.0 + 20.0 * i as f64).collect();
            let (all, all_stats) = render_at(&scene, &lambdas);
            scene.settings.approx.spectral = spectral;
            let (hero, stats) = render_at(&scene, &lambdas);
            if slab {
                // 21 wavelengths, 3 per sample: stride 7. The slab's
                // wavelengths share one tree (constant index), the same
                // for every sample, so a hero sample traces what a full
                // one does, on ⌈S/N⌉ samples per pixel.
                assert!(
                    all_stats.rays > 16 * samples as u64,
                    "{spectral}: the slab is seen"
                );
                assert_eq!(
                    stats.rays,
                    all_stats.rays / samples as u64 * samples.div_ceil(spectral.every) as u64,
                    "{spectral}"
                );
            } else {
                // Samples without colour trace nothing here (no
                // single-wavelength mode): one camera ray per colour
                // sample, ⌈S/N⌉ per pixel.
                assert_eq!(
                    stats.rays,
                    16 * samples.div_ceil(spectral.every) as u64,
                    "{spectral}"
                );
            }
            for y in 0..4 {
                for x in 0..4 {
                    for i in 0..21 {
                        let (a, h) = (all.stokes(x, y, i)[0], hero.stokes(x, y, i)[0]);
                        assert!(a > 0.5, "the light is seen");
                        // Sums of up to 16 f32 values on both sides and an
                        // inexact weight (16/3): a few f32 roundings.
                        assert!(
                            (a - h).abs() <= 4.0 * f32::EPSILON as f64 * a,
                            "slab {slab}, {spectral}, {samples} samples: {a} vs {h}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn hero_samples_that_meet_no_object_trace_every_wavelength() {
    // The calcite gem over the textured light: a pixel none of whose camera
    // rays meets the stone (its full render equals the render without the
    // stone) is, with hero wavelengths, the full render bit for bit (every
    // sample traced every wavelength there, weighing 1); a pixel on the
    // stone is a hero estimate, which differs.
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (scene, _d) = scene(&gem("calcite", axis, 16, 7), &[]);
    let (full, _) = render_at(&scene, &LAMBDAS);
    let mut bare = scene.clone();
    bare.objects.clear();
    let (light_only, _) = render_at(&bare, &LAMBDAS);
    for k in [2, 3] {
        let mut hero = scene.clone();
        hero.settings.approx.spectral = Spectral::hero(k);
        let (film, _) = render_at(&hero, &LAMBDAS);
        let (mut off, mut on_differ) = (0, 0);
        for y in 0..16 {
            for x in 0..16 {
                let pixel = |f: &spar::render::film::Film| {
                    (0..LAMBDAS.len())
                        .map(|i| f.stokes(x, y, i))
                        .collect::<Vec<_>>()
                };
                if pixel(&full) == pixel(&light_only) {
                    off += 1;
                    assert_eq!(pixel(&film), pixel(&full), "hero:{k} ({x}, {y})");
                } else if pixel(&film) != pixel(&full) {
                    on_differ += 1;
                }
            }
        }
        assert!(
            off >= 64 && on_differ >= 64,
            "hero:{k}: {off} pixels off the stone, {on_differ} on it differ"
        );
    }
}

/// Mean of the per-pixel differences between two films over all pixels and
/// wavelengths, in units of its standard error.
fn z_score(a: &spar::render::film::Film, b: &spar::render::film::Film, c: usize) -> f64 {
    let mut d = Vec::new();
    for y in 0..a.height {
        for x in 0..a.width {
            let s: f64 = (0..a.lambdas.len())
                .map(|i| a.stokes(x, y, i)[c] - b.stokes(x, y, i)[c])
                .sum();
            d.push(s);
        }
    }
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    assert!(
        var > 0.0,
        "the sampled render must differ from the exact one"
    );
    mean / (var / n).sqrt()
}

/// A sampled setting: its name and how it changes a scene.
type Knob = (&'static str, fn(&mut spar::scene::Scene));

#[test]
fn sampled_knobs_are_unbiased_through_the_driver() {
    // Each pixel's difference from the exact render has mean zero if the
    // estimator is unbiased; over 256 pixels the mean difference must be
    // within 5 standard errors (a 1-in-1.7-million false alarm for a
    // normal mean).
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (scene, _d) = scene(&gem("calcite", axis, 16, 7), &[]);
    let (exact, full_stats) = render_at(&scene, &LAMBDAS);
    let knobs: [Knob; 4] = [
        ("hero:2", |s| s.settings.approx.spectral = Spectral::hero(2)),
        ("hero:2/2", |s| {
            s.settings.approx.spectral = Spectral {
                every: 2,
                ..Spectral::hero(2)
            }
        }),
        ("stochastic", |s| {
            s.settings.approx.strategy.branching = Branching::Stochastic
        }),
        ("hybrid:2", |s| {
            s.settings.approx.strategy.branching = Branching::Hybrid { full_depth: 2 }
        }),
    ];
    for (name, set) in knobs {
        let mut sampled = scene.clone();
        set(&mut sampled);
        let (film, stats) = render_at(&sampled, &LAMBDAS);
        assert!(stats.rays < full_stats.rays, "{name} must trace less");
        for c in 0..3 {
            let z = z_score(&film, &exact, c);
            assert!(z.abs() < 5.0, "{name}: S{c} off by {z:.2} standard errors");
        }
        // Deterministic: the same seed gives the same film, another seed
        // another one.
        assert_eq!(render_at(&sampled, &LAMBDAS).0, film, "{name}");
        sampled.settings.seed += 1;
        assert_ne!(render_at(&sampled, &LAMBDAS).0, film, "{name}");
    }
}

#[test]
fn hero_sampling_never_thins_out_a_single_wavelength_mode() {
    // dop at 580 nm with colour over 21 wavelengths (580 among them): with
    // hero sampling the 580 nm channel is still traced for every sample,
    // so it is bit for bit the channel of the unsampled render.
    let dir = tempfile::tempdir().unwrap();
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass-polarized.toml");
    let raw = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_spar"))
            .arg("render")
            .arg(&scene)
            .args([
                "--resolution",
                "16x16",
                "--samples",
                "8",
                "--mode",
                "color,dop",
                "--raw",
                "-q",
                "-o",
            ])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        spar::image::read(&out).unwrap()
    };
    let all = raw("all.exr", &[]);
    for (i, spectral) in ["hero:3", "hero:3/2", "all/4"].into_iter().enumerate() {
        let hero = raw(&format!("hero{i}.exr"), &["--spectral", spectral]);
        for c in 0..4 {
            let name = format!("S{c}_580nm");
            assert_eq!(
                all.channel(&name).unwrap(),
                hero.channel(&name).unwrap(),
                "{spectral}: {name}"
            );
        }
        // The thinned colour wavelengths do differ.
        assert_ne!(
            all.channel("S0_600nm").unwrap(),
            hero.channel("S0_600nm").unwrap(),
            "{spectral}"
        );
    }
}

/// `LAMBDAS` as the colour wavelengths and 580 nm as a single-wavelength
/// mode's (traced on every sample), rendered with the scene's settings.
fn render_with_dop(
    scene: &spar::scene::Scene,
) -> (spar::render::film::Film, spar::render::integrator::Stats) {
    let mut lambdas = LAMBDAS.to_vec();
    lambdas.push(580.0);
    let accel = spar::render::prepare::accel(scene, Default::default(), 2, None).unwrap();
    let mut opts = spar::render::prepare::options_at(scene, lambdas);
    opts.colour_lambdas = LAMBDAS.len();
    spar::render::render(scene, accel.as_ref(), &opts)
}

/// Root-mean-square difference of the colour wavelengths' S0.
fn colour_rmse(a: &spar::render::film::Film, b: &spar::render::film::Film) -> f64 {
    let mut sum = 0.0;
    for y in 0..a.height {
        for x in 0..a.width {
            for i in 0..LAMBDAS.len() {
                sum += (a.stokes(x, y, i)[0] - b.stokes(x, y, i)[0]).powi(2);
            }
        }
    }
    (sum / (a.width * a.height) as f64 / LAMBDAS.len() as f64).sqrt()
}

#[test]
fn the_control_variate_is_exact_where_every_wavelength_shares_the_paths() {
    // Constant indices: every colour wavelength follows the 580 nm paths,
    // so the control variate (the 580 nm tree at every colour wavelength)
    // is each wavelength's own value on every sample, and hero sampling
    // gives the image of every wavelength on every sample, from the same
    // one tree per sample. `,plain` thins them out (and differs).
    let (scene, _d) = scene(&gem("iso:1.55", "", 12, 3), &[]);
    let mut all = scene.clone();
    all.settings.approx.spectral = Spectral::ALL;
    let (exact, exact_stats) = render_with_dop(&all);
    for k in [1, 2] {
        let mut hero = scene.clone();
        hero.settings.approx.spectral = Spectral::hero(k);
        let (film, stats) = render_with_dop(&hero);
        assert_eq!(
            stats.rays, exact_stats.rays,
            "hero:{k}: one tree per sample"
        );
        for y in 0..12 {
            for x in 0..12 {
                for i in 0..=LAMBDAS.len() {
                    let (a, b) = (film.stokes(x, y, i), exact.stokes(x, y, i));
                    for c in 0..4 {
                        assert!(
                            (a[c] - b[c]).abs() <= 1e-6 * b[0].abs().max(1e-3),
                            "hero:{k} ({x}, {y}) {i} S{c}: {} against {}",
                            a[c],
                            b[c]
                        );
                    }
                }
            }
        }
        hero.settings.approx.spectral.plain = true;
        let (plain, _) = render_with_dop(&hero);
        assert!(colour_rmse(&plain, &exact) > 1e-3, "hero:{k},plain");
    }
}

#[test]
fn the_control_variate_is_unbiased_and_less_noisy_in_a_dispersive_crystal() {
    // The calcite gem (dispersion and birefringence: each wavelength its
    // own tree): with the 580 nm tree as control variate, hero sampling's
    // colour has mean zero difference from every wavelength on every
    // sample (within 5 standard errors over 256 pixels, as for the other
    // sampled knobs), and a smaller error than the plain hero estimate at
    // the same rays.
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (scene, _d) = scene(&gem("calcite", axis, 16, 7), &[]);
    let (exact, _) = render_with_dop(&scene);
    for (k, every) in [(1, 1), (2, 1), (2, 2)] {
        let mut hero = scene.clone();
        hero.settings.approx.spectral = Spectral {
            every,
            ..Spectral::hero(k)
        };
        let (film, stats) = render_with_dop(&hero);
        for c in 0..3 {
            let z = z_score(&film, &exact, c);
            assert!(
                z.abs() < 5.0,
                "hero:{k}/{every}: S{c} off by {z:.2} standard errors"
            );
        }
        hero.settings.approx.spectral.plain = true;
        let (plain, plain_stats) = render_with_dop(&hero);
        assert_eq!(stats.rays, plain_stats.rays, "hero:{k}/{every}");
        let (with, without) = (colour_rmse(&film, &exact), colour_rmse(&plain, &exact));
        assert!(
            with < without,
            "hero:{k}/{every}: colour RMSE {with} with the control variate, {without} without"
        );
    }
}

#[test]
fn the_control_variate_adds_each_traced_wavelengths_own_difference() {
    // One sample per pixel of the calcite gem, the single wavelength at
    // the d line (587.56 nm, so that its paths are those of dispersion
    // off): for each colour wavelength, the control variate y is the
    // dispersion-off render's value, L the every-wavelength render's, and
    // w·L the plain hero render's where that sample traced it (0 where it
    // did not). The estimate must be y + w·(L − y) where traced, y
    // elsewhere: three independent renders against the fourth.
    let axis = "optic_axis = [0.3, 0.2, 1.0]";
    let (scene, _d) = scene(&gem("calcite", axis, 12, 1), &[]);
    let render = |spectral: Spectral, dispersion: DispersionMode| {
        let mut s = scene.clone();
        s.settings.approx.spectral = spectral;
        s.settings.approx.dispersion = dispersion;
        let mut lambdas = LAMBDAS.to_vec();
        lambdas.push(NO_DISPERSION_NM);
        let accel = spar::render::prepare::accel(&s, Default::default(), 2, None).unwrap();
        let mut opts = spar::render::prepare::options_at(&s, lambdas);
        opts.colour_lambdas = LAMBDAS.len();
        spar::render::render(&s, accel.as_ref(), &opts).0
    };
    let exact = render(Spectral::ALL, DispersionMode::On);
    let y = render(Spectral::ALL, DispersionMode::Off);
    let hero = Spectral::hero(2);
    let plain = render(
        Spectral {
            plain: true,
            ..hero
        },
        DispersionMode::On,
    );
    let cv = render(hero, DispersionMode::On);
    let (mut traced, mut untraced, mut differ) = (0, 0, 0);
    for py in 0..12 {
        for px in 0..12 {
            for (i, nm) in LAMBDAS.iter().enumerate() {
                let (l, y, p, e) = (
                    exact.stokes(px, py, i),
                    y.stokes(px, py, i),
                    plain.stokes(px, py, i),
                    cv.stokes(px, py, i),
                );
                let expected: [f64; 4] = if p[0] == 0.0 || l[0] == 0.0 {
                    untraced += 1;
                    y
                } else {
                    traced += 1;
                    let w = p[0] / l[0];
                    std::array::from_fn(|c| y[c] + w * (l[c] - y[c]))
                };
                if (l[0] - y[0]).abs() > 1e-3 * l[0].abs() {
                    differ += 1;
                }
                let scale = l[0].abs().max(y[0].abs()).max(1e-6);
                for c in 0..4 {
                    assert!(
                        (e[c] - expected[c]).abs() <= 1e-4 * scale,
                        "({px}, {py}) {nm} nm S{c}: {} against y + w(L − y) = {}",
                        e[c],
                        expected[c]
                    );
                }
            }
        }
    }
    assert!(
        traced > 100 && untraced > 100 && differ > 50,
        "{traced} traced, {untraced} not, {differ} where L and y differ"
    );
}
