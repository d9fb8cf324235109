//! `spar compare`: both backends render one scene with the same settings;
//! the table has build and render times, rays/s, the speed ratio and, per
//! image, max abs, RMSE and the count of pixels differing by more than
//! 1e-6 relative, with a verdict that agrees with those counts; the
//! difference images say the same. Without the `native` feature there is
//! one backend only, and compare refuses with exit status 2.

use crate::support::run;
use std::path::{Path, PathBuf};

fn spar(args: &[&str], dir: &Path) -> (i32, String, String) {
    run::code_out_err(&run::spar(dir, args))
}

fn glass() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass-unpolarized.toml")
}

#[cfg(not(feature = "native"))]
#[test]
fn compare_needs_both_backends() {
    let dir = tempfile::tempdir().unwrap();
    let scene = glass();
    let (code, out, err) = spar(
        &["compare", scene.to_str().unwrap(), "--resolution", "8x8"],
        dir.path(),
    );
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("both backends") && err.contains("native"),
        "{err}"
    );
    assert!(!dir.path().join("diff.png").exists());
}

/// One image row of the table: max abs, RMSE, pixels differing by more
/// than 1e-6 relative, of how many, pixels not bit for bit equal.
#[cfg(feature = "native")]
fn image_row(table: &str, name: &str) -> (f64, f64, usize, usize, usize) {
    let line = table
        .lines()
        .find(|l| l.starts_with(name) && l.contains(" of "))
        .unwrap_or_else(|| panic!("no row {name} in\n{table}"));
    let f: Vec<&str> = line[name.len()..].split_whitespace().collect();
    assert_eq!(f.len(), 6, "{line}");
    (
        f[0].parse().unwrap(),
        f[1].parse().unwrap(),
        f[2].parse().unwrap(),
        f[4].parse().unwrap(),
        f[5].parse().unwrap(),
    )
}

