//! The pure-Rust image backend (`spar::image::pure`: the `exr` and `png`
//! crates) keeps the image contract for OpenEXR and PNG. It is compiled in
//! every build, so these tests run in both; without the `native` feature
//! it is also what `spar::image::{write, read}` use (checked at the end).

use crate::support::image::{assert_close, bits, names, patterned, srgb_decode, srgb_encode, unit};
use spar::image::pure::{read, write};
use spar::image::{AlphaMode, Cause, Encoding, Image, ImageError, PixelType, WriteOptions};
use std::fs;
use std::path::Path;

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
        f32::NAN,
    ];
    let img = patterned(7, 5, &["S0", "S1", "S2", "S3"], |c, p| {
        if p < special.len() {
            special[(p + c) % special.len()]
        } else {
            (unit((p * 4 + c) as u64) - 0.5) * 10.0
        }
    });
    write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    let back = read(&path).unwrap();
    assert_eq!((back.width(), back.height()), (7, 5));
    assert_eq!(back.alpha_mode(), AlphaMode::Premultiplied);
    assert_eq!(back.source(), Some(path.as_path()));
    for name in ["S0", "S1", "S2", "S3"] {
        assert_eq!(bits(&back, name), bits(&img, name), "channel {name}");
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
    write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();

    let back = read(&path).unwrap();
    assert_eq!(back.channels().len(), 16);
    // EXR really reorders (the reason to read by name): sorted as strings.
    let mut sorted = channel_names.clone();
    sorted.sort();
    assert_eq!(back.channels(), &sorted[..]);
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
        (0, 1) => f32::NAN,
        (1, 1) => f32::NEG_INFINITY,
        _ => (unit((p * 3 + c) as u64) - 0.3) * 300.0,
    });
    write(&path, &img, WriteOptions::new(PixelType::Half)).unwrap();
    let back = read(&path).unwrap();
    for name in ["R", "G", "B"] {
        for (i, (&got, &want)) in back
            .channel(name)
            .unwrap()
            .iter()
            .zip(&img.channel(name).unwrap())
            .enumerate()
        {
            if want.is_nan() {
                assert!(got.is_nan(), "{name}[{i}]: {got}");
            } else if want.is_infinite() {
                assert_eq!(got, want, "{name}[{i}]");
            } else if want > 65504.0 {
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
    // Half really is stored: the file is smaller than the float one.
    let float = dir.path().join("float.exr");
    write(&float, &img, WriteOptions::new(PixelType::F32)).unwrap();
    assert!(fs::metadata(&path).unwrap().len() < fs::metadata(&float).unwrap().len());
}

#[test]
fn exr_metadata_strings_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("meta.exr");
    let img = patterned(2, 2, &["S0"], |_, p| p as f32)
        .with_metadata("spar:scene", "scenes/brilliant.toml")
        .with_metadata("spar:wavelengths", "450 550 650")
        .with_metadata("spar:medium", "calcite, n_o = 1.6584 at λ = 589 nm")
        .with_metadata("spar:empty", "")
        .with_metadata("ImageDescription", "Stokes vector per pixel")
        .with_metadata("Copyright", "CC0")
        .with_metadata("DateTime", "2025:06:01 12:00:00")
        .with_metadata("Software", "spar");
    write(&path, &img, WriteOptions::default()).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.metadata(), img.metadata());
}

