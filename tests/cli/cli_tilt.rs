//! `spar tilt` and `spar render --tilt/--light-rig`: the frames are
//! numbered, frame k is bit for bit the render tilted by the k-th angle,
//! the middle frame is the untilted render, and bad flags exit with status
//! 2 leaving nothing behind (every frame is checked before the first is
//! written).

use crate::support::run::{code_out_err, spar, spar_ok};
use std::path::Path;

/// A calcite rod (2 × 2 × 8) seen from (0, −3, 2), lit by a uniform
/// background. Tilted by +45° its top end comes to the eye; by −45° it
/// turns away.
const SCENE: &str = "[camera]\neye = [0.0, -3.0, 2.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 60.0\n\
    resolution = [8, 8]\n[render]\nwavelengths = 5\nmax_depth = 8\n\
    [[object]]\nmesh = \"rod.obj\"\nmedium = \"calcite\"\noptic_axis = [0.0, 0.6, 0.8]\n\
    [background]\nradiance = 1.0\n";

fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut obj = String::new();
    for i in 0..8 {
        let x = if i & 1 == 0 { -1.0 } else { 1.0 };
        let y = if i & 2 == 0 { -1.0 } else { 1.0 };
        let z = if i & 4 == 0 { -4.0 } else { 4.0 };
        obj += &format!("v {x} {y} {z}\n");
    }
    obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(dir.path().join("rod.obj"), obj).unwrap();
    std::fs::write(dir.path().join("s.toml"), SCENE).unwrap();
    std::fs::write(dir.path().join("file"), "not a directory").unwrap();
    dir
}

/// The files in `dir` besides the scene, its mesh and `file`.
fn written(dir: &Path) -> Vec<String> {
    let mut found: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !["s.toml", "rod.obj", "file"].contains(&n.as_str()))
        .collect();
    found.sort();
    found
}

/// A PNG's pixel values.
fn pixels(path: &Path) -> Vec<f32> {
    let image = spar::image::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    image.rgba().unwrap().iter().flatten().copied().collect()
}

#[test]
fn frames_are_the_renders_tilted_by_each_angle_bit_for_bit() {
    let dir = workdir();
    let d = dir.path();
    spar_ok(
        d,
        &[
            "tilt", "s.toml", "--frames", "5", "--angle", "30", "-q", "-o", "t.png",
        ],
    );
    assert_eq!(
        written(d),
        [
            "t-000.png",
            "t-001.png",
            "t-002.png",
            "t-003.png",
            "t-004.png"
        ]
    );
    let frames: Vec<Vec<f32>> = (0..5)
        .map(|k| pixels(&d.join(format!("t-{k:03}.png"))))
        .collect();
    for (k, angle) in ["-30", "-15", "0", "15", "30"].iter().enumerate() {
        let out = format!("r{k}.png");
        spar_ok(d, &["render", "s.toml", "--tilt", angle, "-q", "-o", &out]);
        assert!(frames[k] == pixels(&d.join(&out)), "frame {k} ({angle}°)");
    }
    // The middle frame is the scene as it is; the others are not.
    spar_ok(d, &["render", "s.toml", "-q", "-o", "plain.png"]);
    let plain = pixels(&d.join("plain.png"));
    assert!(frames[2] == plain);
    for k in [0, 1, 3, 4] {
        assert!(frames[k] != plain, "frame {k} equals the untilted render");
    }
    // A rig flag reaches every frame: the first frame under the dome is
    // the render tilted by −30° under the dome.
    spar_ok(
        d,
        &[
            "tilt",
            "s.toml",
            "--frames",
            "2",
            "--angle",
            "30",
            "--light-rig",
            "dome",
            "-q",
            "-o",
            "dome.png",
        ],
    );
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "--tilt",
            "-30",
            "--light-rig",
            "dome",
            "-q",
            "-o",
            "dr.png",
        ],
    );
    let dome = pixels(&d.join("dome-000.png"));
    assert!(dome == pixels(&d.join("dr.png")));
    assert!(dome != frames[0], "the dome changes the lighting");
}

#[test]
fn bad_flags_exit_2_and_write_nothing() {
    let dir = workdir();
    let d = dir.path();
    let refused = |args: &[&str], says: &str| {
        let mut all = vec!["tilt", "s.toml"];
        all.extend(args);
        let (code, _, err) = code_out_err(&spar(d, &all));
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(says), "{all:?}: {err}");
        assert!(!err.contains("panicked"), "{all:?}: {err}");
        assert_eq!(written(d), Vec::<String>::new(), "{all:?}");
    };
    let o = ["-o", "t.png"];
    let with = |a: &[&'static str]| -> Vec<&'static str> { a.iter().chain(&o).copied().collect() };
    refused(&with(&["--frames", "1", "--angle", "10"]), "--frames 1");
    refused(&with(&["--frames", "0", "--angle", "10"]), "--frames 0");
    refused(&with(&["--frames", "3", "--angle", "0"]), "--angle 0");
    refused(&with(&["--frames", "3", "--angle", "91"]), "--angle 91");
    refused(&with(&["--frames", "3", "--angle", "-5"]), "--angle -5");
    refused(&with(&["--frames", "3", "--angle", "NaN"]), "--angle NaN");
    refused(&with(&["--frames", "3"]), "--angle");
    refused(
        &with(&["--frames", "3", "--angle", "10", "--tilt", "5"]),
        "--tilt 5",
    );
    refused(
        &with(&["--frames", "3", "--angle", "10", "--light-rig", "studio"]),
        "unknown light rig `studio`: the light rigs are ring, dome, spot",
    );
    refused(
        &with(&["--frames", "3", "--angle", "10", "--light-rig", "dome:190"]),
        "from 0 to 180",
    );
    refused(
        &with(&["--frames", "3", "--angle", "10", "--max-depth", "5000"]),
        "--max-depth",
    );
    refused(
        &["--frames", "3", "--angle", "10", "-o", "file/t.png"],
        "file/t-000.png",
    );
    // The last frame (+45°) brings the rod to the eye: refused before the
    // first frame, which alone would render, is written.
    refused(
        &with(&["--frames", "3", "--angle", "45"]),
        "reaches where the camera's rays start",
    );
    // spar render's flags, the same checks.
    for (args, says) in [
        (vec!["--tilt", "100"], "--tilt 100"),
        (
            vec!["--tilt", "45"],
            "reaches where the camera's rays start",
        ),
        (vec!["--light-rig", "ring:2"], "takes no parameter"),
    ] {
        let mut all = vec!["render", "s.toml", "-o", "r.png"];
        all.extend(args);
        let (code, _, err) = code_out_err(&spar(d, &all));
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(says), "{all:?}: {err}");
        assert_eq!(written(d), Vec::<String>::new(), "{all:?}");
    }
}
