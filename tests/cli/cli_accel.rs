//! `--accel embree|rust` on every command that traces: the backend is named
//! in the summary and in the settings every output carries, so farm parts
//! of different backends (which can differ at edges) do not merge; `--isa`
//! is Embree's alone; a build without the `native` feature refuses
//! `--accel embree` with exit status 2 and renders with the Rust BVH.

use crate::support::run;
use std::path::Path;

fn spar(args: &[&str], dir: &Path) -> (i32, String, String) {
    run::code_out_err(&run::spar(dir, args))
}

const SCENE: &str = r#"
[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [8, 6]

[render]
wavelengths = [450.0, 550.0, 650.0]

[[object]]
mesh = "builtin:trichecker12"
medium = "n-bk7"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

fn scene_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), SCENE).unwrap();
    dir
}

fn settings(path: &Path) -> String {
    spar::image::read(path).unwrap().metadata()["spar:settings"].clone()
}

#[test]
fn the_rust_backend_renders_and_is_named_in_summary_and_settings() {
    let dir = scene_dir();
    let (code, out, err) = spar(
        &["render", "s.toml", "--accel", "rust", "-o", "r.png"],
        dir.path(),
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(err.contains("accel rust"), "{err}");
    assert!(settings(&dir.path().join("r.png")).contains("accel=rust isa=none"));
}

#[test]
fn the_default_backend_is_embree_with_native_and_rust_without() {
    let dir = scene_dir();
    let (code, out, err) = spar(&["render", "s.toml", "-o", "d.png"], dir.path());
    assert_eq!(code, 0, "{out}{err}");
    let expect = if cfg!(feature = "native") {
        "accel=embree isa=auto"
    } else {
        "accel=rust isa=none"
    };
    assert!(settings(&dir.path().join("d.png")).contains(expect));
}

#[cfg(not(feature = "native"))]
#[test]
fn embree_is_refused_without_native() {
    let dir = scene_dir();
    for cmd in [
        vec!["render", "s.toml", "--accel", "embree", "-o", "e.png"],
        vec![
            "contact-sheet",
            "s.toml",
            "--accel",
            "embree",
            "-o",
            "e.png",
        ],
        vec![
            "plan", "s.toml", "--tiles", "2", "--slurm", "--accel", "embree",
        ],
    ] {
        let (code, out, err) = spar(&cmd, dir.path());
        assert_eq!(code, 2, "{cmd:?}: {out}{err}");
        assert!(
            err.contains("--accel embree") && err.contains("native"),
            "{err}"
        );
    }
    assert!(!dir.path().join("e.png").exists());
}

#[test]
fn isa_is_for_embree_only() {
    let dir = scene_dir();
    for cmd in [
        vec![
            "render", "s.toml", "--accel", "rust", "--isa", "sse2", "-o", "x.png",
        ],
        vec![
            "plan", "s.toml", "--tiles", "2", "--slurm", "--accel", "rust", "--isa", "sse2",
        ],
    ] {
        let (code, out, err) = spar(&cmd, dir.path());
        assert_eq!(code, 2, "{cmd:?}: {out}{err}");
        assert!(err.contains("--isa sse2") && err.contains("rust"), "{err}");
    }
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn plan_passes_the_backend_to_every_tile() {
    let dir = scene_dir();
    let (code, out, err) = spar(
        &[
            "plan", "s.toml", "--tiles", "2", "--slurm", "--accel", "rust",
        ],
        dir.path(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("--accel rust"), "{out}");
}

/// Tiles of one render merge when one backend rendered them all, and do
/// not when the backends differ (only builds with both can try that).
#[test]
fn parts_merge_only_within_one_backend() {
    let dir = scene_dir();
    let tile = |i: u32, accel: &str, out: &str| {
        let (code, o, e) = spar(
            &[
                "render",
                "s.toml",
                "--tile",
                &format!("{i}/2"),
                "--accel",
                accel,
                "-q",
                "-o",
                out,
            ],
            dir.path(),
        );
        assert_eq!(code, 0, "{o}{e}");
    };
    tile(0, "rust", "r0.exr");
    tile(1, "rust", "r1.exr");
    let (code, o, e) = spar(
        &["merge", "r0.exr", "r1.exr", "-q", "-o", "rr.exr"],
        dir.path(),
    );
    assert_eq!(code, 0, "{o}{e}");
    if cfg!(feature = "native") {
        tile(1, "embree", "e1.exr");
        let (code, o, e) = spar(
            &["merge", "r0.exr", "e1.exr", "-q", "-o", "re.exr"],
            dir.path(),
        );
        assert_eq!(code, 2, "{o}{e}");
        assert!(!dir.path().join("re.exr").exists());
    }
}

/// Without `native` images go through the pure-Rust writers: PNG and EXR.
/// Other formats are refused before anything is rendered.
#[cfg(not(feature = "native"))]
#[test]
fn contact_sheets_need_native_and_say_so_before_rendering() {
    let dir = scene_dir();
    let (code, o, e) = spar(&["contact-sheet", "s.toml", "-o", "sheet.png"], dir.path());
    assert_eq!(code, 2, "{o}{e}");
    assert!(e.contains("OpenImageIO") && e.contains("native"), "{e}");
    assert!(!e.contains("rays"), "refused after rendering: {e}");
    assert!(!dir.path().join("sheet.png").exists());
}

#[cfg(not(feature = "native"))]
#[test]
fn formats_other_than_png_and_exr_need_native() {
    let dir = scene_dir();
    for out in ["x.tif", "x.jpg"] {
        let (code, o, e) = spar(&["render", "s.toml", "-o", out], dir.path());
        assert_eq!(code, 2, "{o}{e}");
        assert!(e.contains(out) && e.contains("native"), "{e}");
        assert!(!e.contains("rays"), "refused after rendering: {e}");
    }
}