#[test]
fn exr_refuses_integer_samples_and_reserved_attribute_names() {
    let dir = tempfile::tempdir().unwrap();
    let img = patterned(2, 2, &["Y"], |_, p| p as f32 / 4.0);
    for pixel_type in [PixelType::U8, PixelType::U16] {
        let options = WriteOptions::new(pixel_type).with_encoding(Encoding::Linear);
        let cause = write_cause(&dir.path().join("int.exr"), &img, options);
        assert!(matches!(cause, Cause::Backend(_)), "{cause:?}");
    }
    // Attributes that OpenEXR itself defines with another type.
    for key in ["compression", "channels", "dataWindow", "pixelAspectRatio"] {
        let img = img.clone().with_metadata(key, "zip");
        let cause = write_cause(&dir.path().join("meta.exr"), &img, WriteOptions::default());
        assert!(
            matches!(&cause, Cause::Backend(m) if m.contains(key)),
            "{key}: {cause:?}"
        );
    }
    // Two keys for one attribute.
    let img = img
        .with_metadata("ImageDescription", "a")
        .with_metadata("comments", "b");
    write_cause(&dir.path().join("twice.exr"), &img, WriteOptions::default());
    assert_eq!(entries(dir.path()), Vec::<String>::new());
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
    write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.channels(), img.channels());
    assert_eq!(back.alpha_mode(), AlphaMode::Straight);
    for (i, (&linear, &encoded)) in back.data().iter().zip(img.data()).enumerate() {
        // Half a level of quantization, plus float slack.
        assert_close(
            srgb_encode(linear),
            encoded,
            0.5 / 255.0 + 1e-5,
            &format!("value {i}"),
        );
    }
    // Every level decodes to exactly the sRGB curve's value.
    for (i, &linear) in back.data().iter().take(256).enumerate() {
        assert_close(linear, srgb_decode(i as f32 / 255.0), 1e-6, "level");
    }
    // An encoded 0.5 is stored as 128/255 and decoded to linear ≈ 0.2140
    // (0.2159 for the stored 128/255).
    let grey = Image::new(1, 1, names(&["R", "G", "B"]), vec![0.5; 3]).unwrap();
    let grey_path = dir.path().join("grey.png");
    write(&grey_path, &grey, WriteOptions::new(PixelType::U8)).unwrap();
    let back = read(&grey_path).unwrap();
    for &v in back.data() {
        assert_close(v, srgb_decode(128.0 / 255.0), 1e-6, "encoded 0.5");
        assert_close(v, 0.2140, 0.0025, "encoded 0.5 vs the unquantized 0.2140");
    }
}

#[test]
fn png_16bit_srgb_and_linear_round_trip_within_a_level() {
    let dir = tempfile::tempdir().unwrap();
    let img = patterned(16, 8, &["R", "G", "B"], |c, p| unit((p * 3 + c) as u64));
    let path = dir.path().join("display16.png");
    write(&path, &img, WriteOptions::new(PixelType::U16)).unwrap();
    let back = read(&path).unwrap();
    for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
        assert_close(
            srgb_encode(got),
            want,
            0.5 / 65535.0 + 1e-5,
            &format!("sRGB value {i}"),
        );
    }
    let path = dir.path().join("linear16.png");
    let grey = patterned(16, 8, &["Y"], |_, p| unit(p as u64));
    let options = WriteOptions::new(PixelType::U16).with_encoding(Encoding::Linear);
    write(&path, &grey, options).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.channels(), ["Y"]);
    for (i, (&got, &want)) in back.data().iter().zip(grey.data()).enumerate() {
        assert_close(
            got,
            want,
            0.5 / 65535.0 + 1e-7,
            &format!("linear value {i}"),
        );
    }
    // Linear 8-bit too: returned as stored.
    let path = dir.path().join("linear8.png");
    let options = WriteOptions::new(PixelType::U8).with_encoding(Encoding::Linear);
    write(&path, &grey, options).unwrap();
    for (&got, &want) in read(&path).unwrap().data().iter().zip(grey.data()) {
        assert_close(got, want, 0.5 / 255.0 + 1e-7, "linear 8-bit");
    }
}

