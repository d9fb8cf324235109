//! Shared helpers of the render tests: scenes from TOML text with meshes
//! written to a temporary directory, rendered through the library with
//! either intersection backend.

use spar::accel::AccelKind;
use spar::render::film::Film;
use spar::render::integrator::Stats;
use spar::render::{prepare, render};
use spar::scene::Scene;

/// A scene from TOML text; `files` are (name, contents) written next to it.
pub fn scene(toml: &str, files: &[(&str, String)]) -> (Scene, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let scene = Scene::parse(toml, "test.toml", dir.path()).unwrap_or_else(|e| panic!("{e}"));
    (scene, dir)
}

/// The intersection backends of this build: Embree (with the `native`
/// feature) and the Rust BVH.
pub fn backends() -> Vec<AccelKind> {
    AccelKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .collect()
}

/// Runs each named test function (`fn name(accel: AccelKind)`) once per
/// backend of this build, as tests `embree::name` and `rust::name`.
#[allow(unused_macros)] // in the crates whose tests do not
macro_rules! on_every_backend {
    ($($name:ident),* $(,)?) => {
        #[cfg(feature = "native")]
        mod embree {
            $(
                #[test]
                fn $name() {
                    super::$name(spar::accel::AccelKind::Embree)
                }
            )*
        }
        mod rust {
            $(
                #[test]
                fn $name() {
                    super::$name(spar::accel::AccelKind::Rust)
                }
            )*
        }
    };
}

// Importable as `support::render::on_every_backend` by any crate.
#[allow(unused_imports)]
pub(crate) use on_every_backend;

/// Renders at the given wavelengths with the scene's settings and this
/// build's default backend.
pub fn render_at(scene: &Scene, lambdas: &[f64]) -> (Film, Stats) {
    render_with(scene, lambdas, AccelKind::default())
}

/// Renders at the given wavelengths with the scene's settings through
/// the `accel` backend.
pub fn render_with(scene: &Scene, lambdas: &[f64], accel: AccelKind) -> (Film, Stats) {
    let accel = prepare::accel(scene, accel, 2, None).unwrap();
    let opts = prepare::options_at(scene, lambdas.to_vec());
    render(scene, accel.as_ref(), &opts)
}

/// Mean Stokes vector over a pixel rectangle [x0, x1) × [y0, y1).
pub fn mean_stokes(film: &Film, x0: u32, x1: u32, y0: u32, y1: u32, i: usize) -> [f64; 4] {
    let mut s = [0.0; 4];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = film.stokes(x, y, i);
            for c in 0..4 {
                s[c] += p[c];
            }
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

/// Degree of polarization, azimuth (degrees) and b/a of a Stokes vector.
pub fn polarimetry(s: [f64; 4]) -> (f64, f64, f64) {
    let p = spar::optics::Polarimetry::from_stokes(spar::optics::Stokes {
        s0: s[0],
        s1: s[1],
        s2: s[2],
        s3: s[3],
    });
    (
        p.degree_of_polarization,
        p.azimuth.to_degrees(),
        p.ellipticity,
    )
}

/// OBJ text of an axis-aligned box, faces counter-clockwise from outside.
pub fn box_obj(lo: [f64; 3], hi: [f64; 3]) -> String {
    let mut s = String::new();
    for i in 0..8 {
        let x = if i & 1 == 0 { lo[0] } else { hi[0] };
        let y = if i & 2 == 0 { lo[1] } else { hi[1] };
        let z = if i & 4 == 0 { lo[2] } else { hi[2] };
        s += &format!("v {x} {y} {z}\n");
    }
    for f in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        s += &format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]);
    }
    s
}

/// OBJ text of a prism: a convex polygon in the x–z plane (counter-clockwise
/// seen from +y), extruded over y ∈ [y0, y1].
pub fn prism_obj(polygon_xz: &[[f64; 2]], y0: f64, y1: f64) -> String {
    let n = polygon_xz.len();
    let mut s = String::new();
    for &[x, z] in polygon_xz {
        s += &format!("v {x} {y0} {z}\n");
    }
    for &[x, z] in polygon_xz {
        s += &format!("v {x} {y1} {z}\n");
    }
    // Counter-clockwise in x–z seen from +y is clockwise seen from −y: the
    // y1 cap (outward +y) lists the ring in order reversed... worked out
    // per face below and checked by the loader's orientation test.
    let ring = |o: usize| (0..n).map(move |i| o + i + 1);
    s += &format!(
        "f {}\n",
        ring(0).map(|i| i.to_string()).collect::<Vec<_>>().join(" ")
    );
    s += &format!(
        "f {}\n",
        ring(n)
            .rev()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    );
    for i in 0..n {
        let j = (i + 1) % n;
        s += &format!("f {} {} {} {}\n", i + 1, n + i + 1, n + j + 1, j + 1);
    }
    s
}