#[cfg(feature = "native")]
#[test]
fn compare_prints_the_table_and_writes_difference_images() {
    let dir = tempfile::tempdir().unwrap();
    let scene = glass();
    let (code, table, err) = spar(
        &[
            "compare",
            scene.to_str().unwrap(),
            "--resolution",
            "32x32",
            "--mode",
            "color,dop",
            "--threads",
            "2",
            "-o",
            "d.png",
        ],
        dir.path(),
    );
    assert_eq!(code, 0, "{table}{err}");
    assert!(table.contains("32x32 px"), "{table}");
    assert!(
        table.contains("rays inside convex stones: their facet planes, as in renders"),
        "{table}"
    );
    // The timing table: a row per backend with build, render, rays, rays/s.
    for backend in ["embree", "rust"] {
        let line = table
            .lines()
            .find(|l| l.starts_with(backend))
            .unwrap_or_else(|| panic!("no {backend} row in\n{table}"));
        // embree 1.23 ms 0.456 s 0.90 s 162486 0.356 M
        let f: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(f.len(), 10, "{line}");
        assert!(f[5].parse::<f64>().unwrap() >= 0.0, "{line}");
        assert!(f[7].parse::<u64>().unwrap() > 1000, "{line}");
        assert!(f[8].parse::<f64>().unwrap() > 0.0, "{line}");
    }
    let ratio = table
        .lines()
        .find_map(|l| l.strip_prefix("speed ratio rust/embree: "))
        .unwrap_or_else(|| panic!("no speed ratio in\n{table}"));
    let ratio: f64 = ratio.split_whitespace().next().unwrap().parse().unwrap();
    assert!(ratio > 0.0 && ratio.is_finite(), "{table}");
    assert!(table.contains("CPU time ratio rust/embree: "), "{table}");
    // The image rows: the raw film and each mode, over all 32×32 pixels.
    let (mut differing, mut unequal) = (0, 0);
    for name in ["raw (Stokes sums)", "color", "dop"] {
        let (max_abs, rmse, n, of, ne) = image_row(&table, name);
        assert_eq!(of, 1024, "{table}");
        assert!(n <= ne && ne <= of, "{table}");
        assert!(rmse <= max_abs && max_abs >= 0.0, "{table}");
        assert_eq!(ne == 0, max_abs == 0.0, "{table}");
        // Both backends find the same triangles but for rays within ~1e-6
        // of an edge: a handful of pixels at most.
        assert!(n <= 20, "{table}");
        differing += n;
        unequal += ne;
    }
    let verdict = table
        .lines()
        .find_map(|l| l.strip_prefix("verdict: "))
        .unwrap_or_else(|| panic!("no verdict in\n{table}"));
    assert_eq!(
        differing == 0,
        verdict.starts_with("identical"),
        "verdict disagrees with the counts:\n{table}"
    );
    assert_eq!(
        unequal == 0,
        verdict.starts_with("identical: the images are the same bit for bit"),
        "{table}"
    );
    // One difference image per mode, relative differences on a log scale
    // (1e-6 relative is grey 1/7): as many bright pixels as the table
    // counts, give or take those within a grey level of 1e-6.
    for mode in ["color", "dop"] {
        let img = spar::image::read(&dir.path().join(format!("d-{mode}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (32, 32));
        assert_eq!(img.metadata()["spar:mode"], mode);
        assert_eq!(img.metadata()["spar:compare"], "embree vs rust");
        let (_, _, n, _, _) = image_row(&table, mode);
        let r = img.channel("R").unwrap();
        let above = |level: f32| r.iter().filter(|&&v| v > level).count();
        assert!(above(38.0 / 255.0) <= n, "{mode}: {table}");
        assert!(above(35.0 / 255.0) >= n, "{mode}: {table}");
    }

    // An EXR difference image holds the absolute differences: its largest
    // value is the table's max abs.
    let (code, table, err) = spar(
        &[
            "compare",
            scene.to_str().unwrap(),
            "--resolution",
            "16x16",
            "--mode",
            "stokes",
            "--repeat",
            "2",
            "-o",
            "d.exr",
        ],
        dir.path(),
    );
    assert_eq!(code, 0, "{table}{err}");
    assert!(table.contains("best of 2"), "{table}");
    let (max_abs, _, _, of, _) = image_row(&table, "stokes");
    assert_eq!(of, 256);
    let img = spar::image::read(&dir.path().join("d.exr")).unwrap();
    let max = img.data().iter().fold(0.0f64, |m, &v| m.max(v as f64));
    assert!(
        (max - max_abs).abs() <= 1e-3 * max_abs,
        "{max} vs {max_abs}\n{table}"
    );
}

#[cfg(feature = "native")]
#[test]
fn compare_backend_only_sends_every_ray_to_the_backends() {
    let dir = tempfile::tempdir().unwrap();
    let scene = glass();
    let args = |extra: &[&'static str]| {
        let mut a = vec![
            "compare",
            scene.to_str().unwrap(),
            "--resolution",
            "16x16",
            "--threads",
            "1",
            "-q",
            "-o",
            "d.png",
        ];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<String>>()
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(|s| s.as_str()).collect();
        spar(&a, dir.path())
    };
    let (code, table, err) = run(args(&["--backend-only"]));
    assert_eq!(code, 0, "{table}{err}");
    assert!(
        table.contains("rays inside convex stones: traced by the backends (--backend-only)"),
        "{table}"
    );
    // The same rays either way (the planes and the triangles agree).
    let rays = |t: &str| -> Vec<u64> {
        t.lines()
            .filter(|l| l.starts_with("embree") || l.starts_with("rust"))
            .map(|l| l.split_whitespace().nth(7).unwrap().parse().unwrap())
            .collect()
    };
    let (code, default, err) = run(args(&[]));
    assert_eq!(code, 0, "{default}{err}");
    assert_eq!(rays(&table), rays(&default), "{table}\n{default}");
}

#[cfg(feature = "native")]
#[test]
fn compare_refuses_bad_input_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let scene = glass();
    let scene = scene.to_str().unwrap();
    for (args, expect) in [
        (vec!["compare", scene, "-o", "d.tif"], "d.tif"),
        (
            vec!["compare", scene, "-o", "no/such/d.png"],
            "does not exist",
        ),
        (vec!["compare", "missing.toml"], "missing.toml"),
        (vec!["compare", scene, "--samples", "0..1"], "sample block"),
    ] {
        let (code, out, err) = spar(&args, dir.path());
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(err.contains(expect), "{args:?}: {err}");
    }
}
