//! The polarization camera (issue 16 item 3): `--mode polcam` writes the
//! intensities behind linear polarizers at 0°, 45°, 90° and 135° from
//! image right toward image up, from which S0 = I0 + I90, S1 = I0 − I90
//! and S2 = I45 − I135 come back as the Stokes EXR holds them;
//! `polcam-mosaic` puts them into the 2×2 mosaic of an IMX250MZR-type
//! sensor (90 45 over 135 0, docs/outputs.md).

use crate::support::run::spar_ok;
use spar::image::Image;
use std::path::Path;

const ANGLES: [&str; 4] = ["000", "045", "090", "135"];

fn read(dir: &Path, name: &str) -> Image {
    spar::image::read(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The one grey channel of a polarization-camera image.
fn grey(img: &Image) -> Vec<f32> {
    assert_eq!(img.channels(), ["Y"]);
    img.channel("Y").unwrap()
}

#[test]
fn stokes_come_back_from_the_four_images_and_the_mosaic_is_theirs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/calcite-polarized.toml");
    let small = ["--resolution", "32x24", "--samples", "1", "-q"];
    // Floats: the four images, the mosaic and the Stokes EXR of the same
    // render, at 600 nm (the Stokes EXR then holds that wavelength only).
    let modes = [
        "--mode",
        "polcam,polcam-mosaic,stokes",
        "--wavelength",
        "600",
    ];
    spar_ok(
        d,
        &[&["render", scene][..], &small, &modes, &["-o", "cam.exr"]].concat(),
    );
    let stokes = read(d, "cam-stokes.exr");
    // One wavelength: the JCGT layout's channels, no RGB preview.
    assert_eq!(
        stokes.channels(),
        ["S0.600nm", "S1.600nm", "S2.600nm", "S3.600nm"]
    );
    assert_eq!(stokes.metadata()["spar:wavelengths_nm"], "600");
    let s: Vec<Vec<f32>> = (0..3)
        .map(|c| stokes.channel(&format!("S{c}.600nm")).unwrap())
        .collect();
    let i: Vec<Vec<f32>> = ANGLES
        .iter()
        .map(|a| {
            let img = read(d, &format!("cam-polcam-{a}.exr"));
            assert_eq!((img.width(), img.height()), (32, 24));
            assert_eq!(img.metadata()["spar:mode"], "polcam");
            assert_eq!(img.metadata()["spar:wavelength_nm"], "600");
            grey(&img)
        })
        .collect();
    let (mut s1_seen, mut s2_seen) = (0, 0);
    for p in 0..32 * 24 {
        let v = |k: usize| i[k][p] as f64;
        let recovered = [v(0) + v(2), v(0) - v(2), v(1) - v(3)];
        let s0 = s[0][p] as f64;
        for c in 0..3 {
            let err = (recovered[c] - s[c][p] as f64).abs();
            // Relative to the pixel's intensity: S1 and S2 are differences
            // of the images and can be far smaller than S0.
            assert!(
                err <= 1e-6 * s0.max(1e-30),
                "pixel {p}: S{c} {} from the images, {} in the EXR (S0 {s0})",
                recovered[c],
                s[c][p]
            );
        }
        s1_seen += usize::from((s[1][p] as f64).abs() > 0.05 * s0);
        s2_seen += usize::from((s[2][p] as f64).abs() > 0.05 * s0);
    }
    // The scene's polarization has structure, in both linear components.
    assert!(s1_seen > 20 && s2_seen > 20, "{s1_seen} {s2_seen}");
    assert_mosaic(&grey(&read(d, "cam-polcam-mosaic.exr")), &i, 32);

    // Display images: the same layout, pixel for pixel.
    spar_ok(
        d,
        &[
            &["render", scene][..],
            &small,
            &["--mode", "polcam,polcam-mosaic", "-o", "cam.png"],
        ]
        .concat(),
    );
    let shown: Vec<Vec<f32>> = ANGLES
        .iter()
        .map(|a| grey(&read(d, &format!("cam-polcam-{a}.png"))))
        .collect();
    assert_mosaic(&grey(&read(d, "cam-polcam-mosaic.png")), &shown, 32);
}

/// Mosaic pixel (x, y) (y counted down from the top row) is the image of
/// the angle the documented 2×2 block gives it: 90 45 over 135 0.
fn assert_mosaic(mosaic: &[f32], images: &[Vec<f32>], width: usize) {
    let block = [[2, 1], [3, 0]]; // indices into ANGLES: 090 045 / 135 000
    for (p, &m) in mosaic.iter().enumerate() {
        let (x, y) = (p % width, p / width);
        let k = block[y % 2][x % 2];
        assert_eq!(
            m, images[k][p],
            "mosaic pixel ({x}, {y}) is not {}°",
            ANGLES[k]
        );
    }
}

/// A light behind a polarizer at +45° (from image right toward image up)
/// seen directly: the 45° image has it all, the 135° image nothing, 0° and
/// 90° half each; the display images show I/D65 as mono shows S0.
#[test]
fn angles_turn_from_image_right_toward_image_up() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("s.toml"),
        r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 10.0
resolution = [4, 4]
[[light]]
corners = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]]
polarization = { linear = [1.0, 1.0, 0.0] }
"#,
    )
    .unwrap();
    spar_ok(
        d,
        &[
            "render",
            "s.toml",
            "-q",
            "--mode",
            "polcam,mono",
            "-o",
            "p.exr",
        ],
    );
    let d65 = spar::spectrum::cie::d65(580.0);
    let mean = |a: &str| {
        let v = grey(&read(d, &format!("p-polcam-{a}.exr")));
        v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64 / d65
    };
    // The light's radiance is half of D65 (an ideal polarizer).
    let [i0, i45, i90, i135] = ANGLES.map(mean);
    assert!((i45 - 0.5).abs() < 1e-3, "45°: {i45}");
    assert!(i135.abs() < 1e-3, "135°: {i135}");
    assert!(
        (i0 - 0.25).abs() < 2e-3 && (i90 - 0.25).abs() < 2e-3,
        "{i0} {i90}"
    );
    // mono was written beside them as a display image (no float mono).
    assert!(d.join("p-mono.png").exists());
}
