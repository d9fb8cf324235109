//! Command-line details: `spar cut` refuses an output it cannot or should
//! not write (exit status 2, the path named, nothing written); `--region`'s
//! help shows the form its parser takes; negative numbers reach each
//! flag's own check instead of clap's "use '-- -1'" hint; `--coherence`
//! overrides the scene's, is named in the render's settings and is passed
//! on by `spar plan`.

use crate::support::run;
use std::path::Path;

const SCENE: &str = r#"
[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [8, 8]

[render]
wavelengths = 8

[[object]]
mesh = "builtin:trichecker12"
medium = "n-bk7"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

fn spar(dir: &Path, args: &[&str]) -> (i32, String, String) {
    run::code_out_err(&run::spar(dir, args))
}

/// Exit 2 with each of `says` in the message, never clap's hint.
fn refused(dir: &Path, args: &[&str], says: &[&str]) {
    let (code, _, err) = spar(dir, args);
    assert_eq!(code, 2, "{args:?}: {err}");
    for s in says {
        assert!(err.contains(s), "{args:?}: `{s}` not in {err}");
    }
    assert!(!err.contains("'-- "), "{args:?}: clap's hint: {err}");
}

#[test]
fn cut_refuses_outputs_it_cannot_or_should_not_write() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused(
        d,
        &["cut", "round-brilliant", "-o", "x.png"],
        &["x.png", "name the output .obj"],
    );
    assert!(!d.join("x.png").exists(), "OBJ text written into x.png");
    refused(
        d,
        &["cut", "round-brilliant", "-o", "x"],
        &["x: spar cut writes OBJ text"],
    );
    refused(
        d,
        &["cut", "round-brilliant", "-o", "missing/x.obj"],
        &["missing/x.obj", "does not exist"],
    );
    std::fs::create_dir(d.join("dir.obj")).unwrap();
    refused(
        d,
        &["cut", "round-brilliant", "-o", "dir.obj"],
        &["dir.obj", "is a directory"],
    );
    // A directory that exists but takes no files (even for root): the
    // write itself fails, and that is the user's output too.
    #[cfg(target_os = "linux")]
    refused(
        d,
        &["cut", "round-brilliant", "-o", "/proc/spar-cut.obj"],
        &["/proc/spar-cut.obj: cannot write"],
    );
    let (code, _, err) = spar(d, &["cut", "round-brilliant", "-o", "ok.OBJ"]);
    assert_eq!(code, 0, "{err}");
    assert!(d.join("ok.OBJ").exists());
}

#[test]
fn region_help_shows_the_form_the_parser_takes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (code, help, _) = spar(d, &["render", "--help"]);
    assert_eq!(code, 0);
    assert!(help.contains("--region <X0,X1,Y0,Y1>"), "{help}");
    // The help's example, run as written.
    let example = help
        .split("`--region ")
        .nth(1)
        .and_then(|r| r.split('`').next())
        .expect("an example in the help")
        .to_string();
    assert_eq!(example, "0,64,0,32");
    std::fs::write(d.join("scene.toml"), SCENE.replace("[8, 8]", "[64, 40]")).unwrap();
    let (code, _, err) = spar(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--samples",
            "1",
            "--region",
            &example,
            "-o",
            "p.exr",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let part = spar::image::read(&d.join("p.exr")).unwrap();
    assert_eq!((part.width(), part.height()), (64, 32));
    assert_eq!(part.metadata()["spar:region"], "0,64,0,32");
    // The dotted form the help once showed is refused with the form.
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--region",
            "0..64, 0..32",
            "-o",
            "q.exr",
        ],
        &["is not x0,x1,y0,y1"],
    );
}

