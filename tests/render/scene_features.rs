//! The scene-file keys of coherence, units, lights at infinity,
//! environments, the orthographic camera and the camera's analyzer: a good
//! value reads into what the renderer gets, a bad one is refused naming
//! file:line and the field. In process, through the scene loader (and,
//! for environments, one render).

use num_complex::Complex64;
use spar::farm::part::scene_hash;
use spar::optics::Jones;
use spar::render::approx::CoherenceModel;
use spar::render::camera::Projection;
use spar::scene::{Polarization, Scene};
use std::path::Path;

const GOOD: &str = r#"[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 30.0
resolution = [8, 8]

[render]
wavelengths = 8

[[object]]
mesh = "builtin:trichecker12"
medium = "calcite"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "s.toml", Path::new(".")).map_err(|e| e.to_string())
}

/// GOOD with `from` replaced by `to` (which must be there).
fn with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from}");
    GOOD.replacen(from, to, 1)
}

/// GOOD with `line` added to its `[render]` table (line 9).
fn render(line: &str) -> String {
    with("wavelengths = 8", &format!("wavelengths = 8\n{line}"))
}

/// GOOD with `lines` added to its `[camera]` table (line 7 on).
fn camera(lines: &str) -> String {
    with(
        "resolution = [8, 8]",
        &format!("resolution = [8, 8]\n{lines}"),
    )
}

/// GOOD with its light replaced by `light` (its table at line 15).
fn light(light: &str) -> String {
    let at = GOOD.find("[[light]]").unwrap();
    format!("{}[[light]]\n{light}\n", &GOOD[..at])
}

/// The message must start with `s.toml:LINE: FIELD: ` (`s.toml:LINE: `
/// for serde's own errors, `field` empty) and hold each of `says`.
fn refused(text: &str, line: usize, field: &str, says: &[&str]) {
    let err = parse(text)
        .err()
        .unwrap_or_else(|| panic!("accepted:\n{text}"));
    let head = if field.is_empty() {
        format!("s.toml:{line}: ")
    } else {
        format!("s.toml:{line}: {field}: ")
    };
    assert!(err.starts_with(&head), "expected `{head}…`, got `{err}`");
    for s in says {
        assert!(err.contains(s), "`{s}` not in `{err}`");
    }
}

fn c(re: f64, im: f64) -> Complex64 {
    Complex64::new(re, im)
}

fn assert_jones(j: &Jones, want: [[Complex64; 2]; 2], what: &str) {
    assert_eq!((j.rows, j.cols), (2, 2), "{what}");
    for (r, (got, want)) in j.m.iter().zip(want).enumerate() {
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            assert!(
                (g - w).norm() < 1e-12,
                "{what}: entry ({r}, {k}) is {g}, want {w}"
            );
        }
    }
}

#[test]
fn units_set_the_length_of_a_scene_unit() {
    assert_eq!(parse(GOOD).unwrap().unit_nm, 1e6, "millimetres by default");
    for (u, nm) in [
        ("nm", 1.0),
        ("um", 1e3),
        ("µm", 1e3),
        ("mm", 1e6),
        ("cm", 1e7),
        ("m", 1e9),
    ] {
        let s = parse(&render(&format!("units = \"{u}\""))).unwrap();
        assert_eq!(s.unit_nm, nm, "{u}");
    }
    for bad in ["furlong", "M", "", "inch"] {
        refused(
            &render(&format!("units = \"{bad}\"")),
            10,
            "render.units",
            &[&format!("`{bad}`"), "nm, um (or µm), mm, cm or m"],
        );
    }
    refused(&render("units = 3"), 10, "", &["string"]);
    // Units are part of what a scene renders.
    assert_ne!(
        scene_hash(&parse(GOOD).unwrap()),
        scene_hash(&parse(&render("units = \"um\"")).unwrap())
    );
}

#[test]
fn coherence_reads_physical_or_incoherent() {
    let coherence = |s: &Scene| s.settings.approx.strategy.coherence;
    assert_eq!(coherence(&parse(GOOD).unwrap()), CoherenceModel::Physical);
    for (v, want) in [
        ("physical", CoherenceModel::Physical),
        ("incoherent", CoherenceModel::Incoherent),
    ] {
        let s = parse(&render(&format!("coherence = \"{v}\""))).unwrap();
        assert_eq!(coherence(&s), want, "{v}");
    }
    refused(
        &render("coherence = \"partial\""),
        10,
        "render.coherence",
        &["`partial`", "\"physical\"", "\"incoherent\""],
    );
}

