//! Start-up stays light: spar does not link OpenImageIO, so commands that
//! write no image through it (`--version`, `interface`, and every render
//! to PNG or EXR, which spar's own codecs write) never map its ~260 shared
//! libraries; a command that needs it (TIFF, JPEG…) loads spar's shim
//! library (`libspar_oiio.so`) when it first reads or writes such a file,
//! from `SPAR_OIIO_SHIM`, beside the executable, or where the build wrote
//! it; and a shim that cannot be loaded is a clear error, not a crash.
//!
//! What is loaded is seen through the dynamic linker's own report
//! (`LD_DEBUG=files`, glibc), checked first on a command that must load
//! the shim. Times and memory are not tested here: docs/architecture.md
//! has the measurements and the commands that make them.
#![cfg(feature = "native")]

use std::path::Path;
use std::process::{Command, Output};

const ENV: &str = "SPAR_OIIO_SHIM";

/// Runs the spar binary of this build (or `exe`) in `dir` with `args` and
/// the environment `env` (`None` removes a variable).
fn run(exe: &Path, dir: &Path, args: &[&str], env: &[(&str, Option<&str>)]) -> Output {
    let mut command = Command::new(exe);
    command.args(args).current_dir(dir).env_remove(ENV);
    for (key, value) in env {
        match value {
            Some(v) => command.env(key, v),
            None => command.env_remove(key),
        };
    }
    // A freshly copied executable can be "busy" for a moment (Linux
    // ETXTBSY): a test running beside this one may fork between the copy's
    // write and its close, and its child holds the write descriptor until
    // it execs. Try again then.
    for _ in 0..100 {
        match command.output() {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy => {
                std::thread::sleep(std::time::Duration::from_millis(20))
            }
            result => return result.expect("spar runs"),
        }
    }
    command.output().expect("spar runs")
}

fn spar_exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_spar"))
}

fn text(out: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

fn assert_ok(out: &Output) {
    assert!(out.status.success(), "{}", text(out));
}

/// The files the dynamic linker loaded for a run under `LD_DEBUG=files`
/// (each `file=NAME [0];  …` line of its report), or None if it reported
/// nothing (not glibc).
fn loaded_files(out: &Output) -> Option<Vec<String>> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    let files: Vec<String> = stderr
        .lines()
        .filter_map(|l| l.split_once("file=").map(|(_, rest)| rest))
        .filter_map(|rest| rest.split_whitespace().next())
        .map(str::to_string)
        .collect();
    (!files.is_empty()).then_some(files)
}

fn mentions(files: &[String], name: &str) -> bool {
    files.iter().any(|f| f.contains(name))
}

const RENDER: [&str; 4] = ["render", "--resolution", "8x8", "-o"];

#[test]
fn version_interface_and_png_or_exr_renders_do_not_load_openimageio() {
    let dir = tempfile::tempdir().unwrap();
    let debug = [("LD_DEBUG", Some("files"))];

    // The control: a TIFF needs OpenImageIO, so the report must show the
    // shim and OpenImageIO being loaded; if it does not, the check below
    // would prove nothing.
    let tif = dir.path().join("control.tif");
    let args = [&RENDER[..], &[tif.to_str().unwrap()]].concat();
    let out = run(spar_exe(), dir.path(), &args, &debug);
    assert_ok(&out);
    let Some(files) = loaded_files(&out) else {
        eprintln!("SKIPPED: the dynamic linker does not report LD_DEBUG=files (not glibc?)");
        return;
    };
    assert!(mentions(&files, "libspar_oiio.so"), "{files:?}");
    assert!(mentions(&files, "libOpenImageIO"), "{files:?}");

    let png = dir.path().join("r.png");
    let exr = dir.path().join("r.exr");
    let png_render = [&RENDER[..], &[png.to_str().unwrap()]].concat();
    let exr_render = [&RENDER[..], &[exr.to_str().unwrap(), "--mode", "stokes"]].concat();
    for args in [
        &["--version"][..],
        &png_render,
        &exr_render,
        &[
            "interface",
            "--from",
            "air",
            "--to",
            "calcite",
            "--axis",
            "0,0.6,0.8",
            "--incident",
            "0.3,0,-1",
            "--mode",
            "s",
            "--json",
        ],
    ] {
        let out = run(spar_exe(), dir.path(), args, &debug);
        assert_ok(&out);
        let files = loaded_files(&out).expect("the control run had a report");
        for name in ["libspar_oiio", "libOpenImageIO", "libopencv", "libavcodec"] {
            assert!(
                !mentions(&files, name),
                "spar {args:?} loaded {name}: {files:?}"
            );
        }
        // Embree stays linked (it costs a few milliseconds).
        assert!(mentions(&files, "libembree3"), "{files:?}");
    }
}