#[test]
fn png_rgba_keeps_straight_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgba.png");
    let pixels = [
        [0.8, 0.6, 0.4, 0.25],
        [0.3, 0.9, 0.1, 0.0],
        [0.5, 0.5, 0.5, 1.0],
    ];
    let data: Vec<f32> = pixels.iter().flatten().copied().collect();
    let img = Image::new(3, 1, names(&["R", "G", "B", "A"]), data).unwrap();
    write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.alpha_mode(), AlphaMode::Straight);
    assert_eq!(back.alpha_channel(), Some(3));
    for (got, want) in back.rgba().unwrap().iter().zip(&pixels) {
        for c in 0..3 {
            assert_close(srgb_encode(got[c]), want[c], 0.5 / 255.0 + 1e-5, "colour");
        }
        assert_close(got[3], want[3], 0.5 / 255.0 + 1e-6, "alpha is not decoded");
    }
}

#[test]
fn png_premultiplied_colours_are_divided_by_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("premultiplied.png");
    let img = Image::new(
        3,
        1,
        names(&["R", "G", "B", "A"]),
        vec![
            0.4, 0.2, 0.1, 0.5, // → 0.8, 0.4, 0.2
            0.3, 0.2, 0.1, 0.0, // zero alpha: kept
            0.9, 0.6, 0.3, 0.6, // 0.9 / 0.6 = 1.5: clamped to 1
        ],
    )
    .unwrap()
    .with_alpha_mode(AlphaMode::Premultiplied);
    let options = WriteOptions::new(PixelType::U16).with_encoding(Encoding::Linear);
    write(&path, &img, options).unwrap();
    let back = read(&path).unwrap();
    let want = [0.8, 0.4, 0.2, 0.5, 0.3, 0.2, 0.1, 0.0, 1.0, 1.0, 0.5, 0.6];
    for (i, (&got, &want)) in back.data().iter().zip(&want).enumerate() {
        assert_close(got, want, 1.0 / 65535.0, &format!("value {i}"));
    }
}

#[test]
fn png_with_two_or_four_data_channels_reads_the_last_as_alpha() {
    // PNG has no place for a fourth (or second) channel but alpha; with no
    // channel named A they still come back as written, undivided.
    let dir = tempfile::tempdir().unwrap();
    for (file, channels, want_names) in [
        ("two.png", &["S0", "S1"][..], &["Y", "A"][..]),
        (
            "four.png",
            &["S0", "S1", "S2", "S3"][..],
            &["R", "G", "B", "A"][..],
        ),
    ] {
        let path = dir.path().join(file);
        let n = channels.len();
        let img = patterned(5, 2, channels, |c, p| unit((p * n + c) as u64));
        assert_eq!(img.alpha_channel(), None);
        write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.channels(), want_names, "{file}");
        for (i, (&got, &want)) in back.data().iter().zip(img.data()).enumerate() {
            // The last channel is read back as alpha, which is never decoded.
            let got = if i % n == n - 1 {
                got
            } else {
                srgb_encode(got)
            };
            assert_close(got, want, 0.5 / 255.0 + 1e-5, &format!("{file} value {i}"));
        }
    }
}

#[test]
fn png_metadata_round_trips_as_text_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("meta.png");
    let img = patterned(2, 2, &["R", "G", "B"], |_, p| p as f32 / 4.0)
        .with_metadata("spar:scene", "scenes/brilliant.toml")
        .with_metadata("spar:medium", "calcite, n_o = 1.6584 at λ = 589 nm")
        .with_metadata("spar:latin1", "café")
        .with_metadata("ImageDescription", "a gem")
        .with_metadata("Artist", "spar")
        .with_metadata("DocumentName", "brilliant")
        .with_metadata("DateTime", "2025:06:01 12:00:00");
    write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.metadata(), img.metadata());
    // Standard keys are stored under PNG's own keywords.
    let bytes = fs::read(&path).unwrap();
    for keyword in ["Description", "Author", "Title"] {
        let needle = format!("{keyword}\0");
        assert!(
            bytes.windows(needle.len()).any(|w| w == needle.as_bytes()),
            "no text chunk {keyword}"
        );
    }
}