#[test]
fn a_light_at_infinity_reads_its_direction_size_and_polarizer() {
    let s = parse(&light(
        "direction = [0.0, 0.0, -2.0]\nangular_diameter = 0.53\nradiance = 3.0\n\
         polarization = { linear = [1.0, 0.0, 1.0] }",
    ))
    .unwrap();
    assert!(s.lights.is_empty(), "{:?}", s.lights);
    assert_eq!(s.distant_lights.len(), 1);
    let d = &s.distant_lights[0];
    assert_eq!(d.direction, glam::DVec3::new(0.0, 0.0, -1.0));
    assert!((d.angular_diameter - 0.53f64.to_radians()).abs() < 1e-15);
    assert_eq!(d.radiance, 3.0);
    // The polarizer's axis, projected normal to the direction, normalized.
    match d.polarization {
        Polarization::Linear { axis } => {
            assert!((axis - glam::DVec3::X).length() < 1e-15, "{axis}")
        }
        ref p => panic!("{p:?}"),
    }
    // A skew direction is normalized; the defaults are collimated,
    // radiance 1, unpolarized.
    let s = parse(&light("direction = [1.0, 2.0, -2.0]")).unwrap();
    let d = &s.distant_lights[0];
    assert!((d.direction - glam::DVec3::new(1.0, 2.0, -2.0) / 3.0).length() < 1e-15);
    assert_eq!(d.angular_diameter, 0.0);
    assert_eq!(d.radiance, 1.0);
    assert_eq!(d.polarization, Polarization::Unpolarized);
    // A calcite plate, as on a rectangle; the whole sky's disc.
    let s = parse(&light(
        "direction = [0, 0, -1]\nangular_diameter = 180\n\
         polarization = { calcite_plate = { keep = \"e\", axis = [0.0, 3.0, 0.0] } }",
    ))
    .unwrap();
    assert_eq!(s.distant_lights[0].angular_diameter, std::f64::consts::PI);
    assert!(matches!(
        s.distant_lights[0].polarization,
        Polarization::CalcitePlate { axis, .. } if axis == glam::DVec3::Y
    ));
    // A rectangle and a light at infinity together.
    let both = format!("{GOOD}\n[[light]]\ndirection = [0.0, 0.0, -1.0]\n");
    let s = parse(&both).unwrap();
    assert_eq!((s.lights.len(), s.distant_lights.len()), (1, 1));
    // A light at infinity alone lights the scene.
    parse(&light("direction = [0.0, 0.0, -1.0]\nradiance = 0.0")).unwrap();
    // It is part of what the scene renders.
    let a = scene_hash(&parse(&both).unwrap());
    let b = scene_hash(&parse(&both.replace("[0.0, 0.0, -1.0]", "[0.0, 0.1, -1.0]")).unwrap());
    assert_ne!(a, b);
    assert_ne!(a, scene_hash(&parse(GOOD).unwrap()));
}

