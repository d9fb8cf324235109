//! Every command exits with status 2 for what the user can fix: bad flags
//! or input files, and outputs that cannot be written (then writing
//! nothing). The exit status comes from the error's kind alone
//! (`spar::cli::ErrorKind::exit_status`).

use crate::support::run::{self, code_out_err};
use spar::cli::{CliError, ErrorKind};
use std::path::{Path, PathBuf};

/// Runs spar in `dir`: its exit status and standard error.
fn spar(dir: &Path, args: &[&str]) -> (i32, String) {
    let (code, _, err) = code_out_err(&run::spar(dir, args));
    (code, err)
}

/// Asserts that spar exits with status 2 and says `needle`.
fn refused(dir: &Path, args: &[&str], needle: &str) {
    let (code, err) = spar(dir, args);
    assert_eq!(code, 2, "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
}

/// A working directory holding `file`, a regular file: `file/x.png` is
/// an output that cannot be written (tests run as root, so permission
/// bits would not stop a write).
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("file"), "not a directory").unwrap();
    dir
}

fn scene() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/glass-unpolarized.toml")
        .to_string_lossy()
        .into_owned()
}

/// The flags of a tiny, fast render.
const TINY: [&str; 6] = [
    "--resolution",
    "4x4",
    "--samples",
    "1",
    "--wavelengths",
    "7",
];

/// `args` with the tiny render's flags.
fn tiny<'a>(args: &[&'a str]) -> Vec<&'a str> {
    let mut v = args.to_vec();
    v.extend(TINY);
    v
}

/// The files in `dir` besides `file`.
fn written(dir: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name() != Some("file".as_ref()))
        .collect();
    found.sort();
    found
}

#[test]
fn the_kind_alone_gives_the_exit_status() {
    assert_eq!(ErrorKind::Input.exit_status(), 2);
    assert_eq!(ErrorKind::Output.exit_status(), 2);
    assert_eq!(ErrorKind::Internal.exit_status(), 1);
    for kind in [ErrorKind::Input, ErrorKind::Output, ErrorKind::Internal] {
        let e = CliError::new(kind, "message");
        assert_eq!(e.exit_status(), kind.exit_status());
        assert_eq!(e.to_string(), "message");
    }
}

#[test]
fn render() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    refused(
        d,
        &tiny(&["render", &s, "--max-depth", "5000", "-o", "x.png"]),
        "--max-depth",
    );
    refused(d, &tiny(&["render", "missing.toml"]), "missing.toml");
    refused(d, &tiny(&["render", &s, "-o", "file/x.png"]), "file/x.png");
    // A format no writer takes: refused by the writer after the render
    // (with OpenImageIO) or before it (the pure-Rust writers).
    refused(d, &tiny(&["render", &s, "-o", "x.xyz"]), "x.xyz");
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

#[test]
fn compare() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    // Without Embree, every run is refused (it needs both backends).
    let native = cfg!(feature = "native");
    let bad = if native { "--wavelength" } else { "native" };
    refused(
        d,
        &tiny(&["compare", &s, "--wavelength", "100", "-o", "d.png"]),
        bad,
    );
    let unwritable = if native { "file/d.png" } else { "native" };
    refused(d, &tiny(&["compare", &s, "-o", "file/d.png"]), unwritable);
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

#[test]
fn contact_sheet() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    let native = cfg!(feature = "native");
    refused(
        d,
        &tiny(&["contact-sheet", "missing.toml", "-o", "sheet.png"]),
        if native { "missing.toml" } else { "native" },
    );
    // The sheet is rendered, then cannot be written.
    refused(
        d,
        &tiny(&["contact-sheet", &s, "-m", "color", "-o", "file/sheet.png"]),
        if native { "file/sheet.png" } else { "native" },
    );
    // Too sparse a colour set for the colour mode: the scene's or the
    // flags' fault, found when the panels are developed.
    if native {
        refused(
            d,
            &[
                "contact-sheet",
                &s,
                "-m",
                "color",
                "--resolution",
                "4x4",
                "--samples",
                "1",
                "--wavelengths",
                "450,451",
                "-o",
                "sheet.png",
            ],
            "too sparse",
        );
    }
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

