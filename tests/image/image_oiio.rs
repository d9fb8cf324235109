//! Round trips through OpenImageIO: every format and sample type spar
//! writes, read back by channel name, plus a cross-check with OpenImageIO's
//! own command-line tools and reads and writes from several threads.
#![cfg(feature = "native")]

use spar::image::{self, AlphaMode, Encoding, Image, PixelType, WriteOptions};
use std::path::Path;
use std::process::Command;

/// The sRGB transfer curve (IEC 61966-2-1), for checking values only.
fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// A deterministic value in [0, 1) for test pattern `seed`.
fn unit(seed: u64) -> f32 {
    let mut x = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 40) as f32 / (1u64 << 24) as f32
}

fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// An image whose values cover `pattern(channel, pixel)`.
fn patterned(
    w: usize,
    h: usize,
    channels: &[&str],
    pattern: impl Fn(usize, usize) -> f32,
) -> Image {
    let n = channels.len();
    let data = (0..w * h * n).map(|i| pattern(i % n, i / n)).collect();
    Image::new(w, h, names(channels), data).unwrap()
}

fn assert_close(got: f32, want: f32, tol: f32, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got}, want {want} (tolerance {tol})"
    );
}

#[test]
fn exr_float_stokes_channels_round_trip_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("stokes.exr");
    let special = [
        0.0,
        -0.0,
        1e-30,
        -2.5e-42,
        3.0e38,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1.0,
    ];
    let img = patterned(7, 5, &["S0", "S1", "S2", "S3"], |c, p| {
        if p < special.len() {
            special[(p + c) % special.len()]
        } else {
            (unit((p * 4 + c) as u64) - 0.5) * 10.0
        }
    });
    image::write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    let back = image::read(&path).unwrap();
    assert_eq!((back.width(), back.height()), (7, 5));
    for name in ["S0", "S1", "S2", "S3"] {
        let want: Vec<u32> = img
            .channel(name)
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect();
        let got: Vec<u32> = back
            .channel(name)
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect();
        assert_eq!(got, want, "channel {name}");
    }
}

#[test]
fn exr_with_many_channels_is_read_back_by_name_not_position() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("spectral.exr");
    // Three wavelengths of S0..S3, plus names that sort differently as
    // strings and as numbers (S10 < S2 < S3 as strings).
    let mut channel_names: Vec<String> = Vec::new();
    for wavelength in [650, 450, 550] {
        for s in 0..4 {
            channel_names.push(format!("S{s}_{wavelength}"));
        }
    }
    channel_names.extend(names(&["S3", "S2", "S10", "S1"]));
    let refs: Vec<&str> = channel_names.iter().map(String::as_str).collect();
    let img = patterned(6, 4, &refs, |c, p| {
        c as f32 * 1000.0 + p as f32 + unit(p as u64)
    });
    image::write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();

    let back = image::read(&path).unwrap();
    assert_eq!(back.channels().len(), 16);
    // EXR really reorders (the reason to read by name) ...
    assert_ne!(back.channels(), img.channels());
    let s10 = back.channel_index("S10").unwrap();
    let s2 = back.channel_index("S2").unwrap();
    assert!(s10 < s2, "EXR sorts S10 before S2: {:?}", back.channels());
    // ... and every channel comes back exactly under its own name.
    for name in &channel_names {
        assert_eq!(
            back.channel(name).unwrap(),
            img.channel(name).unwrap(),
            "channel {name}"
        );
    }
}

#[test]
fn half_exr_keeps_half_precision_and_overflows_to_infinity() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("half.exr");
    let img = patterned(9, 3, &["R", "G", "B"], |c, p| match (c, p) {
        (0, 0) => 70000.0, // above the largest half, 65504
        (1, 0) => 65504.0,
        (2, 0) => -1.0e-3,
        _ => (unit((p * 3 + c) as u64) - 0.3) * 300.0,
    });
    image::write(&path, &img, WriteOptions::new(PixelType::Half)).unwrap();
    let back = image::read(&path).unwrap();
    for name in ["R", "G", "B"] {
        for (i, (&got, &want)) in back
            .channel(name)
            .unwrap()
            .iter()
            .zip(&img.channel(name).unwrap())
            .enumerate()
        {
            if want > 65504.0 {
                assert_eq!(got, f32::INFINITY, "{name}[{i}]");
            } else {
                // Half has 11 significant bits: relative error ≤ 2^-11.
                assert_close(
                    got,
                    want,
                    want.abs() * 2f32.powi(-11),
                    &format!("{name}[{i}]"),
                );
            }
        }
    }
}