#[test]
fn png_refuses_what_it_cannot_store() {
    let dir = tempfile::tempdir().unwrap();
    let five = patterned(2, 2, &["a", "b", "c", "d", "e"], |_, _| 0.5);
    let alpha_first = patterned(2, 2, &["A", "R", "G", "B"], |_, _| 0.5);
    let alpha_of_three = patterned(2, 2, &["R", "G", "A"], |_, _| 0.5);
    let rgb = patterned(2, 2, &["R", "G", "B"], |_, _| 0.5);
    let u8 = WriteOptions::new(PixelType::U8);
    let cases = [
        ("five.png", &five, u8, "1 to 4 channels"),
        ("alpha_first.png", &alpha_first, u8, "alpha"),
        ("alpha_of_three.png", &alpha_of_three, u8, "alpha"),
        (
            "half.png",
            &rgb,
            WriteOptions::new(PixelType::Half),
            "8- or 16-bit",
        ),
        (
            "float.png",
            &rgb,
            WriteOptions::new(PixelType::F32),
            "8- or 16-bit",
        ),
    ];
    for (file, img, options, says) in cases {
        let cause = write_cause(&dir.path().join(file), img, options);
        assert!(
            matches!(&cause, Cause::Backend(m) if m.contains(says)),
            "{file}: {cause:?}"
        );
    }
    // Keywords PNG cannot hold.
    let long = "k".repeat(80);
    for key in [
        long.as_str(),
        " lead",
        "trail ",
        "two  spaces",
        "λ",
        "tab\there",
    ] {
        let img = rgb.clone().with_metadata(key, "v");
        let cause = write_cause(&dir.path().join("meta.png"), &img, u8);
        assert!(matches!(cause, Cause::Backend(_)), "{key:?}: {cause:?}");
    }
    assert_eq!(entries(dir.path()), Vec::<String>::new());
}

#[test]
fn integer_outputs_clamp_and_write_nan_as_zero() {
    let dir = tempfile::tempdir().unwrap();
    let values = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.5, 1.5, 0.25];
    let expected = [0.0, 1.0, 0.0, 0.0, 1.0, 0.25];
    let img = Image::new(6, 1, names(&["Y"]), values.to_vec()).unwrap();
    for (file, pixel_type, tol) in [
        ("clamp8.png", PixelType::U8, 0.5 / 255.0),
        ("clamp16.png", PixelType::U16, 0.5 / 65535.0),
    ] {
        let path = dir.path().join(file);
        let options = WriteOptions::new(pixel_type).with_encoding(Encoding::Linear);
        write(&path, &img, options).unwrap();
        let back = read(&path).unwrap();
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
    write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    let back = read(&path).unwrap();
    assert!(back.data()[0].is_nan());
    assert_eq!(&back.data()[1..], &values[1..]);
}