#[test]
fn bad_lights_at_infinity_are_refused_by_line_and_field() {
    // The [[light]] table starts at line 15; its first key is line 16.
    refused(
        &light("direction = [0.0, 0.0, 0.0]"),
        16,
        "light[0].direction",
        &["finite non-zero"],
    );
    refused(
        &light("direction = [nan, 0.0, 1.0]"),
        16,
        "light[0].direction",
        &["finite non-zero"],
    );
    refused(
        &light("direction = [0.0, 0.0, -1.0, 0.0]"),
        16,
        "light.direction",
        &["4 value(s) given, it takes exactly 3"],
    );
    for bad in ["-1.0", "180.5", "nan", "inf"] {
        refused(
            &light(&format!(
                "direction = [0.0, 0.0, -1.0]\nangular_diameter = {bad}"
            )),
            17,
            "light[0].angular_diameter",
            &["from 0 (collimated) to 180"],
        );
    }
    refused(
        &light("direction = [0.0, 0.0, -1.0]\nradiance = -1.0"),
        17,
        "light[0].radiance",
        &["≥ 0"],
    );
    refused(
        &light("direction = [0.0, 0.0, -1.0]\ntexture = \"builtin:checker\""),
        17,
        "light[0].texture",
        &["textures need a rectangle (`corners`)"],
    );
    refused(
        &light("direction = [0.0, 0.0, -1.0]\npolarization = { linear = [0.0, 0.0, 2.0] }"),
        17,
        "light[0].polarization.linear",
        &["perpendicular to the light's direction"],
    );
    refused(
        &light("direction = [0.0, 0.0, -1.0]\npolarization = \"circular\""),
        17,
        "light[0].polarization",
        &["unknown polarization `circular`"],
    );
    // Exactly one of corners and direction.
    refused(
        &light("radiance = 2.0"),
        15,
        "light[0]",
        &[
            "exactly one of `corners`",
            "`direction`",
            "`environment`",
            "none of them",
        ],
    );
    refused(
        &format!("{GOOD}direction = [0.0, 0.0, -1.0]\n"),
        15,
        "light[0]",
        &["exactly one of `corners`", "both"],
    );
    // A rectangle has no angular diameter.
    refused(
        &format!("{GOOD}angular_diameter = 1.0\n"),
        17,
        "light[0].angular_diameter",
        &["light at infinity"],
    );
    // Unknown keys are refused.
    refused(
        &light("direction = [0.0, 0.0, -1.0]\nspread = 2.0"),
        17,
        "",
        &["unknown field `spread`"],
    );
}

#[test]
fn an_orthographic_camera_takes_a_width_and_no_fov() {
    let s = parse(&camera("projection = \"orthographic\"\nwidth = 4.0")).unwrap();
    assert_eq!(s.camera.projection, Projection::Orthographic { width: 4.0 });
    // Every ray travels along the viewing direction from the image plane.
    let (o0, d0) = s.camera.ray(0.0, 0.0);
    let (o1, d1) = s.camera.ray(8.0, 8.0);
    assert_eq!(d0, d1);
    assert!(((o1 - o0).length() - 4.0 * 2f64.sqrt()).abs() < 1e-12);
    // fov is optional for it.
    let no_fov = camera("projection = \"orthographic\"\nwidth = 4.0").replace("fov = 30.0\n", "");
    parse(&no_fov).unwrap();
    // A pinhole camera is the default, and its fov is still required, with
    // serde's message.
    let s = parse(&camera("projection = \"pinhole\"")).unwrap();
    assert_eq!(s.camera.projection, Projection::Pinhole);
    assert_eq!(parse(GOOD).unwrap().camera.projection, Projection::Pinhole);
    let err = parse(&GOOD.replace("fov = 30.0\n", "")).unwrap_err();
    assert_eq!(err, "s.toml:1: missing field `fov`");

    refused(
        &camera("projection = \"orthographic\""),
        1,
        "camera.width",
        &["needs `width`"],
    );
    refused(&camera("width = 4.0"), 7, "camera.width", &["orthographic"]);
    refused(
        &camera("projection = \"fisheye\""),
        7,
        "camera.projection",
        &["`fisheye`", "\"pinhole\"", "\"orthographic\""],
    );
    for bad in ["0.0", "-2.0", "nan", "inf"] {
        refused(
            &camera(&format!("projection = \"orthographic\"\nwidth = {bad}")),
            8,
            "camera.width",
            &["finite number > 0"],
        );
    }
    refused(
        &camera("projection = \"orthographic\"\nwidth = 1e7"),
        8,
        "camera.width",
        &["beyond 1e6 units"],
    );
}

