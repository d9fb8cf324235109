//! `spar interface`: the JSON output parses and equals the library's answer
//! for the same inputs; bad arguments exit with status 2 and a message.

use crate::support::run;
use glam::DVec3;
use spar::material::Material;
use spar::optics::{Interface, Mode, Side};

fn spar(args: &[&str]) -> std::process::Output {
    run::spar_in(None, &[&["interface"], args].concat())
}

fn vec3(v: &serde_json::Value) -> DVec3 {
    let a = v.as_array().expect("array");
    assert_eq!(a.len(), 3);
    DVec3::new(
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    )
}

/// Run `--json` and compare every wave with the library call.
#[allow(clippy::too_many_arguments)]
fn check_against_library(
    from: &str,
    to: &str,
    axis: DVec3,
    normal: DVec3,
    incident: DVec3,
    mode: &str,
    lambda: f64,
) {
    let f = |v: DVec3| format!("{},{},{}", v.x, v.y, v.z);
    let (axis_s, normal_s, inc_s, lambda_s) = (f(axis), f(normal), f(incident), lambda.to_string());
    let out = spar(&[
        "--from",
        from,
        "--to",
        to,
        "--axis",
        &axis_s,
        "--normal",
        &normal_s,
        "--incident",
        &inc_s,
        "--mode",
        mode,
        "--wavelength",
        &lambda_s,
        "--json",
    ]);
    assert!(
        out.status.success(),
        "spar failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        text.trim().lines().count(),
        1,
        "exactly one JSON line: {text}"
    );
    let doc: serde_json::Value = serde_json::from_str(text.trim()).expect("valid JSON");

    let m_from = Material::parse(from).unwrap().medium(lambda, axis);
    let m_to = Material::parse(to).unwrap().medium(lambda, axis);
    let iface = Interface::new(normal, m_from, m_to).unwrap();
    let sc = iface
        .solve_direction(Side::Plus, Mode::parse(mode).unwrap(), incident)
        .unwrap();

    let waves = doc["waves"].as_array().expect("waves");
    assert_eq!(waves.len(), 4);
    for (w, o) in waves.iter().zip(&sc.outgoing) {
        let side = if o.wave.side == Side::Plus {
            "reflected"
        } else {
            "transmitted"
        };
        assert_eq!(w["side"], side);
        assert_eq!(w["mode"], o.wave.mode.name());
        assert_eq!(w["evanescent"], o.wave.evanescent);
        // serde_json prints the shortest representation that round-trips,
        // but its default parser may land 1 ulp away (without its
        // `float_roundtrip` feature): compare to 2 ulp.
        let ulp2 = |x: f64| 4.5e-16 * x.abs().max(1e-300);
        let (k, r) = (vec3(&w["k"]), vec3(&w["ray"]));
        for (a, b) in [(k, o.wave.k.re), (r, o.wave.ray)] {
            for i in 0..3 {
                assert!((a[i] - b[i]).abs() <= ulp2(b[i]), "{a} vs {b}");
            }
        }
        let e = w["energy"].as_f64().unwrap();
        assert!(
            (e - o.energy).abs() <= ulp2(o.energy),
            "{e} vs {}",
            o.energy
        );
        let keys: Vec<&String> = w.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 6, "{keys:?}");
    }
    let sum = doc["energy_sum"].as_f64().unwrap();
    assert!((sum - sc.energy_sum()).abs() <= 4.5e-16);
    assert!((sum - 1.0).abs() < 1e-12);
    assert_eq!(doc.as_object().unwrap().len(), 2);
}

#[test]
fn json_matches_the_library_air_to_glass() {
    check_against_library(
        "air",
        "n-bk7",
        DVec3::Z,
        DVec3::Z,
        DVec3::new(1.0, 0.0, -1.0),
        "s",
        587.6,
    );
    check_against_library(
        "air",
        "iso:1.5",
        DVec3::Z,
        DVec3::Z,
        DVec3::new(0.3, 0.2, -1.0),
        "p",
        589.3,
    );
}

#[test]
fn json_matches_the_library_total_internal_reflection() {
    check_against_library(
        "n-bk7",
        "air",
        DVec3::Z,
        DVec3::Z,
        DVec3::new(1.0, 0.0, -1.0),
        "p",
        589.3,
    );
}