/// PNGs that spar does not write but reads: palette, low bit depth,
/// transparency chunk, gamma, compressed text, no colour information at
/// all. (Interlaced files, which the `png` crate cannot write, are made by
/// OpenImageIO in `image_cross.rs`.)
#[test]
fn png_reader_takes_what_other_writers_make() {
    let dir = tempfile::tempdir().unwrap();
    let encode = |path: &Path, setup: &dyn Fn(&mut png::Encoder<'_, fs::File>), data: &[u8]| {
        let file = fs::File::create(path).unwrap();
        let mut encoder = png::Encoder::new(file, 4, 2);
        setup(&mut encoder);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
        writer.finish().unwrap();
    };

    // A palette of four colours, index 1 half transparent, gamma 1/2.2.
    let path = dir.path().join("palette.png");
    encode(
        &path,
        &|e| {
            e.set_color(png::ColorType::Indexed);
            e.set_depth(png::BitDepth::Two);
            e.set_palette(vec![0, 0, 0, 255, 128, 0, 10, 20, 30, 255, 255, 255]);
            e.set_trns(vec![255, 128]);
            e.set_source_gamma(png::ScaledFloat::new(1.0 / 2.2));
            e.add_ztxt_chunk("spar:z".into(), "compressed text".into())
                .unwrap();
        },
        // Indices 0 1 2 3 / 3 2 1 0, two bits each.
        &[0b0001_1011, 0b1110_0100],
    );
    let back = read(&path).unwrap();
    assert_eq!(back.channels(), ["R", "G", "B", "A"]);
    assert_eq!(back.metadata()["spar:z"], "compressed text");
    let gamma = |v: f32| (v / 255.0).powf(2.2);
    let p1 = back.pixel(1, 0);
    assert_close(p1[0], 1.0, 1e-4, "palette red");
    assert_close(p1[1], gamma(128.0), 1e-4, "palette green, gamma 2.2");
    assert_close(p1[3], 128.0 / 255.0, 1e-6, "transparency");
    assert_eq!(back.pixel(2, 0)[3], 1.0, "entries past tRNS are opaque");
    assert_eq!(back.pixel(0, 1), back.pixel(3, 0));

    // 16-bit grey without colour information: sRGB is assumed.
    let path = dir.path().join("untagged.png");
    let levels: [u16; 8] = [0, 1000, 20000, 32768, 40000, 50000, 65000, 65535];
    let data: Vec<u8> = levels.iter().flat_map(|v| v.to_be_bytes()).collect();
    encode(
        &path,
        &|e| {
            e.set_color(png::ColorType::Grayscale);
            e.set_depth(png::BitDepth::Sixteen);
        },
        &data,
    );
    let back = read(&path).unwrap();
    assert_eq!(back.channels(), ["Y"]);
    for (&got, &level) in back.data().iter().zip(&levels) {
        assert_close(got, srgb_decode(f32::from(level) / 65535.0), 1e-6, "grey");
    }
}

#[test]
fn oiio_settings_in_a_file_are_not_returned() {
    // OpenImageIO records its colour space as a text chunk; reading it back
    // must not hand write a key it refuses.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("oiio.png");
    let file = fs::File::create(&path).unwrap();
    let mut encoder = png::Encoder::new(file, 1, 1);
    encoder
        .add_text_chunk("oiio:ColorSpace".into(), "sRGB".into())
        .unwrap();
    encoder
        .add_text_chunk("Software".into(), "OpenImageIO".into())
        .unwrap();
    // UTF-8 in a tEXt chunk, as OpenImageIO writes it.
    encoder
        .add_text_chunk("spar:utf8".into(), "Î» = 589 nm".into())
        .unwrap();
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&[77]).unwrap();
    writer.finish().unwrap();
    let back = read(&path).unwrap();
    assert_eq!(back.metadata().len(), 2, "{:?}", back.metadata());
    assert_eq!(back.metadata()["Software"], "OpenImageIO");
    assert_eq!(back.metadata()["spar:utf8"], "λ = 589 nm");
    let copy = dir.path().join("copy.png");
    write(&copy, &back, WriteOptions::new(PixelType::U8)).unwrap();
}

#[test]
fn other_formats_are_refused_naming_the_native_feature() {
    let dir = tempfile::tempdir().unwrap();
    let img = patterned(2, 2, &["R", "G", "B"], |_, _| 0.5);
    for file in ["out.tif", "out.tiff", "out.jpg", "out.notaformat"] {
        let path = dir.path().join(file);
        let err = write(&path, &img, WriteOptions::new(PixelType::U8)).unwrap_err();
        let message = err.to_string();
        assert!(message.contains(file), "{message}");
        assert!(message.contains("`native` feature"), "{message}");
        assert!(!message.contains(".tmp-"), "{message}");
    }
    // Reading goes by content, not name: a PNG called .tif is read, a TIFF
    // is refused.
    let png_named_tif = dir.path().join("really_png.tif");
    write(
        &dir.path().join("a.png"),
        &img,
        WriteOptions::new(PixelType::U8),
    )
    .unwrap();
    fs::rename(dir.path().join("a.png"), &png_named_tif).unwrap();
    assert_eq!(read(&png_named_tif).unwrap().channels(), ["R", "G", "B"]);
    let tiff = dir.path().join("little_endian.tif");
    fs::write(&tiff, b"II*\0\x08\0\0\0\0\0").unwrap();
    let message = read(&tiff).unwrap_err().to_string();
    assert!(message.contains("`native` feature"), "{message}");
    assert_eq!(entries(dir.path()), ["little_endian.tif", "really_png.tif"]);
}

