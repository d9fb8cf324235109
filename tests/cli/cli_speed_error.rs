//! `spar speed-error` end to end: the CSV, table and plot it writes, the
//! reference it saves and checks, and its errors.

use crate::support::run;
use std::path::Path;

fn spar(args: &[&str]) -> std::process::Output {
    run::spar_in(None, args)
}

fn scene() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/glass-unpolarized.toml")
        .to_string_lossy()
        .into_owned()
}

/// Asserts that a run succeeded, showing its errors if not.
fn succeeded(run: &std::process::Output) {
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

const SMALL: [&str; 4] = ["--resolution", "12x12", "--wavelengths", "7"];

#[test]
fn a_sweep_writes_csv_table_and_plot_and_reuses_its_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("se");
    let reference = dir.path().join("ref.exr");
    let (out_s, ref_s) = (out.to_str().unwrap(), reference.to_str().unwrap());
    let s = scene();
    let mut args = vec!["speed-error", &s, "-o", out_s, "--reference", ref_s];
    args.extend(SMALL);
    args.extend([
        "--reference-config",
        "depth=13 prune=1e-4 spp=2",
        "--config",
        "",
        "--config",
        "depth=2",
        "--config",
        "spectral=hero:1",
    ]);
    let run = spar(&args);
    succeeded(&run);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "config,seconds,rays,color_rmse,color_max,color_rmse_net,dop_rmse,dop_max,dop_rmse_net,\
         dop-weighted_rmse,dop-weighted_max,dop-weighted_rmse_net,\
         color_pareto,dop_pareto,dop-weighted_pareto"
    );
    assert_eq!(lines.len(), 4);
    // The scene's own settings are the reference's, but the reference's
    // samples use other seeds: an error of the order of the sampling noise
    // (1 sample against 2: about sqrt(3) times the reference's noise
    // estimate), never zero.
    let scene_row: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(scene_row[0], "\"scene\"");
    let about = std::fs::read_to_string(out.join("reference.txt")).unwrap();
    let noise: f64 = about
        .lines()
        .find_map(|l| l.strip_prefix("reference noise estimate, color RMSE: "))
        .unwrap_or_else(|| panic!("{about}"))
        .parse()
        .unwrap();
    let scene_err: f64 = scene_row[3].parse().unwrap();
    assert!(
        noise > 0.0 && scene_err > noise,
        "{scene_err} vs noise {noise}"
    );
    // Depth 2 misses light: more error than the noise, and fewer rays.
    let shallow: Vec<&str> = lines[2].split(',').collect();
    assert!(
        shallow[3].parse::<f64>().unwrap() > scene_err,
        "{}",
        lines[2]
    );
    assert!(shallow[2].parse::<u64>().unwrap() < scene_row[2].parse::<u64>().unwrap());
    // One colour wavelength per sample out of seven, plus dop's 580 nm:
    // two trees per sample instead of eight (N-BK7 disperses).
    let hero: Vec<&str> = lines[3].split(',').collect();
    assert!(hero[2].parse::<u64>().unwrap() * 3 < scene_row[2].parse::<u64>().unwrap());
    // A most accurate row of each mode is on that mode's front (of rows
    // with equal error, the fastest).
    let rows: Vec<Vec<&str>> = lines[1..].iter().map(|l| l.split(',').collect()).collect();
    for (err_col, front_col) in [(3, 12), (6, 13), (9, 14)] {
        let e = |r: &Vec<&str>| r[err_col].parse::<f64>().unwrap();
        let least = rows.iter().map(e).fold(f64::INFINITY, f64::min);
        assert!(
            rows.iter().any(|r| e(r) == least && r[front_col] == "1"),
            "{csv}"
        );
        assert!(rows
            .iter()
            .all(|r| r[front_col] == "0" || r[front_col] == "1"));
    }
    // The net error takes the reference's noise out: never above the RMSE,
    // and below it wherever the reference has noise.
    for r in &rows {
        for col in [3, 6, 9] {
            let (rmse, net) = (
                r[col].parse::<f64>().unwrap(),
                r[col + 2].parse::<f64>().unwrap(),
            );
            assert!(net.is_finite() && net >= 0.0 && net <= rmse, "{csv}");
        }
    }
    let table = String::from_utf8_lossy(&run.stdout);
    assert!(table.contains("| settings | time (s) | rays |"), "{table}");
    assert!(table.contains("| depth=2 |"), "{table}");

    let plot = spar::image::read(&out.join("pareto.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), (1200, 800));
    assert!(plot.data().iter().any(|&v| v < 0.5), "something is drawn");

    // The saved reference is read back, not rendered again (this is
    // printed only when rendering one).
    assert!(reference.exists());
    assert!(String::from_utf8_lossy(&run.stderr).contains("rendering the reference"));
    let again = spar(&args);
    succeeded(&again);
    assert!(!String::from_utf8_lossy(&again.stderr).contains("rendering the reference"));
    let csv2 = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let err = |c: &str| {
        c.lines()
            .nth(2)
            .unwrap()
            .split(',')
            .nth(3)
            .unwrap()
            .to_string()
    };
    assert_eq!(err(&csv), err(&csv2), "the same reference, the same error");

    // Other reference settings: the saved file no longer fits.
    let mut other = args.clone();
    let i = other
        .iter()
        .position(|a| *a == "depth=13 prune=1e-4 spp=2")
        .unwrap();
    other[i] = "depth=12 prune=1e-4 spp=2";
    let refused = spar(&other);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("not a reference for this scene"));
}