#[test]
fn an_orthographic_camera_whose_image_plane_corner_is_in_a_stone_is_refused() {
    let (lo, hi) = parse(GOOD).unwrap().objects[0].mesh.bounds();
    let centre = 0.5 * (lo + hi);
    // The eye 3 units left of and below the stone's centre, looking along
    // +y: the top-right corner of a 6-unit image is the centre.
    let eye = centre - glam::DVec3::new(3.0, 0.0, 3.0);
    let look = eye + glam::DVec3::Y;
    let text = GOOD
        .replace(
            "eye = [0.0, -3.0, 2.0]",
            &format!("eye = [{:?}, {:?}, {:?}]", eye.x, eye.y, eye.z),
        )
        .replace(
            "look_at = [0.0, 0.0, 0.0]",
            &format!("look_at = [{:?}, {:?}, {:?}]", look.x, look.y, look.z),
        );
    // As a pinhole camera the eye is outside: it loads.
    parse(&text).unwrap();
    let ortho = text.replace(
        "resolution = [8, 8]",
        "resolution = [8, 8]\nprojection = \"orthographic\"\nwidth = 6.0",
    );
    refused(
        &ortho,
        8,
        "camera.width",
        &[
            "image-plane corner",
            "inside object[0] (builtin:trichecker12",
        ],
    );
    // A narrower image keeps its corners outside.
    parse(&ortho.replace("width = 6.0", "width = 1.0")).unwrap();
}

#[test]
fn the_analyzer_is_the_jones_matrix_of_its_chain() {
    let analyzer = |a: &str| {
        parse(&camera(&format!("analyzer = {a}")))
            .unwrap()
            .camera
            .analyzer
            .expect("an analyzer")
    };
    assert_eq!(parse(GOOD).unwrap().camera.analyzer, None);
    let (o, l) = (c(0.0, 0.0), c(1.0, 0.0));
    // A polarizer at 90° (image up) passes y and blocks x.
    let p = analyzer("{ linear = 90.0 }");
    assert_jones(&p, [[o, o], [o, l]], "linear = 90");
    let x = p.apply([l, o]);
    assert!(x[0].norm() < 1e-15 && x[1].norm() < 1e-15, "{x:?}");
    let y = p.apply([o, l]);
    assert!((y[1] - l).norm() < 1e-15 && y[0].norm() < 1e-15, "{y:?}");
    // At 30°: the projector a aᵀ, a = (cos 30°, sin 30°).
    let (s30, c30) = 30f64.to_radians().sin_cos();
    assert_jones(
        &analyzer("{ linear = 30 }"),
        [
            [c(c30 * c30, 0.0), c(c30 * s30, 0.0)],
            [c(c30 * s30, 0.0), c(s30 * s30, 0.0)],
        ],
        "linear = 30",
    );

    // A retarder, fast axis θ, retardance δ: a aᵀ + e^{iδ} b bᵀ with
    // a = (cos θ, sin θ) the fast axis and b = (−sin θ, cos θ) the slow.
    let retarder = |theta_deg: f64, delta_deg: f64| {
        let (s, co) = theta_deg.to_radians().sin_cos();
        let e = Complex64::from_polar(1.0, delta_deg.to_radians());
        [
            [co * co + e * s * s, (1.0 - e) * co * s],
            [(1.0 - e) * co * s, s * s + e * co * co],
        ]
    };
    // A quarter-wave plate at 45°: ½ [[1+i, 1−i], [1−i, 1+i]]; x-linear
    // light leaves it circular (equal amplitudes, 90° apart in phase).
    let q = analyzer("{ retarder = { fast_axis = 45.0, retardance = 90.0 } }");
    assert_jones(&q, retarder(45.0, 90.0), "quarter-wave at 45°");
    assert_jones(
        &q,
        [[c(0.5, 0.5), c(0.5, -0.5)], [c(0.5, -0.5), c(0.5, 0.5)]],
        "quarter-wave at 45°, by hand",
    );
    let out = q.apply([l, o]);
    assert!((out[0].norm() - out[1].norm()).abs() < 1e-15, "{out:?}");
    assert!((out[0].norm_sqr() + out[1].norm_sqr() - 1.0).abs() < 1e-15);
    let phase = (out[1] / out[0]).arg();
    assert!(
        (phase.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
        "{phase}"
    );

    // The retarder first, then the polarizer: P · R.
    let chain = analyzer(
        "{ retarder = { fast_axis = 20.0, retardance = 70.0 }, then = { linear = 110.0 } }",
    );
    let r = retarder(20.0, 70.0);
    let (s, co) = 110f64.to_radians().sin_cos();
    let pm = [[co * co, co * s], [co * s, s * s]];
    let mut want = [[o; 2]; 2];
    for (i, row) in want.iter_mut().enumerate() {
        for (k, w) in row.iter_mut().enumerate() {
            *w = pm[i][0] * r[0][k] + pm[i][1] * r[1][k];
        }
    }
    assert_jones(&chain, want, "retarder then linear");
    // Chains nest: a polarizer, a half-wave plate, a polarizer.
    let three = analyzer(
        "{ linear = 0.0, then = { retarder = { fast_axis = 22.5, retardance = 180.0 }, \
         then = { linear = 45.0 } } }",
    );
    // x through a half-wave plate at 22.5° turns to 45° and passes whole.
    let out = three.apply([l, o]);
    let half = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (out[0] - c(half, 0.0)).norm() < 1e-12 && (out[1] - c(half, 0.0)).norm() < 1e-12,
        "{out:?}"
    );
    assert!(three.apply([o, l]).iter().all(|v| v.norm() < 1e-12));
    // The analyzer is part of what the scene renders.
    assert_ne!(
        scene_hash(&parse(GOOD).unwrap()),
        scene_hash(&parse(&camera("analyzer = { linear = 0.0 }")).unwrap())
    );
}

