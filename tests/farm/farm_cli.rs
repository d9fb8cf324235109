//! The render-farm command line end to end: parts merged and developed give
//! the images of a one-machine `spar render`; progress lines in the plain
//! and OpenJD formats; SIGTERM writes a checkpoint that `--resume`
//! continues to the same pixels, SIGUSR1 one that the render outlives;
//! `--isa`; `spar plan`'s scripts; bad farm flags exit 2.
#![cfg(feature = "native")]

use crate::support::farm::{pixel_bits, write_scene};
use crate::support::run::{spar, spar_ok};
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn merged_parts_develop_into_the_one_machine_images() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 24, 16, 3);
    let modes = "color,dop,azimuth,stokes";
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--mode",
            modes,
            "-o",
            "direct.png",
        ],
    );
    // One machine, raw, then developed.
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--mode",
            modes,
            "--raw",
            "-o",
            "raw.exr",
        ],
    );
    spar_ok(
        d,
        &["develop", "raw.exr", "-q", "--mode", modes, "-o", "dev.png"],
    );
    // Three tiles, the middle one in two sample blocks, merged, developed.
    for (i, (tile, block)) in [("0/3", ""), ("1/3", "0..2"), ("1/3", "2..3"), ("2/3", "")]
        .into_iter()
        .enumerate()
    {
        let out = format!("p{i}.exr");
        let mut args = vec![
            "render",
            "scene.toml",
            "-q",
            "--mode",
            modes,
            "--tile",
            tile,
        ];
        if !block.is_empty() {
            args.extend(["--samples", block]);
        }
        args.extend(["-o", &out]);
        spar_ok(d, &args);
    }
    spar_ok(
        d,
        &[
            "merge",
            "p3.exr",
            "p1.exr",
            "p0.exr",
            "p2.exr",
            "-q",
            "-o",
            "merged.exr",
        ],
    );
    assert_eq!(
        pixel_bits(&d.join("raw.exr")),
        pixel_bits(&d.join("merged.exr"))
    );
    spar_ok(
        d,
        &[
            "develop",
            "merged.exr",
            "-q",
            "--mode",
            modes,
            "-o",
            "farm.png",
        ],
    );
    for m in ["color.png", "dop.png", "azimuth.png", "stokes.exr"] {
        let direct = pixel_bits(&d.join(format!("direct-{m}")));
        assert!(!direct.is_empty());
        assert_eq!(direct, pixel_bits(&d.join(format!("dev-{m}"))), "{m}");
        assert_eq!(direct, pixel_bits(&d.join(format!("farm-{m}"))), "{m}");
        let a = spar::image::read(&d.join(format!("direct-{m}"))).unwrap();
        let b = spar::image::read(&d.join(format!("farm-{m}"))).unwrap();
        for key in [
            "spar:settings",
            "spar:scene_hash",
            "spar:mode",
            "spar:version",
        ] {
            assert_eq!(a.metadata().get(key), b.metadata().get(key), "{m} {key}");
        }
    }
    // The raw file says what it is.
    let raw = spar::image::read(&d.join("p1.exr")).unwrap();
    let meta = raw.metadata();
    assert_eq!(meta["spar:samples"], "0..2/3");
    assert_eq!(meta["spar:format"], "spar-raw-1");
    assert!(meta["spar:settings"].contains("seed=0"));
    assert!(meta["spar:settings"].contains("isa=auto"));
    assert!(meta.contains_key("spar:region"));
    assert!(meta.contains_key("spar:scene_hash"));
}