#[test]
fn renders_write_png_exr_and_tiff() {
    let dir = tempfile::tempdir().unwrap();
    for (file, mode) in [("r.png", "color"), ("r.exr", "stokes"), ("r.tif", "color")] {
        let path = dir.path().join(file);
        let args = [&RENDER[..], &[path.to_str().unwrap(), "--mode", mode]].concat();
        assert_ok(&run(spar_exe(), dir.path(), &args, &[]));
        let image = spar::image::read(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!((image.width(), image.height()), (8, 8), "{file}");
        if mode == "stokes" {
            assert!(
                image.channel_index("S0.580nm").is_ok(),
                "{:?}",
                image.channels()
            );
        }
    }
}

#[test]
fn the_environment_variable_overrides_the_search() {
    let dir = tempfile::tempdir().unwrap();
    let built = spar_sys::oiio::BUILT_LIBRARY;
    let tif = dir.path().join("named.tif");
    let args = [&RENDER[..], &[tif.to_str().unwrap()]].concat();
    let out = run(spar_exe(), dir.path(), &args, &[(ENV, Some(built))]);
    assert_ok(&out);
    assert!(tif.is_file());
}

#[test]
fn a_shim_that_cannot_be_loaded_is_a_clear_error_not_a_crash() {
    let dir = tempfile::tempdir().unwrap();
    let nowhere = dir.path().join("nowhere").join("libspar_oiio.so");
    let env = [(ENV, Some(nowhere.to_str().unwrap()))];

    // Commands that need no image library do not notice, renders to PNG
    // and EXR included.
    assert_ok(&run(spar_exe(), dir.path(), &["--version"], &env));
    let own = dir.path().join("own");
    std::fs::create_dir(&own).unwrap();
    for (file, mode) in [("out.png", "color"), ("out.exr", "stokes")] {
        let path = own.join(file);
        let args = [&RENDER[..], &[path.to_str().unwrap(), "--mode", mode]].concat();
        assert_ok(&run(spar_exe(), dir.path(), &args, &env));
        assert!(path.is_file(), "{file}");
    }
    std::fs::remove_dir_all(&own).unwrap();

    for (file, mode) in [("out.tif", "color"), ("out.jpg", "color")] {
        let path = dir.path().join(file);
        let args = [&RENDER[..], &[path.to_str().unwrap(), "--mode", mode]].concat();
        let out = run(spar_exe(), dir.path(), &args, &env);
        let code = out.status.code();
        // spar's own failure (exit 1: cli/error.rs), not a panic's 101
        // nor a signal.
        assert_eq!(code, Some(1), "{}", text(&out));
        let stderr = String::from_utf8_lossy(&out.stderr);
        for needle in [
            "could not be loaded",
            ENV,
            &format!("{}: no such file", nowhere.display()),
            file,
        ] {
            assert!(stderr.contains(needle), "{needle:?} missing:\n{stderr}");
        }
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "{left:?}");

    // A file that is not a shared library is refused the same way.
    let junk = dir.path().join("junk.so");
    std::fs::write(&junk, b"not a library").unwrap();
    let tif = dir.path().join("out.tif");
    let args = [&RENDER[..], &[tif.to_str().unwrap()]].concat();
    let out = run(
        spar_exe(),
        dir.path(),
        &args,
        &[(ENV, Some(junk.to_str().unwrap()))],
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains(junk.to_str().unwrap()),
        "{}",
        text(&out)
    );
}

#[test]
fn a_copied_executable_finds_the_shim_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let exe = bin.join("spar");
    std::fs::copy(spar_exe(), &exe).unwrap();
    let beside = bin.join("libspar_oiio.so");
    std::fs::copy(spar_sys::oiio::BUILT_LIBRARY, &beside).unwrap();

    let tif = dir.path().join("copied.tif");
    let args = [&RENDER[..], &[tif.to_str().unwrap()]].concat();
    let out = run(&exe, dir.path(), &args, &[("LD_DEBUG", Some("files"))]);
    assert_ok(&out);
    assert!(tif.is_file());
    if let Some(files) = loaded_files(&out) {
        let beside = beside.to_str().unwrap();
        assert!(files.iter().any(|f| f == beside), "{files:?}");
        assert!(
            !files.iter().any(|f| f == spar_sys::oiio::BUILT_LIBRARY),
            "{files:?}"
        );
    }
}