#[test]
fn bad_configs_and_modes_exit_2_naming_the_item() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("se");
    let s = scene();
    for (extra, needle) in [
        (vec!["--config", "depth=x"], "depth=x"),
        (vec!["--config", "colour=3"], "unknown key"),
        (vec!["--reference-config", "spp=0"], "spp=0"),
        (vec!["--mode", "stokes"], "stokes"),
    ] {
        let mut args = vec!["speed-error", &s, "-o", out.to_str().unwrap()];
        args.extend(SMALL);
        args.extend(extra);
        let run = spar(&args);
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!out.join("results.csv").exists());
    }
}

#[test]
fn errors_on_every_kth_row_need_a_reference_of_those_rows() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("se");
    let reference = dir.path().join("ref.exr");
    let (out_s, ref_s) = (out.to_str().unwrap(), reference.to_str().unwrap());
    let s = scene();
    let base = |rows: &'static str| {
        let mut a = vec![
            "speed-error",
            &s,
            "-o",
            out_s,
            "--reference",
            ref_s,
            "--reference-config",
            "spp=2",
            "--config",
            "",
            "--error-rows",
            rows,
        ];
        a.extend(SMALL);
        a.iter().map(|x| x.to_string()).collect::<Vec<String>>()
    };
    let run = |a: &[String]| spar(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let rows4 = run(&base("4"));
    succeeded(&rows4);
    let about = std::fs::read_to_string(out.join("reference.txt")).unwrap();
    assert!(about.contains("1 row in 4 (3 of 12 rows)"), "{about}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let err: f64 = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    assert!(err > 0.0 && err.is_finite(), "{csv}");
    // A reference of some rows is not one of the whole image.
    let whole = run(&base("1"));
    assert_eq!(whole.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&whole.stderr).contains("not a reference"));
    let zero = run(&base("0"));
    assert_eq!(zero.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&zero.stderr).contains("--error-rows"));
}

