//! The Python module (`python/`, issue 19), as a user installs it: a
//! virtual environment under `target/tmp`, `pip install ./python` (maturin
//! and the module's dependencies from PyPI), then its pytest suite against
//! this build's `spar` (`SPAR_BIN`). A failure prints pip's or pytest's
//! output.
//!
//! The module is built into this build's target directory (cargo holds no
//! lock on it while tests run), so the dependencies it shares with spar
//! are not compiled again; later runs, and the pure-Rust pass of the same
//! CI run, rebuild only what changed. Each step's time is printed
//! (`--nocapture`).

use std::path::Path;
use std::process::{Command, Output};
use std::time::Instant;

/// Runs `program args…` in the repository with `env`, failing the test
/// with its output (and `hint`) if it fails.
fn step(what: &str, program: &Path, args: &[&str], env: &[(&str, &str)], hint: &str) -> Output {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let start = Instant::now();
    let out = Command::new(program)
        .args(args)
        .current_dir(repo)
        .envs(env.iter().copied())
        .env("PIP_DISABLE_PIP_VERSION_CHECK", "1")
        .env("PIP_ROOT_USER_ACTION", "ignore")
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {}: {e}{hint}", program.display()));
    println!("{what}: {:.1} s", start.elapsed().as_secs_f64());
    assert!(
        out.status.success(),
        "{what} failed ({}):\n--- stdout\n{}\n--- stderr\n{}{hint}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn the_python_module_installs_with_pip_and_passes_its_pytest_suite() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let venv = tmp.join("python-venv");
    let python = venv.join("bin").join("python");
    if !python.exists() {
        step(
            "python3 -m venv",
            Path::new("python3"),
            &["-m", "venv", &venv.to_string_lossy()],
            &[],
            "\n(./setup installs python3 and python3-venv on Debian)",
        );
    }
    let pip = |what: &str, args: &[&str], env: &[(&str, &str)]| {
        let mut all = vec!["-m", "pip", "install", "--quiet"];
        all.extend_from_slice(args);
        step(what, &python, &all, env, "");
    };
    pip(
        "pip install numpy pytest OpenEXR",
        &["numpy", "pytest", "OpenEXR>=3.2"],
        &[],
    );
    let target = tmp.parent().expect("CARGO_TARGET_TMPDIR is target/tmp");
    pip(
        "pip install ./python",
        &["./python"],
        &[("CARGO_TARGET_DIR", &target.to_string_lossy())],
    );
    let out = step(
        "pytest python/tests",
        &python,
        &[
            "-m",
            "pytest",
            "-q",
            "-rs",
            "-p",
            "no:cacheprovider",
            "python/tests",
        ],
        &[("SPAR_BIN", env!("CARGO_BIN_EXE_spar"))],
        "",
    );
    let report = String::from_utf8_lossy(&out.stdout);
    println!("{report}");
    // No test may be skipped.
    let skipped = report
        .lines()
        .filter(|l| l.starts_with("SKIPPED"))
        .collect::<Vec<_>>();
    assert!(
        skipped.is_empty(),
        "unexpected skips:\n{}",
        skipped.join("\n")
    );
}