#[test]
fn negative_numbers_reach_the_flags_own_checks() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let render = |flag: &'static str, value: &'static str| {
        vec![
            "render",
            "scene.toml",
            "-q",
            "--samples",
            "1",
            flag,
            value,
            "-o",
            "o.png",
        ]
    };
    refused(
        d,
        &render("--prune", "-1"),
        &["--prune must be a number ≥ 0"],
    );
    refused(
        d,
        &render("--wavelength", "-5"),
        &["--wavelength -5 is outside"],
    );
    refused(
        d,
        &render("--seed", "-1"),
        &["'--seed <SEED>'", "invalid digit"],
    );
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--region",
            "-1,4,0,4",
            "-o",
            "p.exr",
        ],
        &["`-1,4,0,4` is not x0,x1,y0,y1"],
    );
    refused(
        d,
        &[
            "cut",
            "round-brilliant",
            "--crown-angle",
            "-5",
            "-o",
            "c.obj",
        ],
        &["--crown-angle = -5 is outside"],
    );
    assert!(!d.join("o.png").exists() && !d.join("c.obj").exists());
    // Vectors with negative components are values, not flags.
    let (code, out, err) = spar(
        d,
        &[
            "interface",
            "--from",
            "air",
            "--to",
            "calcite",
            "--mode",
            "s",
            "--incident",
            "-0.3,0,-1",
            "--axis",
            "-1,0,0",
            "--normal",
            "0,0,1",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("axis = (-1.0000, 0.0000, 0.0000)"), "{out}");
    refused(
        d,
        &[
            "interface",
            "--from",
            "air",
            "--to",
            "n-bk7",
            "--mode",
            "s",
            "--incident",
            "0,0,-1",
            "--wavelength",
            "-500",
        ],
        &["-500"],
    );
}

/// `spar:settings` of an image spar wrote.
fn settings(path: &Path) -> String {
    spar::image::read(path).unwrap().metadata()["spar:settings"].clone()
}

#[test]
fn coherence_flag_overrides_the_scene_and_is_part_of_the_identity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let incoherent = SCENE.replace(
        "wavelengths = 8",
        "wavelengths = 8\ncoherence = \"incoherent\"",
    );
    std::fs::write(d.join("incoherent.toml"), incoherent).unwrap();
    let render = |scene: &str, flags: &[&str], out: &str| {
        let mut args = vec!["render", scene, "-q", "-o", out];
        args.extend_from_slice(flags);
        let (code, o, e) = spar(d, &args);
        assert_eq!(code, 0, "{args:?}: {o}{e}");
        settings(&d.join(out))
    };
    let s = render("scene.toml", &[], "a.png");
    assert!(s.ends_with(" coherence=physical"), "{s}");
    let s = render("scene.toml", &["--coherence", "incoherent"], "b.png");
    assert!(s.ends_with(" coherence=incoherent"), "{s}");
    let s = render("incoherent.toml", &[], "c.png");
    assert!(s.ends_with(" coherence=incoherent"), "{s}");
    let s = render("incoherent.toml", &["--coherence", "physical"], "d.png");
    assert!(s.ends_with(" coherence=physical"), "{s}");
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "--coherence",
            "partial",
            "-o",
            "e.png",
        ],
        &["--coherence", "partial", "incoherent"],
    );
    assert!(!d.join("e.png").exists());
    // A job script passes the flag on to every tile's render.
    let (code, script, err) = spar(
        d,
        &[
            "plan",
            "scene.toml",
            "--tiles",
            "2",
            "--slurm",
            "--coherence",
            "incoherent",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(script.contains("--coherence incoherent"), "{script}");
}

#[test]
fn bundle_flag_needs_the_incoherent_model_and_is_part_of_the_identity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let bundled = SCENE.replace(
        "wavelengths = 8",
        "wavelengths = 8\ncoherence = \"incoherent\"\nbundle = 0.5",
    );
    std::fs::write(d.join("bundled.toml"), bundled).unwrap();
    // With the physical model the o/e interference would be lost: refused,
    // naming where the tolerance came from.
    refused(
        d,
        &["render", "scene.toml", "--bundle", "1", "-o", "a.png"],
        &["--bundle", "coherence = \"incoherent\""],
    );
    refused(
        d,
        &[
            "render",
            "bundled.toml",
            "--coherence",
            "physical",
            "-o",
            "a.png",
        ],
        &["--coherence", "physical", "bundle = 0.5", "incoherent"],
    );
    for bad in ["-1", "nan", "inf"] {
        refused(
            d,
            &[
                "render",
                "scene.toml",
                "--coherence",
                "incoherent",
                "--bundle",
                bad,
                "-o",
                "a.png",
            ],
            &["--bundle", "pixel footprints"],
        );
    }
    assert!(!d.join("a.png").exists());
    let (code, o, e) = spar(d, &["render", "bundled.toml", "-q", "-o", "b.png"]);
    assert_eq!(code, 0, "{o}{e}");
    let s = settings(&d.join("b.png"));
    assert!(s.ends_with(" coherence=incoherent bundle=0.5"), "{s}");
    // Off (0) leaves the identity as before bundles existed.
    let (code, o, e) = spar(
        d,
        &[
            "render",
            "bundled.toml",
            "--bundle",
            "0",
            "-q",
            "-o",
            "c.png",
        ],
    );
    assert_eq!(code, 0, "{o}{e}");
    let s = settings(&d.join("c.png"));
    assert!(s.ends_with(" coherence=incoherent"), "{s}");
}

