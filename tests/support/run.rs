//! Running the spar binary of this build as a user would: the one runner
//! the command-line tests share.

use std::path::Path;
use std::process::{Command, Output};

/// Runs spar with `args` in `dir` (in the test's own current directory if
/// `None`), capturing its exit status, standard output and standard error.
pub fn spar_in(dir: Option<&Path>, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_spar"));
    command.args(args);
    if let Some(dir) = dir {
        command.current_dir(dir);
    }
    command.output().expect("spar runs")
}

/// Runs spar in `dir`.
pub fn spar(dir: &Path, args: &[&str]) -> Output {
    spar_in(Some(dir), args)
}

/// Runs spar in `dir` and insists on success.
pub fn spar_ok(dir: &Path, args: &[&str]) -> Output {
    let out = spar(dir, args);
    assert!(
        out.status.success(),
        "spar {args:?} failed: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A run's exit status (-1 if a signal ended it), standard output and
/// standard error.
pub fn code_out_err(out: &Output) -> (i32, String, String) {
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