#[test]
fn threads_write_and_read_independent_files_at_once() {
    let dir = tempfile::tempdir().unwrap();
    std::thread::scope(|scope| {
        for t in 0..4u64 {
            let dir = dir.path();
            scope.spawn(move || {
                for k in 0..4u64 {
                    let seed = t * 100 + k;
                    let img = patterned(40, 30, &["S0", "S1", "S2", "S10"], |c, p| {
                        unit(seed * 1_000_000 + (p * 4 + c) as u64)
                    })
                    .with_metadata("spar:seed", seed.to_string());
                    let exr = dir.join(format!("t{t}-{k}.exr"));
                    write(&exr, &img, WriteOptions::new(PixelType::F32)).unwrap();
                    let back = read(&exr).unwrap();
                    assert_eq!(back.channel("S10").unwrap(), img.channel("S10").unwrap());
                    assert_eq!(back.metadata()["spar:seed"], seed.to_string());
                    let png = dir.join(format!("t{t}-{k}.png"));
                    write(&png, &img, WriteOptions::new(PixelType::U8)).unwrap();
                    let back = read(&png).unwrap();
                    for (i, (&g, &w)) in back.data().iter().zip(img.data()).enumerate() {
                        let g = if i % 4 == 3 { g } else { srgb_encode(g) };
                        assert_close(g, w, 0.5 / 255.0 + 1e-5, &png.display().to_string());
                    }
                }
            });
        }
    });
    assert_eq!(entries(dir.path()).len(), 32);
}

/// Without the `native` feature, `spar::image::{write, read}` are this
/// backend.
#[cfg(not(feature = "native"))]
#[test]
fn without_native_the_default_backend_is_pure_rust() {
    use spar::image;
    let dir = tempfile::tempdir().unwrap();
    let img = patterned(3, 2, &["S0", "S2", "S10"], |c, p| (c * 10 + p) as f32)
        .with_metadata("spar:scene", "gem.toml");
    let path = dir.path().join("stokes.exr");
    image::write(&path, &img, WriteOptions::new(PixelType::F32)).unwrap();
    let back = image::read(&path).unwrap();
    assert_eq!(back.channels(), ["S0", "S10", "S2"]);
    assert_eq!(back.channel("S2").unwrap(), img.channel("S2").unwrap());
    assert_eq!(back.metadata()["spar:scene"], "gem.toml");
    // The file is the one the pure backend writes, byte for byte.
    let direct = dir.path().join("direct.exr");
    write(&direct, &img, WriteOptions::new(PixelType::F32)).unwrap();
    assert_eq!(fs::read(&path).unwrap(), fs::read(&direct).unwrap());

    let err = image::write(
        &dir.path().join("out.tif"),
        &img,
        WriteOptions::new(PixelType::F32),
    )
    .unwrap_err();
    assert!(err.to_string().contains("`native` feature"), "{err}");

    let mut canvas = patterned(8, 8, &["R", "G", "B"], |_, _| 0.0);
    let err = image::draw_text(&mut canvas, 1, 6, "x", 6, "DejaVuSans", &[1.0; 3]).unwrap_err();
    assert!(err.to_string().contains("`native` feature"), "{err}");
}

/// The cause of a write that must fail; checks that it names the file.
fn write_cause(path: &Path, img: &Image, options: WriteOptions) -> Cause {
    match write(path, img, options) {
        Ok(()) => panic!("writing {} succeeded", path.display()),
        Err(err) => {
            let message = err.to_string();
            assert!(message.contains(&path.display().to_string()), "{message}");
            match err {
                ImageError::Write { cause, .. } => cause,
                other => panic!("not a write error: {other:?}"),
            }
        }
    }
}

/// Names of the entries in `dir`, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