#[test]
fn roulette_is_checked_and_joins_the_identity_only_when_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    for bad in ["-0.1", "1", "nan", "inf"] {
        refused(
            d,
            &["render", "scene.toml", "--roulette", bad, "-o", "a.png"],
            &["--roulette", "fraction of the brightest light"],
        );
    }
    std::fs::write(
        d.join("bad.toml"),
        SCENE.replace("wavelengths = 8", "wavelengths = 8\nroulette = 2.0"),
    )
    .unwrap();
    refused(
        d,
        &["render", "bad.toml", "-o", "a.png"],
        &[
            "bad.toml:",
            "render.roulette",
            "fraction of the brightest light",
        ],
    );
    assert!(!d.join("a.png").exists());
    std::fs::write(
        d.join("rouletted.toml"),
        SCENE.replace("wavelengths = 8", "wavelengths = 8\nroulette = 0.01"),
    )
    .unwrap();
    let (code, o, e) = spar(d, &["render", "rouletted.toml", "-q", "-o", "b.png"]);
    assert_eq!(code, 0, "{o}{e}");
    let s = settings(&d.join("b.png"));
    assert!(s.ends_with(" coherence=physical roulette=0.01"), "{s}");
    // The flag beats the scene; off (0) leaves the identity as before
    // roulette existed.
    let (code, o, e) = spar(
        d,
        &[
            "render",
            "rouletted.toml",
            "--roulette",
            "0",
            "-q",
            "-o",
            "c.png",
        ],
    );
    assert_eq!(code, 0, "{o}{e}");
    let s = settings(&d.join("c.png"));
    assert!(s.ends_with(" coherence=physical"), "{s}");
}

/// `flag` refuses -1, NaN and infinity, and the scene key `render.KEY`
/// a negative value, named by its file and line; each message says `what`.
fn refuses_bad_values(d: &Path, flag: &str, key: &str, what: &str) {
    for bad in ["-1", "nan", "inf"] {
        refused(
            d,
            &["render", "scene.toml", flag, bad, "-o", "a.png"],
            &[flag, what],
        );
    }
    let bad = SCENE.replace("wavelengths = 8", &format!("wavelengths = 8\n{key} = -0.5"));
    std::fs::write(d.join("bad.toml"), bad).unwrap();
    let field = format!("render.{key}");
    refused(
        d,
        &["render", "bad.toml", "-o", "a.png"],
        &["bad.toml:", &field, what],
    );
}