#[test]
fn json_matches_the_library_crystals() {
    let axis = DVec3::new(0.0, 1.0, 1.0);
    let normal = DVec3::new(0.1, -0.2, 1.0);
    check_against_library(
        "calcite",
        "air",
        axis,
        normal,
        DVec3::new(0.3, 0.0, -1.0),
        "e",
        589.3,
    );
    check_against_library(
        "air",
        "calcite",
        axis,
        normal,
        DVec3::new(0.3, 0.5, -1.0),
        "s",
        500.0,
    );
    check_against_library(
        "quartz",
        "calcite",
        axis,
        normal,
        DVec3::new(-0.4, 0.1, -1.0),
        "o",
        650.0,
    );
    check_against_library(
        "uniaxial:1.6584:1.4864",
        "iso:1.0",
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::Z,
        DVec3::Z * -1.0,
        "e",
        589.3,
    );
}

#[test]
fn table_output_by_default() {
    let out = spar(&[
        "--from",
        "air",
        "--to",
        "calcite",
        "--incident",
        "1,0,-1",
        "--mode",
        "p",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("energy sum"), "{text}");
    assert!(
        text.contains("reflected") && text.contains("transmitted"),
        "{text}"
    );
}

#[test]
fn bad_arguments_exit_2_with_a_message() {
    let base = [
        "--from",
        "air",
        "--to",
        "calcite",
        "--incident",
        "1,0,-1",
        "--mode",
        "s",
    ];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--incident", "0,0,0"], "non-zero"),
        (vec!["--incident", "nan,0,-1"], "finite"),
        (vec!["--incident", "1,0"], "three numbers"),
        (vec!["--incident", "1,0,1"], "points away"),
        (vec!["--incident", "1,0,0"], "points away"),
        (vec!["--normal", "0,0,0"], "non-zero"),
        (vec!["--normal", "inf,0,1"], "finite"),
        (vec!["--axis", "0,0,0"], "non-zero"),
        (vec!["--from", "unobtainium"], "unknown material"),
        (vec!["--to", "iso:-1"], "positive"),
        (vec!["--mode", "x"], "expected s, p, o or e"),
        (vec!["--mode", "o"], "isotropic"),
        (vec!["--mode", "e"], "isotropic"),
        (vec!["--wavelength", "-5"], "wavelength"),
        (vec!["--wavelength", "NaN"], "wavelength"),
    ];
    for (overrides, needle) in cases {
        let mut args: Vec<&str> = base.to_vec();
        for pair in overrides.chunks(2) {
            match args.iter().position(|a| *a == pair[0]) {
                Some(i) => args[i + 1] = pair[1],
                None => args.extend_from_slice(pair),
            }
        }
        let out = spar(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: expected `{needle}` in: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing on stdout");
    }
    // s/p in a crystal.
    let out = spar(&[
        "--from",
        "calcite",
        "--to",
        "air",
        "--incident",
        "0,0,-1",
        "--mode",
        "s",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("uniaxial crystal"));
    // Missing required flag (clap's usage error is also status 2).
    let out = spar(&["--from", "air", "--to", "calcite", "--mode", "s"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn biaxial_media_by_name_with_both_axes() {
    // Topaz-like constant indices, crystal z tilted and x set by --axis-x:
    // the solve conserves energy and the table reports the crystal axes
    // (x orthogonalized against z) and 2V.
    let args = [
        "--from",
        "biaxial:1.6093:1.6116:1.6194",
        "--to",
        "air",
        "--axis",
        "0,1,1",
        "--axis-x",
        "1,0,0.5",
        "--incident",
        "0.2,0.1,-1",
        "--mode",
        "slow",
    ];
    let mut json = args.to_vec();
    json.push("--json");
    let out = spar(&json);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sum = doc["energy_sum"].as_f64().unwrap();
    assert!((sum - 1.0).abs() < 1e-9, "energy sum {sum}");
    let out = spar(&args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("biaxial, n_x = 1.609300"), "{text}");
    assert!(text.contains("z = (0.0000, 0.7071, 0.7071)"), "{text}");
    // (1, 0, 0.5) less its part along z: (1, −0.25, 0.25)/√1.125.
    assert!(
        text.contains("crystal x = (0.9428, -0.2357, 0.2357)"),
        "{text}"
    );
    assert!(text.contains("2V = "), "{text}");
    // Bad biaxial input: exit 2 with a message naming the flag.
    let cases: [(&[&str], &str); 4] = [
        (
            &["--axis", "1,0,0", "--axis-x", "2,0,0"],
            "--axis-x `2,0,0` is parallel",
        ),
        (
            &["--axis-x", "0,0,0"],
            "--axis-x `0,0,0` must be a non-zero",
        ),
        (&["--from", "biaxial:1.6:1.7"], "biaxial:NX:NY:NZ"),
        (&["--mode", "o"], "biaxial crystal: use --mode fast or slow"),
    ];
    for (overrides, needle) in cases {
        let mut a: Vec<&str> = args.to_vec();
        for pair in overrides.chunks(2) {
            match a.iter().position(|x| *x == pair[0]) {
                Some(i) => a[i + 1] = pair[1],
                None => a.extend_from_slice(pair),
            }
        }
        let out = spar(&a);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{a:?}: {err}");
        assert!(err.contains(needle), "{a:?}: `{needle}` not in {err}");
        assert!(!err.contains("panicked"), "{a:?}: {err}");
    }
}

#[test]
fn biaxial_axis_alone_takes_a_default_x_orthogonal_to_it() {
    // `--axis 1,0,0` alone: z along x, so the default x is +y (not +x,
    // which is parallel); the result equals giving `--axis-x 0,1,0`.
    // Along +z the default stays +x. Only a given --axis-x parallel to
    // --axis is refused (exit 2, naming both flags).
    let base = [
        "--from",
        "air",
        "--to",
        "biaxial:1.6093:1.6116:1.6194",
        "--incident",
        "0.3,0.2,-1",
        "--mode",
        "s",
        "--json",
    ];
    for (axis, default_x) in [
        ("1,0,0", "0,1,0"),
        ("-0.9,0.1,0.3", "0,1,0"),
        ("0,0.6,0.8", "1,0,0"),
    ] {
        let mut alone = base.to_vec();
        alone.extend_from_slice(&["--axis", axis]);
        let mut both = alone.clone();
        both.extend_from_slice(&["--axis-x", default_x]);
        let (a, b) = (spar(&alone), spar(&both));
        assert_eq!(
            a.status.code(),
            Some(0),
            "{axis}: {}",
            String::from_utf8_lossy(&a.stderr)
        );
        assert_eq!(b.status.code(), Some(0));
        assert_eq!(
            a.stdout, b.stdout,
            "--axis {axis} alone differs from --axis-x {default_x}"
        );
    }
    let mut bad = base.to_vec();
    bad.extend_from_slice(&["--axis", "0,0,2", "--axis-x", "0,0,-1"]);
    let out = spar(&bad);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--axis-x `0,0,-1` is parallel to --axis `0,0,2`"),
        "{err}"
    );
}

#[test]
fn extraordinary_wave_whose_energy_leaves_is_rejected() {
    // Calcite, axis 45° in the x–z plane, interface normal +z. A wave vector
    // just below the interface plane (k·N < 0) whose ray has S·N > 0 (the
    // walk-off tilts the ray by up to 6° across the plane): not incident.
    let out = spar(&[
        "--from",
        "uniaxial:1.6584:1.4864",
        "--to",
        "air",
        "--axis",
        "1,0,1",
        "--incident",
        "-1,0,-0.01",
        "--mode",
        "e",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("energy flows away"), "{err}");
}

/// `air` in `spar interface` is the air renders put around every object
/// (issue 16 item 5): n = 1 exactly, so air → N-BK7 at normal incidence
/// reflects ((n − 1)/(n + 1))² of the light, n N-BK7's index there (with
/// Ciddor's air, n = 1.00028, it would be 0.1 % less); standard air is
/// `standard-air`.
#[test]
fn air_is_the_air_renders_use() {
    let run = |from: &str| {
        let out = spar(&[
            "--from",
            from,
            "--to",
            "n-bk7",
            "--incident",
            "0,0,-1",
            "--mode",
            "s",
            "--json",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        doc["waves"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["side"] == "reflected")
            .map(|w| w["energy"].as_f64().unwrap())
            .sum::<f64>()
    };
    let n = spar::material::catalog::n_bk7().indices(589.3).0;
    let want = ((n - 1.0) / (n + 1.0)).powi(2);
    let air = run("air");
    assert!(
        (air - want).abs() < 1e-12,
        "air: R = {air}, n = 1 gives {want}"
    );
    assert_eq!(run("vacuum"), air);
    let standard = run("standard-air");
    assert!(
        (standard - want).abs() > 1e-5,
        "standard air (n − 1 = 2.8e-4) reflects less: {standard} vs {want}"
    );
    // The table names the index it used.
    let out = spar(&[
        "--from",
        "air",
        "--to",
        "n-bk7",
        "--incident",
        "0,0,-1",
        "--mode",
        "s",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("air (isotropic, n = 1.000000)"), "{text}");
}

/// The built-in biaxial gems by name (`--help` gives topaz as an example):
/// the table reports the principal indices along crystal x, y, z and 2V,
/// the solve conserves energy, and the help text's example exists.
#[test]
fn biaxial_gems_by_name_report_2v() {
    for (name, indices, two_v) in [
        (
            "topaz",
            "n_x = 1.606000, n_y = 1.609000, n_z = 1.616000",
            "2V = 66.6",
        ),
        ("chrysoberyl", "n_x = 1.7407", "2V = 61.1"),
        ("tanzanite", "n_x = 1.692000", "2V = 41.5"),
        ("iolite", "n_x = 1.530000", "2V = 83.87"),
    ] {
        let args = [
            "--from",
            "air",
            "--to",
            name,
            "--axis",
            "0,1,1",
            "--incident",
            "0.3,0.1,-1",
            "--mode",
            "s",
        ];
        let out = spar(&args);
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(text.contains(&format!("to   {name} (biaxial, ")), "{text}");
        assert!(text.contains(indices), "{name}: {text}");
        assert!(text.contains(two_v), "{name}: {text}");
        let mut json = args.to_vec();
        json.push("--json");
        let doc: serde_json::Value = serde_json::from_slice(&spar(&json).stdout).unwrap();
        let sum = doc["energy_sum"].as_f64().unwrap();
        assert!((sum - 1.0).abs() < 1e-9, "{name}: energy sum {sum}");
    }
    let help = run::spar_in(None, &["interface", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("topaz"), "{help}");
}

/// `spar interface --describe MEDIUM` (issue 17): one medium, no interface.
/// For topaz oriented by --axis and --axis-x it prints the indices, 2V and
/// the two optic axes; the angle between the printed axes is 2V as the tan
/// form gives it from the printed indices (tan²V_z = (1/n_α² − 1/n_β²) /
/// (1/n_β² − 1/n_γ²), computed here), and both lie in the crystal's x–z
/// plane. Bad input exits 2 naming the flag, with nothing on stdout.
#[test]
fn describe_reports_a_medium_its_2v_and_its_optic_axes() {
    let out = spar(&[
        "--describe",
        "topaz",
        "--axis",
        "0,1,1",
        "--axis-x",
        "1,0,0",
    ]);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("topaz (biaxial, n_x = 1.606000, n_y = 1.609000, n_z = 1.616000"),
        "{text}"
    );
    let axes: Vec<DVec3> = text
        .lines()
        .filter_map(|l| l.strip_prefix("optic axis "))
        .map(|l| {
            let inner = l.split_once('(').unwrap().1.trim_end_matches(')');
            let v: Vec<f64> = inner
                .split(',')
                .map(|x| x.trim().parse().unwrap())
                .collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect();
    assert_eq!(axes.len(), 2, "{text}");
    let [a, b, g] = [1.606f64, 1.609, 1.616].map(|n| 1.0 / (n * n));
    let v_z = ((a - b) / (b - g)).sqrt().atan();
    let between = axes[0].angle_between(axes[1]);
    assert!(
        (between - 2.0 * v_z).abs() < 1e-4,
        "{between} vs 2V {}",
        2.0 * v_z
    );
    assert!(
        text.contains(&format!("2V = {:.3}°", 2.0 * v_z.to_degrees())),
        "{text}"
    );
    // Crystal y = z × x = (0, 1, −1)/√2 is normal to both optic axes.
    let y = DVec3::new(0.0, 1.0, 1.0).cross(DVec3::X).normalize();
    for ax in &axes {
        assert!(
            ax.dot(y).abs() < 1e-4 && (ax.length() - 1.0).abs() < 1e-4,
            "{ax}"
        );
    }
    // An isotropic or uniaxial medium has no 2V line and no optic axes list.
    let out = spar(&["--describe", "calcite"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("calcite (uniaxial, n_o = 1.658") && !text.contains("optic axis 1"),
        "{text}"
    );
    for (args, says) in [
        (
            &["--describe", "nope"][..],
            "--describe: unknown material `nope`",
        ),
        (
            &["--describe", "topaz", "--from", "air"][..],
            "cannot be used with",
        ),
        (
            &["--describe", "topaz", "--wavelength", "-3"][..],
            "--wavelength",
        ),
        (
            &[
                "--describe",
                "topaz",
                "--axis",
                "1,0,0",
                "--axis-x",
                "2,0,0",
            ][..],
            "parallel",
        ),
    ] {
        let out = spar(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}