/// Renders at the given wavelengths through `accel` with the paths of a
/// sample combined as `model` says (docs/physics.md §9).
#[allow(dead_code)] // in the crates that do not use it
pub fn render_model(
    scene: &Scene,
    lambdas: &[f64],
    accel: AccelKind,
    model: spar::render::approx::CoherenceModel,
) -> (Film, Stats) {
    let mut scene = scene.clone();
    scene.settings.approx.strategy.coherence = model;
    render_with(&scene, lambdas, accel)
}

/// A white furnace's result: the worst |I/I_bg − 1| and the worst degree
/// of polarization over the image at 550 nm (the background is a
/// radiance-1 light, D65(550 nm)), and the render's counters.
#[allow(dead_code)] // in the crates that do not use it
pub fn furnace_worst(toml: &str) -> (f64, f64, Stats) {
    let (scene, _d) = scene(toml, &[]);
    let (film, stats) = render_at(&scene, &[550.0]);
    let bg = spar::spectrum::cie::d65(550.0);
    let (mut di, mut dp) = (0.0f64, 0.0f64);
    for y in 0..film.height {
        for x in 0..film.width {
            let s = film.stokes(x, y, 0);
            let (p, _, _) = polarimetry(s);
            di = di.max((s[0] / bg - 1.0).abs());
            dp = dp.max(p);
        }
    }
    (di, dp, stats)
}

/// Mean and standard error of the Stokes vector of `n` estimates of one
/// camera ray `(origin, direction, basis)` at one wavelength, and the
/// render's counters: the samples differ only in their random numbers
/// (sample keys of `seed` and `pixel`). Each estimate is taken as the film
/// sums it where one sample may be unphysical (unclipped,
/// `Coherence::stokes_linear`).
#[allow(dead_code)] // in the crates that do not use it
pub fn sampled_mean(
    tracer: &spar::render::integrator::Tracer,
    ray: (glam::DVec3, glam::DVec3, [glam::DVec3; 2]),
    media: &spar::render::integrator::WavelengthMedia,
    n: u32,
    (seed, pixel): (u64, u64),
) -> ([f64; 4], [f64; 4], Stats) {
    let (origin, d, basis) = ray;
    let mut sum = [0.0; 4];
    let mut sq = [0.0; 4];
    let mut stats = Stats::default();
    for sample in 0..n {
        let key = spar::render::sampling::SampleKey {
            seed,
            pixel,
            sample,
        };
        let mut out = [spar::optics::Coherence::zero(2)];
        tracer.trace_camera(
            origin,
            d,
            basis,
            std::slice::from_ref(media),
            &key,
            &mut out,
            &mut stats,
        );
        let s = out[0].stokes_linear();
        let s = [s.s0, s.s1, s.s2, s.s3];
        for c in 0..4 {
            sum[c] += s[c];
            sq[c] += s[c] * s[c];
        }
    }
    let nf = n as f64;
    let mean = sum.map(|v| v / nf);
    let se = std::array::from_fn(|c| ((sq[c] / nf - mean[c] * mean[c]).max(0.0) / nf).sqrt());
    (mean, se, stats)
}

/// A glass box over a checker-textured light, seen at an angle through
/// jittered pixel positions, 20×20 pixels at 450, 550 and 650 nm: edges,
/// texture and dispersion make most pixels vary from sample to sample, the
/// sky around the light does not. `render_keys` are more `[render]` lines
/// (the sampling settings under test).
pub fn checker_box(samples: u32, render_keys: &str) -> (Scene, tempfile::TempDir) {
    let text = format!(
        r#"
[camera]
eye = [0.0, -3.0, 4.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 40.0
resolution = [20, 20]
samples = {samples}
[render]
wavelengths = [450.0, 550.0, 650.0]
max_depth = 8
{render_keys}
[[object]]
mesh = "box.obj"
medium = "n-bk7"
[[light]]
corners = [[-2.0, -2.0, -1.0], [2.0, -2.0, -1.0], [2.0, 2.0, -1.0], [-2.0, 2.0, -1.0]]
radiance = 1.0
texture = "builtin:checker"
"#
    );
    let mesh = box_obj([-0.8, -0.8, -0.3], [0.8, 0.8, 0.3]);
    scene(&text, &[("box.obj", mesh)])
}

/// A pixel's Stokes values at every wavelength, as bits (for exact
/// comparisons).
pub fn bits(film: &Film, x: u32, y: u32) -> Vec<u64> {
    (0..film.lambdas.len())
        .flat_map(|i| film.stokes(x, y, i))
        .map(f64::to_bits)
        .collect()
}