#[test]
fn exr_metadata_strings_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("meta.exr");
    let img = patterned(2, 2, &["S0"], |_, p| p as f32)
        .with_metadata("spar:scene", "scenes/brilliant.toml")
        .with_metadata("spar:wavelengths", "450 550 650")
        .with_metadata("spar:medium", "calcite, n_o = 1.6584 at λ = 589 nm")
        .with_metadata("ImageDescription", "Stokes vector per pixel");
    image::write(&path, &img, WriteOptions::default()).unwrap();
    let back = image::read(&path).unwrap();
    for (key, value) in img.metadata() {
        assert_eq!(back.metadata().get(key), Some(value), "metadata {key}");
    }
}

#[test]
fn png_8bit_round_trips_in_the_encoded_domain_and_reads_linear() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("display.png");
    // Encoded values: every 8-bit level once, then pseudo-random ones.
    let img = patterned(32, 16, &["R", "G", "B"], |c, p| match p * 3 + c {
        i if i < 256 => i as f32 / 255.0,
        i => unit(i as u64),
    });
    image::write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = image::read(&path).unwrap();
    assert_eq!(back.channels(), img.channels());
    for (i, (&linear, &encoded)) in back.data().iter().zip(img.data()).enumerate() {
        // Half a level of quantization, plus float slack.
        assert_close(
            srgb_encode(linear),
            encoded,
            0.5 / 255.0 + 1e-5,
            &format!("value {i}"),
        );
    }
    // An encoded 0.5 is stored as 128/255 and decoded to linear ≈ 0.2140
    // (0.2159 for the stored 128/255).
    let grey = Image::new(1, 1, names(&["R", "G", "B"]), vec![0.5; 3]).unwrap();
    let grey_path = dir.path().join("grey.png");
    image::write(&grey_path, &grey, WriteOptions::new(PixelType::U8)).unwrap();
    let back = image::read(&grey_path).unwrap();
    for &v in back.data() {
        assert_close(v, srgb_decode(128.0 / 255.0), 1e-5, "encoded 0.5");
        assert_close(v, 0.2140, 0.0025, "encoded 0.5 vs the unquantized 0.2140");
    }
}

#[test]
fn png_rgba_keeps_straight_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgba.png");
    // Colour under zero and partial alpha must survive untouched: OIIO would
    // un-premultiply it without oiio:UnassociatedAlpha.
    let pixels = [
        [0.8, 0.6, 0.4, 0.25],
        [0.3, 0.9, 0.1, 0.0],
        [0.5, 0.5, 0.5, 1.0],
    ];
    let data: Vec<f32> = pixels.iter().flatten().copied().collect();
    let img = Image::new(3, 1, names(&["R", "G", "B", "A"]), data).unwrap();
    assert_eq!(img.alpha_mode(), AlphaMode::Straight);
    image::write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = image::read(&path).unwrap();
    assert_eq!(back.alpha_mode(), AlphaMode::Straight);
    for (got, want) in back.rgba().unwrap().iter().zip(&pixels) {
        for c in 0..3 {
            assert_close(srgb_encode(got[c]), want[c], 0.5 / 255.0 + 1e-5, "colour");
        }
        assert_close(got[3], want[3], 0.5 / 255.0 + 1e-6, "alpha is not decoded");
    }
}

#[test]
fn png_with_four_data_channels_is_not_divided_by_the_fourth() {
    // PNG has no place for a fourth channel but alpha; with no channel named
    // A it must still come back as written, the other three undivided.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("four.png");
    let img = Image::new(
        2,
        1,
        names(&["S0", "S1", "S2", "S3"]),
        vec![0.8, 0.6, 0.4, 0.5, 0.3, 0.2, 0.1, 0.0],
    )
    .unwrap();
    assert_eq!(img.alpha_channel(), None);
    image::write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = image::read(&path).unwrap();
    for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
        // The fourth channel is read back as alpha, which is never decoded.
        let got = if i % 4 == 3 { got } else { srgb_encode(got) };
        assert_close(got, want, 0.5 / 255.0 + 1e-5, &format!("value {i}"));
    }
}

#[test]
fn png_16bit_linear_is_recorded_as_linear() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("linear16.png");
    let img = patterned(16, 8, &["Y"], |_, p| unit(p as u64));
    let options = WriteOptions::new(PixelType::U16).with_encoding(Encoding::Linear);
    image::write(&path, &img, options).unwrap();
    let back = image::read(&path).unwrap();
    for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
        assert_close(got, want, 0.5 / 65535.0 + 1e-7, &format!("value {i}"));
    }
}

