//! `spar merge` refuses what would not give the one-machine render: parts
//! that overlap, leave pixels or samples out, belong to other renders, are
//! stored as half float or with lossy compression, are no parts at all —
//! each with its named error, exit status 2 and no output file. And
//! `spar develop` refuses a part.
#![cfg(feature = "native")]

use crate::support::farm as farm_common;

use crate::support::run::{spar, spar_ok};
use farm_common::write_scene;
use spar::image::{PixelType, WriteOptions};
use std::path::Path;

fn parts(dir: &Path) {
    write_scene(dir, 16, 12, 2);
    for (args, out) in [
        (vec!["--tile", "0/2"], "t0.exr"),
        (vec!["--tile", "1/2"], "t1.exr"),
        (vec!["--tile", "1/2", "--seed", "5"], "t1-seed5.exr"),
        (vec!["--tile", "0/2", "--samples", "0..1"], "t0-s0.exr"),
        (vec!["--tile", "0/2", "--samples", "1..2"], "t0-s1.exr"),
        (vec!["--region", "0,4,0,4"], "corner.exr"),
    ] {
        let mut a = vec!["render", "scene.toml", "-q", "-o", out];
        a.extend(args);
        spar_ok(dir, &a);
    }
}

/// Runs `spar merge PARTS -o merged.exr`, expects exit 2, a message that
/// starts with `name:` and mentions `also`, and no merged file.
fn refused(dir: &Path, parts: &[&str], name: &str, also: &[&str]) {
    let mut args = vec!["merge", "-o", "merged.exr"];
    args.extend(parts);
    let out = spar(dir, &args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{parts:?}: {err}");
    assert!(
        err.contains(&format!("spar: error: {name}: ")),
        "{parts:?}: expected a `{name}` error, got {err}"
    );
    for a in also {
        assert!(err.contains(a), "{parts:?}: `{a}` not in {err}");
    }
    assert!(!dir.join("merged.exr").exists(), "{parts:?} left a file");
}

#[test]
fn merge_names_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    parts(d);

    // The good cases first, in any order, tiles or blocks.
    spar_ok(d, &["merge", "t1.exr", "t0.exr", "-o", "a.exr", "-q"]);
    spar_ok(
        d,
        &[
            "merge",
            "t0-s1.exr",
            "t1.exr",
            "t0-s0.exr",
            "-o",
            "b.exr",
            "-q",
        ],
    );
    assert_eq!(
        farm_common::pixel_bits(&d.join("a.exr")),
        farm_common::pixel_bits(&d.join("b.exr"))
    );
    std::fs::remove_file(d.join("a.exr")).unwrap();
    std::fs::remove_file(d.join("b.exr")).unwrap();

    refused(
        d,
        &["t0.exr", "t1.exr", "corner.exr"],
        "overlap",
        &["corner.exr", "samples 0..2"],
    );
    refused(
        d,
        &["t0.exr", "t0-s1.exr", "t1.exr"],
        "overlap",
        &["t0-s1.exr", "samples 1..2"],
    );
    refused(d, &["t0.exr", "t0.exr", "t1.exr"], "overlap", &["t0.exr"]);
    refused(d, &["t0.exr"], "missing", &["samples 0..2", "8,16,0,12"]);
    refused(d, &["t0-s0.exr", "t1.exr"], "missing", &["samples 1..2"]);
    refused(
        d,
        &["t0.exr", "t1-seed5.exr"],
        "mismatch",
        &["spar:settings", "seed=5"],
    );

    // Half float: the same part, stored as half.
    let t1 = spar::image::read(&d.join("t1.exr")).unwrap();
    spar::image::write(&d.join("half.exr"), &t1, WriteOptions::new(PixelType::Half)).unwrap();
    refused(d, &["t0.exr", "half.exr"], "half-float", &["half.exr"]);

    // Lossy compression: the same part, recompressed by OpenImageIO.
    for method in ["dwaa", "pxr24", "b44"] {
        let lossy = format!("{method}.exr");
        let out = std::process::Command::new("oiiotool")
            .args(["t1.exr", "--compression", method, "-o", &lossy])
            .current_dir(d)
            .output()
            .expect("oiiotool (openimageio-tools) is needed for this test");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        refused(d, &["t0.exr", &lossy], "lossy", &[&lossy, method]);
    }
    // And it matters: PXR24 keeps 24 of float32's 32 bits.
    assert_ne!(
        farm_common::pixel_bits(&d.join("pxr24.exr")),
        farm_common::pixel_bits(&d.join("t1.exr"))
    );

    // Not parts: a display image, a Stokes EXR without spar's raw metadata.
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--mode",
            "color,stokes",
            "-o",
            "img.png",
        ],
    );
    refused(
        d,
        &["t0.exr", "img-color.png"],
        "unreadable",
        &["img-color.png"],
    );
    refused(
        d,
        &["t0.exr", "img-stokes.exr"],
        "not-a-part",
        &["spar:format"],
    );

    // develop wants the whole render.
    let out = spar(d, &["develop", "t0.exr", "-o", "dev.png"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("incomplete: "), "{err}");
    assert!(!d.join("dev.png").exists());
}