#[test]
fn paired_errors_are_the_settings_own() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("se");
    let reference = dir.path().join("ref.exr");
    let (out_s, ref_s) = (out.to_str().unwrap(), reference.to_str().unwrap());
    let s = scene();
    let mut args = vec![
        "speed-error",
        &s,
        "-o",
        out_s,
        "--paired",
        "--reference",
        ref_s,
        "--reference-config",
        "depth=20 prune=1e-6 spp=2",
        "--config",
        "depth=20 prune=1e-6 spp=2",
        "--config",
        "depth=20 prune=1e-6 spp=1",
        "--config",
        "depth=2 prune=1e-6 spp=2",
    ];
    args.extend(SMALL);
    let run = spar(&args);
    succeeded(&run);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
        .collect();
    // Columns after the label: seconds, rays, then rmse, max, net per
    // measure (color, dop, dop-weighted), then the fronts.
    let errs = |r: &Vec<f64>| [r[2], r[5], r[8]];
    // The reference's own settings and seed: the same image.
    assert_eq!(errs(&rows[0]), [0.0; 3], "{csv}");
    // Half of its samples (the same first sample): some error, all of it
    // antialiasing; depth 2 loses light at the same sample positions.
    assert!(errs(&rows[1]).iter().all(|&e| e > 0.0), "{csv}");
    assert!(rows[2][2] > 0.01, "{csv}");
    let about = std::fs::read_to_string(out.join("reference.txt")).unwrap();
    assert!(about.contains("paired"), "{about}");
    assert!(!about.contains("noise estimate"), "{about}");
    // Saved as one film; an unpaired run does not take it.
    let again = spar(&args);
    succeeded(&again);
    assert!(!String::from_utf8_lossy(&again.stderr).contains("rendering the reference"));
    let unpaired: Vec<&str> = args.iter().copied().filter(|a| *a != "--paired").collect();
    let refused = spar(&unpaired);
    assert_eq!(refused.status.code(), Some(2));
}

#[test]
fn from_csv_merges_earlier_runs_without_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let (a, merged) = (dir.path().join("a"), dir.path().join("merged"));
    let s = scene();
    let mut args = vec!["speed-error", &s, "-o", a.to_str().unwrap()];
    args.extend(SMALL);
    args.extend([
        "--reference-config",
        "spp=2",
        "--config",
        "depth=2",
        "--config",
        "",
    ]);
    succeeded(&spar(&args));
    let csv_a = a.join("results.csv");
    let first = std::fs::read_to_string(&csv_a).unwrap();
    // The same file twice: every row twice, equal rows never dominating
    // each other, so the fronts keep both copies.
    let run = spar(&[
        "speed-error",
        "--from-csv",
        csv_a.to_str().unwrap(),
        "--from-csv",
        csv_a.to_str().unwrap(),
        "-o",
        merged.to_str().unwrap(),
    ]);
    succeeded(&run);
    let both = std::fs::read_to_string(merged.join("results.csv")).unwrap();
    let lines: Vec<&str> = both.lines().collect();
    assert_eq!(lines[0], first.lines().next().unwrap());
    assert_eq!(lines.len(), 1 + 2 * (first.lines().count() - 1));
    assert_eq!(lines[1], lines[3], "{both}");
    assert_eq!(lines[1..3], first.lines().skip(1).collect::<Vec<_>>()[..]);
    assert!(merged.join("pareto.png").exists());
    assert!(!String::from_utf8_lossy(&run.stderr).contains("reference"));

    // A file that is not a results.csv, or a broken row: exit 2 naming
    // the file and line, nothing written.
    let bad = dir.path().join("bad.csv");
    let out = dir.path().join("out");
    let mut rows: Vec<String> = first.lines().take(2).map(String::from).collect();
    let mut fields: Vec<&str> = rows[1].split(',').collect();
    fields[1] = "soon";
    rows[1] = fields.join(",");
    std::fs::write(&bad, rows.join("\n")).unwrap();
    for (file, needle) in [
        (bad.clone(), "bad.csv:2:"),
        (dir.path().join("none.csv"), "none.csv"),
    ] {
        let r = spar(&[
            "speed-error",
            "--from-csv",
            file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(r.status.code(), Some(2));
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(needle), "{err}");
        assert!(!out.join("results.csv").exists());
    }
}