#[test]
fn bad_analyzers_are_refused_by_line_and_field() {
    let bad = |a: &str| camera(&format!("analyzer = {a}"));
    for v in ["nan", "inf", "-inf"] {
        refused(
            &bad(&format!("{{ linear = {v} }}")),
            7,
            "camera.analyzer.linear",
            &["finite number of degrees"],
        );
    }
    refused(
        &bad("{ retarder = { fast_axis = nan, retardance = 90.0 } }"),
        7,
        "camera.analyzer.retarder.fast_axis",
        &["finite"],
    );
    refused(
        &bad("{ retarder = { fast_axis = 0.0, retardance = inf } }"),
        7,
        "camera.analyzer.retarder.retardance",
        &["finite"],
    );
    refused(
        &bad("{ linear = 0.0, then = { then = { linear = nan } } }"),
        7,
        "camera.analyzer.then",
        &["exactly one of `linear = DEG`"],
    );
    refused(
        &bad("{ linear = 0.0, then = { linear = nan } }"),
        7,
        "camera.analyzer.then.linear",
        &["finite"],
    );
    refused(
        &bad("{ linear = 0.0, retarder = { fast_axis = 0.0, retardance = 90.0 } }"),
        7,
        "camera.analyzer",
        &["exactly one of"],
    );
    refused(&bad("{}"), 7, "camera.analyzer", &["exactly one of"]);
    refused(
        &bad("{ circular = 1.0 }"),
        7,
        "",
        &["unknown field `circular`"],
    );
    refused(
        &bad("{ retarder = { fast_axis = 0.0 } }"),
        7,
        "",
        &["missing field `retardance`"],
    );
    // The table form names its lines too.
    let text = camera("[camera.analyzer]\nlinear = 0.0\nthen = { linear = inf }");
    refused(&text, 9, "camera.analyzer.then.linear", &["finite"]);
}

/// Writes a linear float image of `channels` (interleaved `data`) as
/// `dir/name` (EXR or PNG by its extension).
fn write_image(
    dir: &Path,
    name: &str,
    w: usize,
    h: usize,
    channels: &[&str],
    data: Vec<f32>,
    pixel_type: spar::image::PixelType,
) {
    let image =
        spar::image::Image::new(w, h, channels.iter().map(|c| c.to_string()).collect(), data)
            .unwrap();
    spar::image::write(
        &dir.join(name),
        &image,
        spar::image::WriteOptions::new(pixel_type),
    )
    .unwrap();
}

/// `text` read with relative paths resolved in `dir`.
fn parse_in(text: &str, dir: &Path) -> Result<Scene, String> {
    Scene::parse(text, "s.toml", dir).map_err(|e| e.to_string())
}