#[test]
fn tiff_16bit_round_trips_within_one_level() {
    let dir = tempfile::tempdir().unwrap();
    // Linear data: returned as stored.
    let path = dir.path().join("data16.tif");
    let img = patterned(20, 10, &["R", "G", "B"], |c, p| unit((p * 3 + c) as u64));
    let linear = WriteOptions::new(PixelType::U16).with_encoding(Encoding::Linear);
    image::write(&path, &img, linear).unwrap();
    let back = image::read(&path).unwrap();
    for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
        assert_close(got, want, 1.0 / 65535.0, &format!("linear value {i}"));
    }
    // sRGB-encoded: tagged, and decoded to linear on read.
    let path = dir.path().join("display16.tif");
    image::write(&path, &img, WriteOptions::new(PixelType::U16)).unwrap();
    let back = image::read(&path).unwrap();
    for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
        assert_close(
            srgb_encode(got),
            want,
            1.0 / 65535.0 + 1e-5,
            &format!("sRGB value {i}"),
        );
    }
}

#[test]
fn tiff_float_round_trips_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("float.tif");
    let img = patterned(5, 5, &["R", "G", "B"], |c, p| {
        (unit((p * 3 + c) as u64) - 0.5) * 1e4
    });
    image::write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    assert_eq!(image::read(&path).unwrap().data(), img.data());
}

#[test]
fn jpeg_8bit_round_trips_loosely() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("photo.jpg");
    // A smooth gradient: JPEG's blocks and chroma subsampling barely touch it.
    let img = patterned(64, 32, &["R", "G", "B"], |c, p| {
        let (x, y) = ((p % 64) as f32 / 63.0, (p / 64) as f32 / 31.0);
        [0.2 + 0.6 * x, 0.3 + 0.4 * y, 0.5][c]
    });
    image::write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = image::read(&path).unwrap();
    assert_eq!(back.channels(), img.channels());
    let mut worst = 0f32;
    for (&linear, &encoded) in back.data().iter().zip(img.data()) {
        worst = worst.max((srgb_encode(linear) - encoded).abs());
    }
    assert!(
        worst < 0.03,
        "largest JPEG error in the encoded domain: {worst}"
    );
}

#[test]
fn integer_outputs_clamp_and_write_nan_as_zero() {
    let dir = tempfile::tempdir().unwrap();
    let values = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.5, 1.5, 0.25];
    let expected = [0.0, 1.0, 0.0, 0.0, 1.0, 0.25];
    let img = Image::new(6, 1, names(&["Y"]), values.to_vec()).unwrap();
    for (file, pixel_type, tol) in [
        ("clamp8.png", PixelType::U8, 0.5 / 255.0),
        ("clamp16.tif", PixelType::U16, 0.5 / 65535.0),
    ] {
        let path = dir.path().join(file);
        let options = WriteOptions::new(pixel_type).with_encoding(Encoding::Linear);
        image::write(&path, &img, options).unwrap();
        let back = image::read(&path).unwrap();
        for (i, (&got, &want)) in back.data().iter().zip(&expected).enumerate() {
            assert_close(
                got,
                want,
                tol + 1e-7,
                &format!("{file}: {} → {want}", values[i]),
            );
        }
    }
    // Float outputs keep them.
    let path = dir.path().join("keep.exr");
    image::write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    let back = image::read(&path).unwrap();
    assert!(back.data()[0].is_nan());
    assert_eq!(&back.data()[1..], &values[1..]);
}

