//! `spar cut` writes OBJ files that the OBJ loader reads back as closed,
//! consistently oriented solids with their facet names, and reports bad
//! flags as user errors.
//!
//! The command's module is compiled into this test directly, so the test
//! runs whether or not the subcommand is wired into the binary yet.

use spar::geometry::load_obj;
use std::path::Path;

pub use spar::cli::{CliError, ErrorKind};
/// The paths `src/cli/cut.rs` uses (`crate::…`), re-exported for it.
mod geometry {
    pub use spar::geometry::*;
}
mod atomic_file {
    pub use spar::atomic_file::*;
}
mod error {
    pub use spar::cli::error::*;
}
mod cli {
    pub mod common {
        pub use spar::cli::common::check_output_location;
    }
}
const VERSION: &str = spar::VERSION;
#[path = "../src/cli/cut.rs"]
#[allow(dead_code)]
mod cut;

use clap::Parser;

#[derive(Parser)]
struct Args {
    #[command(flatten)]
    cut: cut::CutArgs,
}

fn run(argv: &[&str]) -> Result<String, CliError> {
    let args = Args::try_parse_from(std::iter::once("cut").chain(argv.iter().copied()))
        .map_err(|e| CliError::input(e.to_string()))?;
    let mut out = Vec::new();
    cut::run_to(&args.cut, &mut out)?;
    Ok(String::from_utf8(out).unwrap())
}

#[test]
fn every_cut_is_written_and_read_back_closed() {
    let dir = tempfile::tempdir().unwrap();
    for (name, facets) in [
        ("round-brilliant", 73),
        ("oval", 73),
        ("princess", 33),
        ("emerald", 53),
    ] {
        let path = dir.path().join(format!("{name}.obj"));
        let summary = run(&[name, "-o", path.to_str().unwrap()]).unwrap();
        assert!(summary.contains("closed, oriented, convex"), "{summary}");
        let mesh = load_obj(&path).unwrap();
        mesh.check_closed_and_oriented().unwrap();
        assert_eq!(mesh.facets.len(), facets, "{name}");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains(&format!("name = \"{name}\"")),
            "{name}: header"
        );
        assert!(mesh.facets.iter().all(|f| f.name.is_some()));
    }
}

#[test]
fn flags_set_the_proportions_and_names_survive() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.obj");
    let p = path.to_str().unwrap();
    run(&[
        "round-brilliant",
        "--girdle",
        "0",
        "--culet",
        "0.02",
        "--diameter",
        "6.5",
        "-o",
        p,
    ])
    .unwrap();
    let mesh = load_obj(&path).unwrap();
    mesh.check_closed_and_oriented().unwrap();
    assert_eq!(mesh.facets.len(), 58);
    let (lo, hi) = mesh.bounds();
    assert!(((hi.x - lo.x) - 6.5).abs() < 1e-5, "{lo} {hi}");
    let mut names: Vec<&str> = mesh
        .facets
        .iter()
        .map(|f| f.name.as_deref().unwrap())
        .collect();
    names.sort_unstable();
    assert!(
        names.contains(&"culet")
            && names.contains(&"bezel-8")
            && names.contains(&"lower-girdle-16")
    );
}

#[test]
fn asc_designs_convert() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.obj");
    let asc = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems/trichecker12.asc");
    run(&[asc.to_str().unwrap(), "-o", path.to_str().unwrap()]).unwrap();
    let mesh = load_obj(&path).unwrap();
    mesh.check_closed_and_oriented().unwrap();
    assert_eq!(mesh.facets.len(), 48);
    assert!(mesh
        .facets
        .iter()
        .any(|f| f.name.as_deref() == Some("A@52")));
    let e = run(&[
        asc.to_str().unwrap(),
        "--table",
        "0.5",
        "-o",
        path.to_str().unwrap(),
    ])
    .unwrap_err();
    assert!(
        e.kind() == ErrorKind::Input && e.to_string().contains("--table"),
        "{e}"
    );
}

#[test]
fn user_errors_exit_2_and_name_the_flag() {
    let out = "/nonexistent-dir/x.obj";
    for (argv, word) in [
        (vec!["trillion", "-o", out], "round-brilliant"),
        (vec!["emerald", "--star", "0.4", "-o", out], "--star"),
        (
            vec!["round-brilliant", "--crown-angle", "95", "-o", out],
            "--crown-angle",
        ),
        (vec!["princess", "--table", "0", "-o", out], "--table"),
        (vec!["nothere.asc", "-o", out], "nothere.asc"),
    ] {
        let e = run(&argv).unwrap_err();
        assert_eq!(e.exit_status(), 2, "{argv:?}: {e}");
        assert!(e.to_string().contains(word), "{argv:?}: {e}");
    }
    // A bad output path is the user's too (as for render and merge).
    let e = run(&["princess", "-o", out]).unwrap_err();
    assert_eq!(e.exit_status(), 2, "{e}");
    assert!(e.to_string().contains(out), "{e}");
}