#[test]
fn an_environment_reads_uniform_or_a_latitude_longitude_map() {
    use spar::image::PixelType;
    // Uniform, the only light: radiance 1 by default.
    let s = parse(&light("environment = \"uniform\"")).unwrap();
    assert!(s.lights.is_empty() && s.distant_lights.is_empty());
    let env = s.environment.as_ref().expect("an environment");
    assert_eq!(env.radiance, 1.0);
    assert!(env.map.is_none());
    let s = parse(&light("environment = \"uniform\"\nradiance = 2.5")).unwrap();
    assert_eq!(s.environment.as_ref().unwrap().radiance, 2.5);
    // Radiance 0 still counts as a light; a zero background is allowed.
    parse(&light("environment = \"uniform\"\nradiance = 0.0")).unwrap();
    parse(&format!(
        "{}\n[background]\nradiance = 0.0\n",
        light("environment = \"uniform\"")
    ))
    .unwrap();
    // With a rectangle.
    let s = parse(&format!("{GOOD}\n[[light]]\nenvironment = \"uniform\"\n")).unwrap();
    assert_eq!(s.lights.len(), 1);
    assert!(s.environment.is_some());

    // A 4×2 EXR map, one bright texel (2, 1) of [5, 1, 0.5]; alpha is
    // ignored (0 here, and NaN in a second file).
    let dir = tempfile::tempdir().unwrap();
    let texels = |alpha: f32| {
        let mut data = Vec::new();
        for y in 0..2 {
            for x in 0..4 {
                let rgb = if (x, y) == (2, 1) {
                    [5.0, 1.0, 0.5]
                } else {
                    [0.25; 3]
                };
                data.extend_from_slice(&rgb);
                data.push(alpha);
            }
        }
        data
    };
    let rgba = ["R", "G", "B", "A"];
    write_image(
        dir.path(),
        "sky.exr",
        4,
        2,
        &rgba,
        texels(0.0),
        PixelType::F32,
    );
    write_image(
        dir.path(),
        "nan_alpha.exr",
        4,
        2,
        &rgba,
        texels(f32::NAN),
        PixelType::F32,
    );
    for file in ["sky.exr", "nan_alpha.exr"] {
        let s = parse_in(
            &light(&format!("environment = \"{file}\"\nradiance = 3.0")),
            dir.path(),
        )
        .unwrap();
        let env = s.environment.as_ref().unwrap();
        assert_eq!(env.radiance, 3.0);
        let map = env.map.as_ref().expect("a map");
        assert_eq!((map.texture.width, map.texture.height), (4, 2), "{file}");
        for (i, &scale) in map.scale.iter().enumerate() {
            let want = if i == 4 + 2 { 5.0 } else { 0.25 };
            assert_eq!(scale, want, "{file}: texel {i}");
        }
    }
    // A PNG (8-bit sRGB, decoded to linear): white is 1.
    write_image(
        dir.path(),
        "white.png",
        3,
        1,
        &["R", "G", "B"],
        vec![1.0; 9],
        PixelType::U8,
    );
    let s = parse_in(&light("environment = \"white.png\""), dir.path()).unwrap();
    let map = s.environment.as_ref().unwrap().map.as_ref().unwrap();
    assert_eq!((map.texture.width, map.texture.height), (3, 1));
    assert_eq!(map.scale, vec![1.0; 3]);
    // A built-in texture.
    let s = parse(&light("environment = \"builtin:checker\"")).unwrap();
    let map = s.environment.as_ref().unwrap().map.as_ref().unwrap();
    assert_eq!((map.texture.width, map.texture.height), (8, 8));

    // The environment is part of what the scene renders.
    let hash = |text: &str| scene_hash(&parse_in(text, dir.path()).unwrap());
    let uniform = hash(&light("environment = \"uniform\""));
    assert_ne!(
        uniform,
        hash(&light("environment = \"uniform\"\nradiance = 2.0"))
    );
    assert_ne!(uniform, hash(&light("environment = \"sky.exr\"")));
    assert_ne!(
        hash(&light("environment = \"sky.exr\"")),
        hash(&light("environment = \"white.png\""))
    );
    assert_ne!(
        hash(GOOD),
        hash(&format!("{GOOD}\n[[light]]\nenvironment = \"uniform\"\n"))
    );
}