#[test]
fn progress_lines_plain_and_openjd() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 40, 20, 1);
    let out = spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "--raw",
            "-o",
            "a.exr",
            "--progress",
            "plain",
        ],
    );
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.iter().all(|l| l.starts_with("spar: ")), "{text}");
    assert!(
        lines[0]
            .starts_with("spar: start render scene.toml region 0,40,0,20 samples 0..1/1 (6 tiles"),
        "{text}"
    );
    let progress: Vec<&str> = lines
        .iter()
        .filter(|l| l.starts_with("spar: progress "))
        .copied()
        .collect();
    // One line per tile (6 tiles: each passes a whole percentage), counts
    // going up; workers' reports can cross, so the first lines may be
    // fewer (src/farm/progress.rs), but the last one is 100%.
    let counts: Vec<usize> = progress
        .iter()
        .map(|l| {
            let n = l.split(' ').nth(2).and_then(|c| c.split_once('/'));
            assert_eq!(n.map(|n| n.1), Some("6"), "{l}");
            n.unwrap().0.parse().unwrap()
        })
        .collect();
    assert!(counts.windows(2).all(|w| w[0] < w[1]), "{text}");
    assert!((1..=6).contains(&progress.len()), "{text}");
    assert!(
        progress[progress.len() - 1].starts_with("spar: progress 6/6 tiles 100.0% "),
        "{text}"
    );
    assert_eq!(lines[lines.len() - 2], "spar: wrote a.exr");
    assert!(lines[lines.len() - 1].starts_with("spar: done "), "{text}");

    let out = spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "--raw",
            "-o",
            "b.exr",
            "--progress",
            "openjd",
        ],
    );
    let text = stdout(&out);
    let mut last = -1.0;
    let mut n = 0;
    for l in text.lines() {
        if let Some(v) = l.strip_prefix("openjd_progress: ") {
            let v: f64 = v.parse().unwrap_or_else(|_| panic!("{l}"));
            assert!(v > last && v <= 100.0, "{text}");
            last = v;
            n += 1;
        } else {
            assert!(l.starts_with("openjd_status: "), "{l}");
        }
    }
    assert!((1..=6).contains(&n) && last == 100.0, "{text}");
    // Quiet means quiet.
    let out = spar_ok(d, &["render", "scene.toml", "--raw", "-o", "c.exr", "-q"]);
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
}

/// Starts a render that takes a while (one thread, 36 tiles), waits for
/// its first progress line, sends `signal`, and returns its output.
fn signalled_render(d: &Path, signal: &str, extra: &[&str]) -> (i32, String, String) {
    let mut args = vec![
        "render",
        "scene.toml",
        "--raw",
        "-o",
        "big.exr",
        "--threads",
        "1",
        "--progress",
        "plain",
    ];
    args.extend(extra);
    let mut child = Command::new(env!("CARGO_BIN_EXE_spar"))
        .args(&args)
        .current_dir(d)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut text = String::new();
    loop {
        let mut line = String::new();
        assert!(
            out.read_line(&mut line).unwrap() > 0,
            "no progress line: {text}"
        );
        text += &line;
        if line.starts_with("spar: progress ") {
            break;
        }
    }
    let kill = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).unwrap();
    text += &rest;
    let status = child.wait().unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    (status.code().unwrap_or(-1), text, err)
}

#[test]
fn sigterm_checkpoints_and_resume_finishes_the_same_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 96, 96, 2);
    spar_ok(
        d,
        &["render", "scene.toml", "-q", "--raw", "-o", "whole.exr"],
    );

    let (code, out, err) = signalled_render(d, "-TERM", &[]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(err.contains("stopped by SIGTERM"), "{err}");
    assert!(err.contains("--resume"), "{err}");
    assert!(
        out.contains("spar: checkpoint big.exr.checkpoint "),
        "{out}"
    );
    assert!(
        !d.join("big.exr").exists(),
        "a stopped render wrote its output"
    );
    assert!(d.join("big.exr.checkpoint").exists());

    // A checkpoint of another render is refused, not used.
    let out = spar(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--raw",
            "-o",
            "big.exr",
            "--resume",
            "--seed",
            "9",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("belongs to another render"),
        "{}",
        stderr(&out)
    );

    let out = spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "--raw",
            "-o",
            "big.exr",
            "--resume",
            "--progress",
            "plain",
        ],
    );
    let text = stdout(&out);
    let resumed: usize = text
        .lines()
        .find_map(|l| l.strip_prefix("spar: resume big.exr.checkpoint ("))
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no resume line: {text}"));
    assert!((1..36).contains(&resumed), "{resumed} tiles resumed");
    assert!(
        !d.join("big.exr.checkpoint").exists(),
        "the checkpoint outlived the render"
    );
    assert_eq!(
        pixel_bits(&d.join("whole.exr")),
        pixel_bits(&d.join("big.exr"))
    );
}

#[test]
fn sigusr1_checkpoints_and_the_render_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 96, 96, 2);
    let (code, out, err) = signalled_render(d, "-USR1", &[]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("spar: checkpoint big.exr.checkpoint "),
        "{out}"
    );
    assert!(out.contains("spar: wrote big.exr"), "{out}");
    assert!(!d.join("big.exr.checkpoint").exists());
}

