//! Flags mean what they say (issue 16 item 5): an output name whose
//! extension does not fit the mode is refused (exit status 2) naming the
//! name to use, for every mode and extension; `--wavelength` is used by
//! every mode but color (stokes then holds that wavelength alone) and
//! refused where no mode uses it. The rules are docs/outputs.md's.

use crate::support::run::{code_out_err, spar, spar_ok};
use std::path::Path;

/// A light behind a vertical polarizer, seen directly: fast at any size.
const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [4, 3]
[[light]]
corners = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]]
polarization = { linear = [0.0, 1.0, 0.0] }
"#;

const MODES: [&str; 19] = [
    "color",
    "mono",
    "dop",
    "ellipticity",
    "ellipticity-paper",
    "azimuth",
    "stokes",
    "stokes-rgb",
    "polcam",
    "polcam-mosaic",
    "aolp",
    "dolp",
    "polvis-stokes",
    "polvis-dop",
    "polvis-top",
    "polvis-lin",
    "polvis-cir",
    "sheet",
    "dichroscope",
];

/// MODES is every camera mode spar has, so every mode's names are checked.
#[test]
fn the_modes_checked_are_every_mode() {
    use clap::ValueEnum;
    let mut all: Vec<&str> = spar::render::output::OutputMode::value_variants()
        .iter()
        .map(|m| m.name())
        .collect();
    let mut checked = MODES.to_vec();
    all.sort_unstable();
    checked.sort_unstable();
    assert_eq!(checked, all);
}

/// The extensions a mode's file may have (docs/outputs.md), lower case;
/// the first is the one a name without extension gets.
fn fitting(mode: &str) -> &'static [&'static str] {
    match mode {
        "stokes" | "stokes-rgb" => &["exr"],
        "polcam" | "polcam-mosaic" => &["png", "exr", "tif", "tiff", "jpg", "jpeg"],
        _ => &["png", "tif", "tiff", "jpg", "jpeg"],
    }
}

/// The files in `dir` but the scene, sorted.
fn written(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "s.toml")
        .collect();
    v.sort();
    v
}

fn clear(dir: &Path) {
    for f in written(dir) {
        std::fs::remove_file(dir.join(f)).unwrap();
    }
}

fn render(dir: &Path, args: &[&str]) -> (i32, String) {
    let (code, _, err) = code_out_err(&spar(dir, &[&["render", "s.toml", "-q"], args].concat()));
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    (code, err)
}

#[test]
fn every_mode_and_extension_is_written_or_refused_with_the_name_to_use() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    let native = cfg!(feature = "native");
    for mode in MODES {
        for ext in [
            None,
            Some("png"),
            Some("PNG"),
            Some("exr"),
            Some("tif"),
            Some("jpg"),
            Some("txt"),
        ] {
            clear(d);
            let name = ext.map_or("x".to_string(), |e| format!("x.{e}"));
            let (code, err) = render(d, &["--mode", mode, "-o", &name]);
            let what = format!("--mode {mode} -o {name}: exit {code}: {err}");
            let fits = ext.is_none_or(|e| fitting(mode).contains(&e.to_ascii_lowercase().as_str()));
            let own = fitting(mode)[0];
            // The pure-Rust build writes PNG and EXR only: a name that fits
            // the mode but needs OpenImageIO is refused there (a name that
            // does not fit is refused first, with the name to use).
            let pure_refusal = fits && !native && matches!(ext, Some("tif" | "jpg"));
            if fits && !pure_refusal {
                assert_eq!(code, 0, "{what}");
                let ext = ext.unwrap_or(own);
                let expected: Vec<String> = if mode == "polcam" {
                    ["000", "045", "090", "135"]
                        .iter()
                        .map(|a| format!("x-{a}.{ext}"))
                        .collect()
                } else if mode == "polvis-stokes" {
                    ["s1", "s2", "s3"]
                        .iter()
                        .map(|a| format!("x-{a}.{ext}"))
                        .collect()
                } else {
                    vec![format!("x.{ext}")]
                };
                assert_eq!(written(d), expected, "{what}");
                // Float EXR where the name asks for it, display images
                // otherwise: readable, the size of the render.
                // The false-colour maps have their legend below (at least
                // spar::cli::legend::MIN_WIDTH wide).
                let img = spar::image::read(&d.join(&expected[0])).unwrap();
                use spar::cli::legend::{GAP, HEIGHT, MIN_WIDTH, TITLE_HEIGHT};
                let size = if mode == "aolp" || mode == "dolp" || mode.starts_with("polvis") {
                    (MIN_WIDTH, 3 + HEIGHT)
                } else if mode == "sheet" {
                    (4 + 2 * GAP + 2 * MIN_WIDTH, TITLE_HEIGHT + 3 + HEIGHT)
                } else if mode == "dichroscope" {
                    // Two images side by side.
                    (8, 3)
                } else {
                    (4, 3)
                };
                assert_eq!((img.width(), img.height()), size, "{what}");
            } else {
                assert_eq!(code, 2, "{what}");
                if pure_refusal {
                    assert!(err.contains("native"), "{what}");
                } else {
                    assert!(err.contains(&name), "{what}");
                    assert!(err.contains(&format!("use -o x.{own}")), "{what}");
                }
                assert!(written(d).is_empty(), "{what}: {:?}", written(d));
            }
        }
    }
}