#[test]
fn bad_environments_are_refused_by_line_and_field() {
    use spar::image::PixelType;
    let env = "environment = \"uniform\"";
    // The [[light]] table starts at line 15; its first key is line 16.
    refused(
        &light(&format!(
            "{env}\npolarization = {{ linear = [1.0, 0.0, 0.0] }}"
        )),
        17,
        "light[0].polarization",
        &["an environment is unpolarized"],
    );
    refused(
        &light(&format!("{env}\npolarization = \"unpolarized\"")),
        17,
        "light[0].polarization",
        &["an environment is unpolarized"],
    );
    refused(
        &light(&format!("{env}\ntexture = \"builtin:checker\"")),
        17,
        "light[0].texture",
        &["map is its `environment` file"],
    );
    refused(
        &light(&format!("{env}\nangular_diameter = 0.5")),
        17,
        "light[0].angular_diameter",
        &["every direction"],
    );
    for bad in ["-1.0", "nan", "inf"] {
        refused(
            &light(&format!("{env}\nradiance = {bad}")),
            17,
            "light[0].radiance",
            &["finite number ≥ 0"],
        );
    }
    refused(
        &light("environment = \"\""),
        16,
        "light[0].environment",
        &["\"uniform\""],
    );
    refused(
        &light("environment = \"builtin:sky\""),
        16,
        "light[0].environment",
        &["no built-in texture `sky`", "checker"],
    );
    refused(
        &light("environment = \"missing.exr\""),
        16,
        "light[0].environment",
        &["missing.exr"],
    );
    refused(&light("environment = 3"), 16, "", &["string"]);
    // Exactly one of corners, direction and environment.
    refused(
        &format!("{GOOD}{env}\n"),
        15,
        "light[0]",
        &["exactly one of", "both `corners` and `environment`"],
    );
    refused(
        &light(&format!("{env}\ndirection = [0.0, 0.0, -1.0]")),
        15,
        "light[0]",
        &["both `direction` and `environment`"],
    );
    refused(
        &format!("{GOOD}{env}\ndirection = [0.0, 0.0, -1.0]\n"),
        15,
        "light[0]",
        &["all three"],
    );
    // At most one environment: the second is refused, naming the first.
    refused(
        &format!("{}[[light]]\n{env}\n", light(env)),
        18,
        "light[1].environment",
        &["at most one environment", "light[0] (line 16)"],
    );
    // It replaces the background: not both.
    refused(
        &format!("{}\n[background]\nradiance = 0.5\n", light(env)),
        19,
        "background.radiance",
        &[
            "environment (light[0], line 16)",
            "replaces the background",
            "give one",
        ],
    );
    // Texels must be finite and ≥ 0: the file and the pixel are named.
    let dir = tempfile::tempdir().unwrap();
    let rgb = ["R", "G", "B"];
    let mut nan = vec![1.0f32; 2 * 2 * 3];
    nan[3 + 1] = f32::NAN; // pixel (1, 0), green
    write_image(dir.path(), "nan.exr", 2, 2, &rgb, nan, PixelType::F32);
    let mut negative = vec![1.0f32; 2 * 2 * 3];
    negative[2 * 3 + 2] = -0.5; // pixel (0, 1), blue
    write_image(
        dir.path(),
        "negative.exr",
        2,
        2,
        &rgb,
        negative,
        PixelType::F32,
    );
    let mut inf = vec![1.0f32; 2 * 2 * 3];
    inf[3 * 3] = f32::INFINITY; // pixel (1, 1), red
    write_image(dir.path(), "inf.exr", 2, 2, &rgb, inf, PixelType::F32);
    for (file, pixel) in [
        ("nan.exr", "pixel (1, 0)"),
        ("negative.exr", "pixel (0, 1)"),
        ("inf.exr", "pixel (1, 1)"),
    ] {
        let err = parse_in(&light(&format!("environment = \"{file}\"")), dir.path())
            .err()
            .unwrap_or_else(|| panic!("{file} accepted"));
        assert!(
            err.starts_with("s.toml:16: light[0].environment: "),
            "{err}"
        );
        for says in [file, pixel, "finite and ≥ 0"] {
            assert!(err.contains(says), "`{says}` not in `{err}`");
        }
    }
    // A file that is not an image.
    std::fs::write(dir.path().join("sky.png"), b"not a png").unwrap();
    let err = parse_in(&light("environment = \"sky.png\""), dir.path()).unwrap_err();
    assert!(
        err.starts_with("s.toml:16: light[0].environment: ") && err.contains("sky.png"),
        "{err}"
    );
}

