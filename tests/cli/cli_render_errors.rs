//! Bad input to `spar render`: a clear message naming the file, the line
//! and the field, exit status 2, no output file, never a panic.

use crate::support::run;
use std::path::Path;

fn spar(args: &[&str], dir: &Path) -> (i32, String) {
    let (code, _, err) = run::code_out_err(&run::spar(dir, args));
    (code, err)
}

const GOOD: &str = r#"
[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [8, 8]

[[object]]
mesh = "builtin:trichecker12"
medium = "n-bk7"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

/// Each case: a replacement applied to GOOD, and what the message must say.
fn cases() -> Vec<(&'static str, &'static str, Vec<&'static str>)> {
    vec![
        (
            "fov = 30.0",
            "fov = 200.0",
            vec!["scene.toml:", "field of view"],
        ),
        (
            "medium = \"n-bk7\"",
            "medium = \"unobtainium\"",
            vec!["scene.toml:10:", "object[0].medium", "unknown material"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [0, 8]",
            vec!["scene.toml:6:", "camera.resolution"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nlens = 3",
            vec!["scene.toml:7", "lens"],
        ),
        (
            "mesh = \"builtin:trichecker12\"",
            "mesh = \"missing.obj\"",
            vec!["scene.toml:9:", "object[0].mesh", "missing.obj"],
        ),
        (
            "mesh = \"builtin:trichecker12\"",
            "mesh = \"open.obj\"",
            vec!["object[0].mesh", "open.obj"],
        ),
        (
            "mesh = \"builtin:trichecker12\"",
            "mesh = \"bad.obj\"",
            vec!["bad.obj:2:"],
        ),
        (
            "mesh = \"builtin:trichecker12\"",
            "cut = { name = \"trillion\" }",
            vec!["scene.toml:9:", "object[0].cut"],
        ),
        (
            "medium = \"n-bk7\"",
            "medium = \"n-bk7\"\noptic_axis = [0.0, 0.0, 1.0]",
            vec!["scene.toml:11:", "optic_axis", "isotropic"],
        ),
        (
            "[2.0, 2.0, -1.5], [-2.0",
            "[2.0, 3.0, -1.5], [-2.0",
            vec!["scene.toml:13:", "light[0].corners"],
        ),
        (
            "[[light]]",
            "[[light]]\ntexture = \"nothere.png\"",
            vec!["scene.toml:13:", "light[0].texture", "nothere.png"],
        ),
        (
            "[[light]]",
            "[[light]]\ntexture = \"garbage.png\"",
            vec!["light[0].texture", "garbage.png"],
        ),
        (
            "[[light]]",
            "[[light]]\npolarization = \"sideways\"",
            vec!["scene.toml:13:", "light[0].polarization"],
        ),
        (
            "eye = [0.0, -3.0, 2.0]",
            "eye = [0.0, -3.0]",
            vec!["scene.toml:3:"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\nbranching = \"sometimes\"",
            vec!["scene.toml:9:", "render.branching", "hybrid:K"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\nspectral = \"hero:0\"",
            vec!["scene.toml:9:", "render.spectral", "K ≥ 1"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\npolarization = \"half\"",
            vec!["scene.toml:9:", "render.polarization"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\ndispersion = \"bands:0\"",
            vec!["scene.toml:9:", "render.dispersion", "bands:K"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\ndispersion = 3",
            vec!["scene.toml:9:", "render.dispersion", "bands:K"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\ncoherence = \"partial\"",
            vec!["scene.toml:9:", "render.coherence", "incoherent"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\n\n[render]\nunits = \"furlong\"",
            vec!["scene.toml:9:", "render.units", "nm, um (or µm), mm, cm or m"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nprojection = \"fisheye\"",
            vec!["scene.toml:7:", "camera.projection", "orthographic"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nprojection = \"orthographic\"",
            vec!["scene.toml:2:", "camera.width", "needs `width`"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nprojection = \"orthographic\"\nwidth = -1.0",
            vec!["scene.toml:8:", "camera.width", "> 0"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nwidth = 2.0",
            vec!["scene.toml:7:", "camera.width", "orthographic"],
        ),
        (
            "fov = 30.0\n",
            "",
            vec!["scene.toml:2:", "missing field `fov`"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nanalyzer = { linear = nan }",
            vec!["scene.toml:7:", "camera.analyzer.linear", "finite"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nanalyzer = { retarder = { fast_axis = 0.0, retardance = 90.0 }, then = { linear = inf } }",
            vec!["scene.toml:7:", "camera.analyzer.then.linear", "finite"],
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8]\nanalyzer = { circular = 1.0 }",
            vec!["scene.toml:7:", "circular"],
        ),
        (
            "[[light]]",
            "[[light]]\ndirection = [0.0, 0.0, -1.0]",
            vec!["scene.toml:12:", "light[0]", "exactly one of `corners`"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "direction = [0.0, 0.0, 0.0]",
            vec!["scene.toml:13:", "light[0].direction", "non-zero"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "direction = [0.0, 0.0, -1.0]\nangular_diameter = 200.0",
            vec!["scene.toml:14:", "light[0].angular_diameter", "180"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "direction = [0.0, 0.0, -1.0]\ntexture = \"builtin:checker\"",
            vec!["scene.toml:14:", "light[0].texture", "corners"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "direction = [0.0, 0.0, -1.0]\npolarization = { linear = [0.0, 0.0, 1.0] }",
            vec!["scene.toml:14:", "light[0].polarization.linear", "perpendicular"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "environment = \"uniform\"\npolarization = { linear = [1.0, 0.0, 0.0] }",
            vec!["scene.toml:14:", "light[0].polarization", "unpolarized"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "environment = \"missing.exr\"",
            vec!["scene.toml:13:", "light[0].environment", "missing.exr"],
        ),
        (
            "corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]",
            "environment = \"uniform\"\n\n[background]\nradiance = 1.0",
            vec!["scene.toml:16:", "background.radiance", "give one"],
        ),
        (
            "[[light]]",
            "[[light]]\nenvironment = \"uniform\"\n[[light]]\nenvironment = \"uniform\"\n[[light]]",
            vec!["scene.toml:15:", "light[1].environment", "at most one environment"],
        ),
    ]
}

#[test]
fn bad_scenes_exit_2_with_file_line_and_field_and_leave_no_output() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("open.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("bad.obj"),
        "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("garbage.png"), b"this is not a png").unwrap();
    // The good scene renders.
    std::fs::write(dir.path().join("scene.toml"), GOOD).unwrap();
    let (code, err) = spar(
        &["render", "scene.toml", "-q", "-o", "good.png"],
        dir.path(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(dir.path().join("good.png").exists());
    for (from, to, expect) in cases() {
        assert!(GOOD.contains(from), "{from}");
        std::fs::write(dir.path().join("scene.toml"), GOOD.replacen(from, to, 1)).unwrap();
        let (code, err) = spar(&["render", "scene.toml", "-q", "-o", "out.png"], dir.path());
        assert_eq!(code, 2, "{to}: exit {code}, {err}");
        for e in expect {
            assert!(err.contains(e), "{to}: message lacks `{e}`: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            !dir.path().join("out.png").exists(),
            "{to}: an output file was left"
        );
    }
}

#[test]
fn bad_flags_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["render", "--mode", "sepia"],
        vec!["render", "--resolution", "12"],
        vec!["render", "--samples", "0"],
        vec!["render", "--prune", "-1"],
        vec!["render", "--wavelength", "1200"],
        vec!["render", "--wavelengths", "2"],
        vec!["render", "--branching", "sometimes"],
        vec!["render", "--spectral", "hero:0"],
        vec!["render", "--polarization", "half"],
        vec!["render", "--dispersion", "maybe"],
        vec!["render", "--coherence", "partial"],
        vec!["render", "--quality", "best"],
        vec!["render", "-o", "no/such/dir/x.png"],
        vec!["render", "no-such-scene.toml"],
    ] {
        let (code, err) = spar(&args, dir.path());
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "a bad run left a file"
    );
}