/// Copies the repository's scene directory (scene files, meshes, textures)
/// to `to`.
fn copy_scenes(to: &Path) {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut stack = vec![from.clone()];
    while let Some(dir) = stack.pop() {
        let rel = dir.strip_prefix(&from).unwrap();
        std::fs::create_dir_all(to.join(rel)).unwrap();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                std::fs::copy(&path, to.join(rel).join(path.file_name().unwrap())).unwrap();
            }
        }
    }
}

#[test]
fn a_scene_at_another_mount_point_is_the_same_render_an_edited_one_is_not() {
    // Farm machines mount the scene (with its mesh and texture files) at
    // different paths: parts still belong to one render. The same file
    // with one number changed is another render.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_scenes(&d.join("a/scenes"));
    copy_scenes(&d.join("elsewhere/b/scenes"));
    let scene = "scenes/glass-unpolarized.toml";
    let small = ["--resolution", "24x16", "--samples", "2", "-q"];
    let render = |cwd: &Path, scene: &str, extra: &[&str], out: &str| {
        let mut a = vec!["render", scene];
        a.extend(small);
        a.extend(extra);
        a.extend(["-o", out]);
        spar_ok(cwd, &a);
    };
    render(d, &format!("a/{scene}"), &["--raw"], "whole.exr");
    render(&d.join("a"), scene, &["--tile", "0/2"], "../t0.exr");
    render(
        d,
        &d.join("elsewhere/b").join(scene).to_string_lossy(),
        &["--tile", "1/2"],
        "t1.exr",
    );
    let labels: Vec<String> = ["t0.exr", "t1.exr"]
        .iter()
        .map(|p| spar::image::read(&d.join(p)).unwrap().metadata()["spar:scene"].clone())
        .collect();
    assert_ne!(
        labels[0], labels[1],
        "the test should name the scene two ways"
    );
    spar_ok(d, &["merge", "t0.exr", "t1.exr", "-o", "merged.exr", "-q"]);
    assert_eq!(
        farm_common::pixel_bits(&d.join("whole.exr")),
        farm_common::pixel_bits(&d.join("merged.exr"))
    );
    std::fs::remove_file(d.join("merged.exr")).unwrap();

    // The gem turned by 16° instead of 15°, at the same path.
    let b = d.join("elsewhere/b").join(scene);
    let text = std::fs::read_to_string(&b).unwrap();
    let edited = text.replace("rotate = [0.0, 0.0, 15.0]", "rotate = [0.0, 0.0, 16.0]");
    assert_ne!(
        text, edited,
        "the scene no longer has the rotation this test edits"
    );
    std::fs::write(&b, edited).unwrap();
    render(d, &b.to_string_lossy(), &["--tile", "1/2"], "t1-edited.exr");
    refused(
        d,
        &["t0.exr", "t1-edited.exr"],
        "mismatch",
        &["spar:scene_hash", "t1-edited.exr"],
    );
}
