//! Every fixed-length array of a scene file takes exactly its length: a
//! 4-vector where 3 coordinates go (once read as its first three, the
//! fourth dropped), a 3-vector resolution, a fifth corner — each refused
//! with file:line, the field and the count given. In process, through the
//! scene loader.

use spar::scene::Scene;
use std::path::Path;

const GOOD: &str = r#"[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov = 30.0
resolution = [8, 8]

[[object]]
mesh = "builtin:trichecker12"
medium = "calcite"
optic_axis = [0.0, 0.0, 1.0]
transform = { scale = [1.0, 1.0, 1.0], rotate = [0.0, 0.0, 0.0], translate = [0.0, 0.0, 0.0] }

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
polarization = { linear = [1.0, 0.0, 0.0] }

[[light]]
corners = [[-2.0, -2.0, 5.0], [2.0, -2.0, 5.0], [2.0, 2.0, 5.0], [-2.0, 2.0, 5.0]]
polarization = { calcite_plate = { keep = "o", axis = [1.0, 0.0, 0.0] } }
"#;

fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "s.toml", Path::new(".")).map_err(|e| e.to_string())
}

#[test]
fn every_vector_field_takes_exactly_its_length() {
    parse(GOOD).expect("the good scene loads");
    // (text in GOOD, its replacement, line, field, count given, length).
    let cases = [
        (
            "eye = [0.0, -3.0, 2.0]",
            "eye = [0.0, -3.0, 2.0, 7.0]",
            2,
            "camera.eye",
            4,
            3,
        ),
        (
            "look_at = [0.0, 0.0, 0.0]",
            "look_at = [0.0, 0.0, 0.0, 1.0]",
            3,
            "camera.look_at",
            4,
            3,
        ),
        (
            "up = [0.0, 0.0, 1.0]",
            "up = [0.0, 0.0, 1.0, 1.0]",
            4,
            "camera.up",
            4,
            3,
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8, 8, 8]",
            6,
            "camera.resolution",
            3,
            2,
        ),
        (
            "resolution = [8, 8]",
            "resolution = [8]",
            6,
            "camera.resolution",
            1,
            2,
        ),
        (
            "optic_axis = [0.0, 0.0, 1.0]",
            "optic_axis = [0.0, 0.0, 1.0, 0.0]",
            11,
            "object.optic_axis",
            4,
            3,
        ),
        (
            "scale = [1.0, 1.0, 1.0]",
            "scale = [1.0, 1.0, 1.0, 2.0]",
            12,
            "object.transform.scale",
            4,
            3,
        ),
        (
            "rotate = [0.0, 0.0, 0.0]",
            "rotate = [0.0, 0.0, 0.0, 9.0]",
            12,
            "object.transform.rotate",
            4,
            3,
        ),
        (
            "translate = [0.0, 0.0, 0.0]",
            "translate = [0.0, 0.0, 0.0, 1.0]",
            12,
            "object.transform.translate",
            4,
            3,
        ),
        (
            "[-2.0, -2.0, -1.5], [2.0",
            "[-2.0, -2.0, -1.5, 1.0], [2.0",
            15,
            "light.corners (one corner)",
            4,
            3,
        ),
        (
            "[-2.0, 2.0, -1.5]]",
            "[-2.0, 2.0, -1.5], [0.0, 0.0, 0.0]]",
            15,
            "light.corners",
            5,
            4,
        ),
        (
            "linear = [1.0, 0.0, 0.0]",
            "linear = [1.0, 0.0, 0.0, 1.0]",
            16,
            "light.polarization.linear",
            4,
            3,
        ),
        (
            "axis = [1.0, 0.0, 0.0]",
            "axis = [1.0, 0.0, 0.0, 0.0]",
            20,
            "light.polarization.calcite_plate.axis",
            4,
            3,
        ),
    ];
    for (from, to, line, field, given, len) in cases {
        assert!(GOOD.contains(from), "{from}");
        let text = GOOD.replacen(from, to, 1);
        let err = parse(&text)
            .err()
            .unwrap_or_else(|| panic!("`{to}` was accepted"));
        let want =
            format!("s.toml:{line}: {field}: {given} value(s) given, it takes exactly {len}");
        assert!(
            err.contains(&want),
            "`{to}`: expected `{want}`, got `{err}`"
        );
    }
    // Scale also takes one number; a wrong type says what it takes.
    parse(&GOOD.replacen("scale = [1.0, 1.0, 1.0]", "scale = 2.0", 1)).expect("uniform scale");
    let err = parse(&GOOD.replacen("scale = [1.0, 1.0, 1.0]", "scale = \"big\"", 1)).unwrap_err();
    assert!(
        err.contains("s.toml:12:") && err.contains("object.transform.scale"),
        "{err}"
    );
    let err = parse(&GOOD.replacen(
        "polarization = { linear = [1.0, 0.0, 0.0] }",
        "polarization = 3",
        1,
    ))
    .unwrap_err();
    assert!(
        err.contains("s.toml:16:") && err.contains("light.polarization"),
        "{err}"
    );
    parse(&GOOD.replacen(
        "polarization = { linear = [1.0, 0.0, 0.0] }",
        "polarization = \"unpolarized\"",
        1,
    ))
    .expect("a named polarization");
}

#[test]
fn wavelength_counts_are_bounded_before_any_list_is_built() {
    let with = |w: &str| {
        GOOD.replacen(
            "[[object]]",
            &format!("[render]\nwavelengths = {w}\n\n[[object]]"),
            1,
        )
    };
    parse(&with("8")).expect("8 wavelengths");
    for (w, says) in [
        ("4000000000", "4000000000 wavelengths: at most 10000"),
        ("10001", "10001 wavelengths: at most 10000"),
        ("-3", "-3: a count of wavelengths is at least 1"),
    ] {
        let err = parse(&with(w)).unwrap_err();
        assert!(
            err.contains("s.toml:9:") && err.contains(says),
            "{w}: {err}"
        );
    }
}