/// Runs OpenImageIO's `iinfo -v`, or says why the check is skipped.
fn iinfo(path: &Path) -> Option<String> {
    match Command::new("iinfo").arg("-v").arg(path).output() {
        Ok(out) if out.status.success() => Some(String::from_utf8_lossy(&out.stdout).into_owned()),
        Ok(out) => panic!(
            "iinfo failed on {}: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        ),
        Err(e) => {
            eprintln!("SKIPPED: `iinfo` (Debian package openimageio-tools) is not available: {e}");
            None
        }
    }
}

#[test]
fn openimageio_tools_see_what_spar_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let exr = dir.path().join("stokes.exr");
    let img = patterned(3, 2, &["S0", "S1", "S2", "S10"], |c, p| (c + p) as f32)
        .with_metadata("spar:scene", "gem.toml")
        .with_metadata("spar:integrator", "polarized path tracer");
    image::write(&exr, &img, WriteOptions::new(PixelType::Half)).unwrap();
    let Some(info) = iinfo(&exr) else { return };
    assert!(info.contains("3 x    2, 4 channel, half openexr"), "{info}");
    assert!(info.contains("channel list: S0, S1, S10, S2"), "{info}");
    assert!(info.contains("spar:scene: \"gem.toml\""), "{info}");
    assert!(
        info.contains("spar:integrator: \"polarized path tracer\""),
        "{info}"
    );
    assert!(info.contains("compression: \"zip\""), "{info}");

    let png = dir.path().join("display.png");
    image::write(&png, &img, WriteOptions::new(PixelType::U16)).unwrap();
    let info = iinfo(&png).unwrap();
    assert!(info.contains("4 channel, uint16 png"), "{info}");
    assert!(info.contains("oiio:ColorSpace: \"sRGB\""), "{info}");

    // And the other way: a file written by oiiotool, read by spar.
    let by_tool = dir.path().join("by_oiiotool.png");
    let status = Command::new("oiiotool")
        .args([
            "--pattern",
            "constant:color=0.5,0.25,1",
            "4x3",
            "3",
            "-d",
            "uint8",
            "-o",
        ])
        .arg(&by_tool)
        .status()
        .expect("oiiotool ships with iinfo");
    assert!(status.success());
    let back = image::read(&by_tool).unwrap();
    assert_eq!((back.width(), back.height()), (4, 3));
    let rgba = back.rgba().unwrap();
    for (c, want) in [0.5f32, 0.25, 1.0].into_iter().enumerate() {
        let stored = (want * 255.0).round() / 255.0;
        assert_close(rgba[5][c], srgb_decode(stored), 1e-5, "oiiotool's pixel");
    }
    assert_eq!(rgba[5][3], 1.0);

    // A PNG whose metadata says gamma 2.2 rather than sRGB is decoded with it.
    let gamma = dir.path().join("gamma22.png");
    let status = Command::new("oiiotool")
        .args(["--pattern", "constant:color=0.5", "2x2", "1", "-d", "uint8"])
        .args(["--iscolorspace", "Gamma2.2", "-o"])
        .arg(&gamma)
        .status()
        .unwrap();
    assert!(status.success());
    let back = image::read(&gamma).unwrap();
    assert_close(
        back.data()[0],
        (128.0f32 / 255.0).powf(2.2),
        1e-4,
        "gamma 2.2 PNG",
    );

    // Float files are linear whatever colour space they name.
    let tagged = dir.path().join("tagged_srgb.exr");
    let status = Command::new("oiiotool")
        .args(["--pattern", "constant:color=0.5", "2x2", "1", "-d", "float"])
        .args(["--iscolorspace", "sRGB", "-o"])
        .arg(&tagged)
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(image::read(&tagged).unwrap().data(), &[0.5; 4]);
}

#[test]
fn threads_write_and_read_independent_files_at_once() {
    let dir = tempfile::tempdir().unwrap();
    std::thread::scope(|scope| {
        for t in 0..8u64 {
            let dir = dir.path();
            scope.spawn(move || {
                for k in 0..6u64 {
                    let seed = t * 100 + k;
                    let img = patterned(40, 30, &["S0", "S1", "S2", "S10"], |c, p| {
                        unit(seed * 1_000_000 + (p * 4 + c) as u64)
                    })
                    .with_metadata("spar:seed", seed.to_string());
                    for (ext, options) in [
                        ("exr", WriteOptions::new(PixelType::F32)),
                        (
                            "tif",
                            WriteOptions::new(PixelType::U16).with_encoding(Encoding::Linear),
                        ),
                        // sRGB: decoding to linear runs on every thread too.
                        ("png", WriteOptions::new(PixelType::U8)),
                    ] {
                        let path = dir.join(format!("t{t}-{k}.{ext}"));
                        image::write(&path, &img, options).unwrap();
                        let back = image::read(&path).unwrap();
                        let what = path.display().to_string();
                        match ext {
                            "exr" => {
                                assert_eq!(
                                    back.channel("S10").unwrap(),
                                    img.channel("S10").unwrap()
                                );
                                assert_eq!(back.metadata()["spar:seed"], seed.to_string());
                            }
                            // TIFF and PNG keep the order, not the names.
                            "tif" => {
                                for (&g, &w) in back.data().iter().zip(img.data()) {
                                    assert_close(g, w, 1.0 / 65535.0, &what);
                                }
                            }
                            // A PNG's fourth channel is alpha: not decoded.
                            _ => {
                                for (i, (&g, &w)) in back.data().iter().zip(img.data()).enumerate()
                                {
                                    let g = if i % 4 == 3 { g } else { srgb_encode(g) };
                                    assert_close(g, w, 0.5 / 255.0 + 1e-5, &what);
                                }
                            }
                        }
                    }
                }
            });
        }
    });
}

#[test]
fn threads_racing_on_one_destination_leave_one_whole_image() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("shared.exr");
    std::thread::scope(|scope| {
        for t in 0..6 {
            let path = &path;
            scope.spawn(move || {
                let img = patterned(64, 64, &["S0"], |_, _| t as f32);
                for _ in 0..5 {
                    image::write(path, &img, WriteOptions::new(PixelType::F32)).unwrap();
                }
            });
        }
    });
    let back = image::read(&path).unwrap();
    let first = back.data()[0];
    assert!(
        back.data().iter().all(|&v| v == first),
        "pixels from several writers"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n != "shared.exr")
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporaries left behind: {leftovers:?}"
    );
}
