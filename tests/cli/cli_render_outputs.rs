//! `spar render` outputs: several modes in one run, the Stokes EXR read back
//! by channel name with its settings in the metadata, and values a direct
//! view of a light must have.

use std::process::Command;

const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [6, 4]
[render]
wavelengths = [450.0, 550.0, 650.0]
[[light]]
corners = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]]
polarization = { linear = [0.0, 1.0, 0.0] }
"#;

/// `spar render s.toml ARGS` in `dir`, which must succeed: its stderr.
fn render_ok(dir: &std::path::Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_spar"))
        .args(["render", "s.toml"])
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{stderr}");
    stderr
}

#[test]
fn stokes_exr_reads_back_by_name_with_metadata_and_physical_values() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), SCENE).unwrap();
    render_ok(
        dir.path(),
        &["--mode", "stokes,dop,color", "-o", "out.png", "-q"],
    );
    for f in ["out-stokes.exr", "out-dop.png", "out-color.png"] {
        assert!(dir.path().join(f).exists(), "{f} missing");
    }
    let exr = spar::image::read(&dir.path().join("out-stokes.exr")).unwrap();
    assert_eq!((exr.width(), exr.height()), (6, 4));
    assert!(exr
        .metadata()
        .get("spar:settings")
        .is_some_and(|s| s.contains("resolution=6x4")));
    assert_eq!(
        exr.metadata().get("spar:mode").map(String::as_str),
        Some("stokes")
    );
    for l in [450.0f64, 550.0, 650.0] {
        let get = |c: u32| exr.channel(&format!("S{c}.{l:.0}nm")).unwrap();
        let (s0, s1, s2, s3) = (get(0), get(1), get(2), get(3));
        // A polarizer along image up: half of D65, fully polarized, S1 = −S0
        // (vertical), no S2 or S3 on the optical axis; off axis the frame
        // turns a little, so check the pixel mean.
        let d65 = spar::spectrum::cie::d65(l) as f32;
        let n = s0.len() as f32;
        let mean = |v: &[f32]| v.iter().sum::<f32>() / n;
        assert!(
            (mean(&s0) - 0.5 * d65).abs() < 1e-4 * d65,
            "S0 at {l}: {} vs {}",
            mean(&s0),
            0.5 * d65
        );
        assert!(
            (mean(&s1) + 0.5 * d65).abs() < 1e-3 * d65,
            "S1 at {l}: {}",
            mean(&s1)
        );
        assert!(mean(&s2).abs() < 1e-3 * d65 && mean(&s3).abs() < 1e-6 * d65);
    }
    // The DoP map of fully polarized light is white.
    let dop = spar::image::read(&dir.path().join("out-dop.png")).unwrap();
    assert!(dop.channel("R").unwrap().iter().all(|&v| v > 0.99));
}

#[test]
fn colour_on_the_first_samples_says_when_the_other_samples_trace_nothing() {
    // `all/2` with colour alone: samples 3 and 4 of 4 trace nothing, which
    // is said; beside dop they trace 580 nm, and nothing is said.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), SCENE).unwrap();
    let run = |modes: &str| {
        let args = [
            "--mode",
            modes,
            "--spectral",
            "all/2",
            "--samples",
            "4",
            "-o",
            "o.png",
        ];
        render_ok(dir.path(), &args)
    };
    let alone = run("color");
    assert!(
        alone.contains("note: s.toml: spectral = all/2 traces colour on 2 of 4 samples"),
        "{alone}"
    );
    let beside = run("color,dop");
    assert!(!beside.contains("trace nothing"), "{beside}");
}