/// `--KEY 0.02 --min-samples 4` renders, the summary line reports the
/// samples per pixel taken, and the image's identity ends with the two.
fn renders_and_joins_the_identity(d: &Path, key: &str) {
    let flag = format!("--{key}");
    let args = [
        "render",
        "scene.toml",
        "--samples",
        "8",
        &flag,
        "0.02",
        "--min-samples",
        "4",
    ];
    let (code, o, e) = spar(d, &[&args[..], &["-o", "b.png"]].concat());
    assert_eq!(code, 0, "{o}{e}");
    assert!(e.contains(&format!("({key} 0.02: ")), "{e}");
    let s = settings(&d.join("b.png"));
    assert!(s.ends_with(&format!(" {key}=0.02 min_samples=4")), "{s}");
}

/// A sample block cannot be rendered with `flag` on (a pixel decides from
/// all its samples); the message names `what`, and no image is written.
fn refuses_a_sample_block(d: &Path, flag: &str, what: &str) {
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "--samples",
            "0..4/8",
            flag,
            "0.01",
            "-o",
            "a.exr",
            "--mode",
            "stokes",
        ],
        &["--samples 0..4", what, "by region or tiles"],
    );
    assert!(!d.join("a.exr").exists());
}

#[test]
fn adaptive_flags_are_checked_refuse_sample_blocks_and_join_the_identity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let (flag, key) = ("--adaptive", "adaptive");
    refuses_bad_values(d, flag, key, "display units");
    refused(
        d,
        &["render", "scene.toml", "--min-samples", "1", "-o", "a.png"],
        &["--min-samples", "at least 2"],
    );
    // A pixel decides from all its samples: a block cannot be rendered.
    refuses_a_sample_block(d, flag, "adaptive");
    assert!(!d.join("a.png").exists() && !d.join("a.exr").exists());
    renders_and_joins_the_identity(d, "adaptive");
    // Off leaves the identity as before adaptive sampling existed.
    let (code, o, e) = spar(d, &["render", "scene.toml", "-q", "-o", "c.png"]);
    assert_eq!(code, 0, "{o}{e}");
    assert!(!settings(&d.join("c.png")).contains("adaptive"));
}

#[test]
fn edges_flags_are_checked_refuse_sample_blocks_and_colour_on_some_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    refuses_bad_values(d, "--edges", "edges", "contrast in display units");
    // A pixel decides from its neighbours' first samples: a block cannot.
    refuses_a_sample_block(d, "--edges", "edge-adaptive");
    // With every sample among the first ones, nothing can stop early.
    let eight = ["render", "scene.toml", "--samples", "8", "--edges", "0.02"];
    let (code, o, e) = spar(d, &[&eight[..], &["-o", "i.png"]].concat());
    assert_eq!(code, 0, "{o}{e}");
    assert!(
        e.contains("changes nothing") && e.contains("first 32 samples, and there are 8"),
        "{e}"
    );
    // Colour on the first half of the samples needs every pixel's count.
    refused(
        d,
        &[
            &eight[..],
            &["--spectral", "hero:2/2", "-m", "color,dop", "-o", "a.png"],
        ]
        .concat(),
        &[
            "--spectral",
            "hero:2/2",
            "edge-adaptive sampling (edges = 0.02)",
        ],
    );
    assert!(!d.join("a.png").exists() && !d.join("a.exr").exists());
    renders_and_joins_the_identity(d, "edges");
    // Edge refinement: with edges, and at least the samples.
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "--samples",
            "8",
            "--max-samples",
            "32",
        ],
        &["--max-samples 32 needs edge-adaptive sampling"],
    );
    refused(
        d,
        &[&eight[..], &["--max-samples", "4", "-o", "m.png"]].concat(),
        &["--max-samples 4 is below the 8 samples per pixel"],
    );
    assert!(!d.join("m.png").exists());
    let refine = [&eight[..], &["--min-samples", "2", "--max-samples", "32"]].concat();
    let (code, o, e) = spar(d, &[&refine[..], &["-o", "r.png"]].concat());
    assert_eq!(code, 0, "{o}{e}");
    assert!(e.contains("(edges 0.02, up to 32: "), "{e}");
    let s = settings(&d.join("r.png"));
    assert!(
        s.ends_with(" edges=0.02 min_samples=2 max_samples=32"),
        "{s}"
    );
}