#[test]
fn several_modes_take_the_extension_where_it_fits() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "color,stokes",
            "out.png",
            &["out-color.png", "out-stokes.exr"],
        ),
        (
            "dop,polcam,stokes",
            "out.exr",
            &[
                "out-dop.png",
                "out-polcam-000.exr",
                "out-polcam-045.exr",
                "out-polcam-090.exr",
                "out-polcam-135.exr",
                "out-stokes.exr",
            ],
        ),
        (
            "mono,polcam-mosaic",
            "out",
            &["out-mono.png", "out-polcam-mosaic.png"],
        ),
        (
            "stokes,polcam-mosaic",
            "out.png",
            &["out-polcam-mosaic.png", "out-stokes.exr"],
        ),
    ];
    for (modes, name, files) in cases {
        clear(d);
        let (code, err) = render(d, &["--mode", modes, "-o", name]);
        assert_eq!(code, 0, "{modes} {name}: {err}");
        assert_eq!(written(d), files, "{modes} {name}");
    }
    // An extension no mode takes is refused.
    clear(d);
    let (code, err) = render(d, &["--mode", "color,dop", "-o", "out.txt"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("out.txt") && err.contains("-o out "), "{err}");
    assert!(written(d).is_empty());
    // Without -o: spar and each mode's own extension.
    for (mode, file) in [
        ("stokes", "spar.exr"),
        ("color", "spar.png"),
        ("polcam-mosaic", "spar.png"),
    ] {
        clear(d);
        let (code, err) = render(d, &["--mode", mode]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(written(d), [file], "{mode}");
    }
}

#[test]
fn wavelength_is_used_by_stokes_and_refused_where_no_mode_uses_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    // color alone does not use it.
    let (code, err) = render(
        d,
        &["--mode", "color", "--wavelength", "600", "-o", "c.png"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--wavelength 600") && err.contains("color"),
        "{err}"
    );
    assert!(written(d).is_empty());

    // stokes traces that one wavelength: S0..S3 of 600 nm, the same values
    // as the 600 nm channels of a render of several wavelengths.
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "-q",
            "--mode",
            "stokes",
            "--wavelength",
            "600",
            "-o",
            "one.exr",
        ],
    );
    let one = spar::image::read(&d.join("one.exr")).unwrap();
    assert_eq!(
        one.channels(),
        ["S0.600nm", "S1.600nm", "S2.600nm", "S3.600nm"]
    );
    assert_eq!(one.metadata()["spar:wavelengths_nm"], "600");
    assert!(
        one.metadata()["spar:settings"].contains(" lambdas=[600.0] "),
        "{:?}",
        one.metadata()
    );
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "-q",
            "--mode",
            "stokes",
            "--wavelengths",
            "500,600,700",
            "-o",
            "three.exr",
        ],
    );
    let three = spar::image::read(&d.join("three.exr")).unwrap();
    assert_eq!(three.metadata()["spar:wavelengths_nm"], "500,600,700");
    for c in 0..4 {
        let a = one.channel(&format!("S{c}.600nm")).unwrap();
        let b = three.channel(&format!("S{c}.600nm")).unwrap();
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1.0), "S{c}: {x} vs {y}");
        }
    }
    let s0 = one.channel("S0.600nm").unwrap();
    let d65 = spar::spectrum::cie::d65(600.0) as f32;
    assert!(
        s0.iter().all(|&v| (v - 0.5 * d65).abs() < 1e-3 * d65),
        "{s0:?}"
    );

    // With color, color keeps the scene's wavelengths and stokes has 600.
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "-q",
            "--mode",
            "color,stokes",
            "--wavelength",
            "600",
            "-o",
            "both.png",
        ],
    );
    let both = spar::image::read(&d.join("both-stokes.exr")).unwrap();
    assert_eq!(
        both.channels(),
        ["S0.600nm", "S1.600nm", "S2.600nm", "S3.600nm"]
    );
    assert!(d.join("both-color.png").exists());

    // spar develop: --wavelength picks the Stokes EXR's wavelength from
    // a raw render; with color alone it is refused.
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "-q",
            "--mode",
            "color,dop",
            "--raw",
            "-o",
            "raw.exr",
        ],
    );
    spar_ok(
        d,
        &[
            "develop",
            "raw.exr",
            "-q",
            "--mode",
            "stokes",
            "--wavelength",
            "580",
            "-o",
            "dev.exr",
        ],
    );
    let dev = spar::image::read(&d.join("dev.exr")).unwrap();
    assert_eq!(dev.metadata()["spar:wavelengths_nm"], "580");
    assert_eq!(
        dev.channels(),
        ["S0.580nm", "S1.580nm", "S2.580nm", "S3.580nm"]
    );
    for (args, needle) in [
        (
            vec!["--mode", "color", "--wavelength", "580", "-o", "c.png"],
            "--wavelength 580",
        ),
        (vec!["--mode", "stokes", "-o", "d.png"], "use -o d.exr"),
        (vec!["--mode", "dop", "-o", "d.exr"], "use -o d.png"),
    ] {
        let (code, _, err) = code_out_err(&spar(
            d,
            &[&["develop", "raw.exr", "-q"][..], &args].concat(),
        ));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn plan_names_the_image_by_the_same_rules() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    let plan = |args: &[&str]| {
        code_out_err(&spar(
            d,
            &[&["plan", "s.toml", "--tiles", "2", "--slurm"][..], args].concat(),
        ))
    };
    // stokes alone develops image.exr, and --wavelength is passed on only
    // when given.
    let (code, script, err) = plan(&["--mode", "stokes"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        script.contains("image.exr") && !script.contains("--wavelength"),
        "{script}"
    );
    let (code, script, err) = plan(&["--mode", "color,dop", "--wavelength", "600"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        script.contains("image.png") && script.contains("--wavelength 600.0"),
        "{script}"
    );
    for (args, needle) in [
        (vec!["--mode", "stokes", "--image", "x.png"], "x.exr"),
        (
            vec!["--mode", "color", "--wavelength", "600"],
            "--wavelength 600",
        ),
    ] {
        let (code, _, err) = plan(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// compare, contact-sheet and speed-error use --wavelength or refuse it
/// (issue 16 item 5): with color alone it sets nothing and is refused
/// (exit 2, nothing written) instead of ignored; with a mode that uses it,
/// it is taken.
#[test]
fn commands_beside_render_use_or_refuse_wavelength() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    for (cmd, out) in [
        ("compare", "c.png"),
        ("contact-sheet", "k.png"),
        ("speed-error", "se"),
    ] {
        let args = [
            cmd,
            "s.toml",
            "--mode",
            "color",
            "--wavelength",
            "600",
            "-o",
            out,
        ];
        let (code, _, err) = code_out_err(&spar(d, &args));
        assert_eq!(code, 2, "{cmd}: {err}");
        if cmd == "compare" && !cfg!(feature = "native") {
            // The pure build has one backend: compare is refused first.
            assert!(err.contains("native"), "{cmd}: {err}");
        } else {
            assert!(
                err.contains("--wavelength 600") && err.contains("no mode asked for uses it"),
                "{cmd}: {err}"
            );
        }
        assert!(written(d).is_empty(), "{cmd}: {:?}", written(d));
    }
    // A mode that uses it takes it (compare renders with both backends;
    // the pure build has one and refuses compare first).
    if cfg!(feature = "native") {
        let (code, out, err) = code_out_err(&spar(
            d,
            &[
                "compare",
                "s.toml",
                "--mode",
                "mono",
                "--wavelength",
                "600",
                "-o",
                "m.png",
            ],
        ));
        assert_eq!(code, 0, "{out}{err}");
        assert!(out.contains("1 wavelength(s)"), "{out}");
    }
}