/// A scene of nothing but an environment (its 1×2 map: the upper
/// hemisphere grey 2, the lower grey 0.5) seen by a narrow camera at the
/// origin looking along `look`: every pixel sees the environment's
/// radiance there, unpolarized, with either coherence model.
#[test]
fn an_environment_is_seen_where_rays_leave_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    write_image(
        dir.path(),
        "sky.exr",
        1,
        2,
        &["R", "G", "B"],
        vec![2.0, 2.0, 2.0, 0.5, 0.5, 0.5],
        spar::image::PixelType::F32,
    );
    let lambdas = [450.0, 550.0, 650.0];
    for (look, up, level) in [
        ("[0.0, 0.0, 1.0]", "[0.0, 1.0, 0.0]", 2.0),
        ("[0.0, 0.0, -1.0]", "[0.0, 1.0, 0.0]", 0.5),
        // Sideways but a little above and below the horizon.
        ("[1.0, 0.3, 0.2]", "[0.0, 0.0, 1.0]", 2.0),
        ("[-0.4, -1.0, -0.2]", "[0.0, 0.0, 1.0]", 0.5),
    ] {
        for coherence in ["physical", "incoherent"] {
            let text = format!(
                "[camera]\neye = [0.0, 0.0, 0.0]\nlook_at = {look}\nup = {up}\nfov = 1.0\n\
                 resolution = [2, 2]\n\n[render]\ncoherence = \"{coherence}\"\n\n\
                 [[light]]\nenvironment = \"sky.exr\"\nradiance = 1.5\n"
            );
            let s = parse_in(&text, dir.path()).unwrap_or_else(|e| panic!("{e}"));
            let (film, _) = crate::support::render::render_at(&s, &lambdas);
            for (i, &lambda) in lambdas.iter().enumerate() {
                let want = 1.5 * level * spar::spectrum::cie::d65(lambda);
                for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let st = film.stokes(x, y, i);
                    let what = format!("look {look}, {coherence}, {lambda} nm, pixel ({x}, {y})");
                    assert!(
                        (st[0] - want).abs() <= 1e-6 * want,
                        "{what}: S0 {} want {want}",
                        st[0]
                    );
                    for (c, v) in st.iter().enumerate().skip(1) {
                        assert!(v.abs() <= 1e-9 * want, "{what}: S{c} {v}");
                    }
                }
            }
        }
    }
}

#[test]
fn center_sampling_puts_every_sample_through_the_pixel_centre() {
    use spar::render::camera::PixelSampling;
    use spar::render::integrator::{Stats, Tracer, WavelengthMedia};
    let s = parse(&camera("samples = 3\nsampling = \"center\"")).unwrap();
    assert_eq!(s.camera.sampling, PixelSampling::Center);
    assert_eq!(
        parse(GOOD).unwrap().camera.sampling,
        PixelSampling::Jittered
    );
    refused(
        &camera("sampling = \"stratified\""),
        7,
        "camera.sampling",
        &["`stratified`", "jittered", "center"],
    );
    // Each pixel is the tree of the ray through its centre, whatever the
    // sample: the film equals one tracer call per pixel centre.
    let (film, _) = crate::support::render::render_at(&s, &[550.0]);
    let accel = spar::render::prepare::accel(&s, Default::default(), 1, None).unwrap();
    let tracer = Tracer::new(&s, accel.as_ref(), spar::render::prepare::tree(&s))
        .with_strategy(s.settings.approx.strategy);
    let media = WavelengthMedia::new(&s, 550.0);
    let mut lit = 0;
    for y in 0..8 {
        for x in 0..8 {
            let (origin, d) = s.camera.ray(x as f64 + 0.5, y as f64 + 0.5);
            let (bx, by) = s.camera.stokes_frame(d);
            let j = tracer.camera_ray(origin, d, [bx, by], &media, &mut Stats::default());
            let (want, got) = (j.stokes().to_array(), film.stokes(x, y, 0));
            for c in 0..4 {
                assert!(
                    (got[c] - want[c]).abs() <= 1e-6 * want[0].max(1e-30),
                    "pixel ({x}, {y}) S{c}: {} vs the centre ray's {}",
                    got[c],
                    want[c]
                );
            }
            lit += (want[0] > 0.0) as u32;
        }
    }
    assert!(lit > 8, "the gem and the light are in view");
}