#[test]
fn isa_is_checked_pinned_and_part_of_the_identity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 16, 8, 1);
    let out = spar(
        d,
        &[
            "render",
            "scene.toml",
            "--raw",
            "-o",
            "x.exr",
            "--isa",
            "avx512skx",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("sse2, sse4.2, avx, avx2, avx512"),
        "{}",
        stderr(&out)
    );
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--tile",
            "0/2",
            "--isa",
            "sse2",
            "-o",
            "a.exr",
        ],
    );
    spar_ok(
        d,
        &["render", "scene.toml", "-q", "--tile", "1/2", "-o", "b.exr"],
    );
    let a = spar::image::read(&d.join("a.exr")).unwrap();
    assert!(a.metadata()["spar:settings"].contains(" isa=sse2 "));
    let out = spar(d, &["merge", "a.exr", "b.exr", "-o", "m.exr"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("mismatch: "), "{}", stderr(&out));
}

#[test]
fn bad_farm_flags_exit_2_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 16, 8, 2);
    for (args, says) in [
        (vec!["--region", "0,17,0,8"], "not inside the 16x8 image"),
        (vec!["--region", "4,4,0,8"], "x0 < x1"),
        (vec!["--tile", "2/2"], "below the tile count"),
        (vec!["--tile", "0/200"], "cannot be split into 200 tiles"),
        (vec!["--samples", "1..3"], "within the 2 samples"),
        (vec!["--samples", "2..1"], "k0 < k1"),
        (
            vec!["--tile", "0/2", "--region", "0,1,0,1"],
            "cannot be used with",
        ),
    ] {
        let mut a = vec!["render", "scene.toml", "-o", "p.exr"];
        a.extend(&args);
        let out = spar(d, &a);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
        assert!(!d.join("p.exr").exists());
    }
    let out = spar(d, &["render", "scene.toml", "--tile", "0/2", "-o", "p.png"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("is an .exr file"));
    // A sample block is for render only.
    let out = spar(
        d,
        &[
            "contact-sheet",
            "scene.toml",
            "--samples",
            "0..1",
            "-o",
            "s.png",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

#[test]
fn plan_prints_a_slurm_script_and_an_openjd_template() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 32, 16, 2);
    let out = spar_ok(
        d,
        &[
            "plan",
            "scene.toml",
            "--tiles",
            "4",
            "--slurm",
            "--out-dir",
            "job",
            "--seed",
            "3",
            "--mode",
            "color,dop",
            "--time",
            "10:00",
        ],
    );
    let script = stdout(&out);
    let abs = d.canonicalize().unwrap();
    for want in [
        "#!/bin/bash\n",
        "TILES=\"${1:-0-3}\"",
        "--array=\"$TILES\"",
        "--tile \"$SLURM_ARRAY_TASK_ID/4\"",
        "--dependency=\"afterok:$array\"",
        "--kill-on-invalid-dep=yes",
        "--time=10:00",
        "--resume",
        "--seed 3",
        "--mode color,dop",
        "parts/tile-{0..3}.exr",
        " develop ",
    ] {
        assert!(script.contains(want), "no `{want}` in\n{script}");
    }
    assert!(
        script.contains(&format!("{}/scene.toml", abs.display()))
            || script.contains(&format!("{}/scene.toml", d.display())),
        "{script}"
    );
    let check = Command::new("bash")
        .args(["-n"])
        .stdin(Stdio::piped())
        .spawn()
        .and_then(|mut c| {
            std::io::Write::write_all(c.stdin.as_mut().unwrap(), script.as_bytes())?;
            drop(c.stdin.take());
            c.wait()
        });
    assert!(check.unwrap().success(), "the script is not valid bash");

    let out = spar_ok(d, &["plan", "scene.toml", "--tiles", "4", "--openjd"]);
    let template = stdout(&out);
    for want in [
        "specificationVersion: 'jobtemplate-2023-09'",
        "range: \"0-3\"",
        "dependsOn: RenderTiles",
        "--tile '{{Task.Param.Tile}}/4'",
        "--progress openjd",
        "merge parts/tile-{0..3}.exr",
    ] {
        assert!(template.contains(want), "no `{want}` in\n{template}");
    }
    for (args, says) in [
        (vec!["--tiles", "600", "--slurm"], "cannot be split"),
        (vec!["--tiles", "4"], "--slurm"),
        (
            vec!["--tiles", "4", "--slurm", "--samples", "0..1"],
            "a count",
        ),
    ] {
        let mut a = vec!["plan", "scene.toml"];
        a.extend(&args);
        let out = spar(d, &a);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
    }
}