#[test]
fn cut() {
    let dir = workdir();
    let d = dir.path();
    refused(d, &["cut", "trillion", "-o", "t.obj"], "trillion");
    refused(d, &["cut", "nothere.asc", "-o", "t.obj"], "nothere.asc");
    refused(
        d,
        &["cut", "round-brilliant", "-o", "file/b.obj"],
        "file/b.obj",
    );
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

#[test]
fn interface() {
    let dir = workdir();
    let d = dir.path();
    let solve = |to: &str, normal: &str| {
        let args = [
            "interface",
            "--from",
            "air",
            "--to",
            to,
            "--normal",
            normal,
            "--incident",
            "0,0.5,-1",
            "--mode",
            "s",
        ];
        args.map(String::from)
    };
    let (code, err) = spar(d, &solve("n-bk7", "0,0,1").each_ref().map(String::as_str));
    assert_eq!(code, 0, "{err}");
    refused(
        d,
        &solve("n-bk7", "0,0,0").each_ref().map(String::as_str),
        "--normal",
    );
    refused(
        d,
        &solve("unobtainium", "0,0,1").each_ref().map(String::as_str),
        "--to",
    );
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

#[test]
fn merge_and_develop() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    std::fs::write(d.join("text.exr"), "not an EXR").unwrap();
    refused(d, &["merge", "text.exr", "-o", "merged.exr"], "text.exr");
    refused(d, &["merge", "text.exr", "-o", "file/m.exr"], "file/m.exr");
    refused(d, &["develop", "missing.exr", "-o", "x.png"], "missing.exr");
    // A real raw render to develop.
    let (code, err) = spar(d, &tiny(&["render", &s, "--raw", "-o", "raw.exr", "-q"]));
    assert_eq!(code, 0, "{err}");
    refused(d, &["develop", "raw.exr", "-o", "file/x.png"], "file/x.png");
    // A wavelength the raw render did not trace.
    refused(
        d,
        &[
            "develop",
            "raw.exr",
            "-m",
            "mono",
            "--wavelength",
            "500",
            "-o",
            "mono.png",
        ],
        "500",
    );
    assert_eq!(written(d), vec![d.join("raw.exr"), d.join("text.exr")]);
}

#[test]
fn plan() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    refused(d, &["plan", &s, "--tiles", "0", "--slurm"], "--tiles");
    refused(
        d,
        &["plan", "missing.toml", "--tiles", "4", "--slurm"],
        "missing.toml",
    );
    assert_eq!(written(d), Vec::<PathBuf>::new());
}

/// A results.csv as `spar speed-error` writes it, of one measure.
const RESULTS: &str = "config,seconds,rays,color_rmse,color_max\n\
                       \"scene\",1.0,100,0.01,0.1\n\
                       \"depth=2\",0.5,50,0.05,0.3\n";

#[test]
fn speed_error() {
    let dir = workdir();
    let d = dir.path();
    let s = scene();
    refused(
        d,
        &tiny(&["speed-error", &s, "--config", "depth=x", "-o", "se"]),
        "depth",
    );
    refused(
        d,
        &tiny(&["speed-error", &s, "--config", "", "-o", "file/se"]),
        "file/se",
    );
    assert_eq!(written(d), Vec::<PathBuf>::new());

    // Merging earlier results renders nothing: a quick way to the writes.
    std::fs::write(d.join("in.csv"), RESULTS).unwrap();
    fn merge(out: &str) -> [&str; 6] {
        ["speed-error", "--from-csv", "in.csv", "-o", out, "-q"]
    }
    let (code, err) = spar(d, &merge("ok"));
    assert_eq!(code, 0, "{err}");
    assert!(d.join("ok/results.csv").is_file() && d.join("ok/pareto.png").is_file());
    // An unwritable plot (its name taken by a directory): written first,
    // so nothing is written.
    std::fs::create_dir_all(d.join("plot/pareto.png")).unwrap();
    refused(d, &merge("plot"), "pareto.png");
    assert!(!d.join("plot/results.csv").exists());
    // An unwritable CSV.
    std::fs::create_dir_all(d.join("csv/results.csv")).unwrap();
    refused(d, &merge("csv"), "results.csv");
    assert!(d.join("csv/results.csv").is_dir());
}
