//! Every way an image read or write can fail returns an error that names
//! the file, never panics, and leaves no file (not even a temporary) behind.
//! Each test runs for every backend of the build: `spar::image::{write,
//! read}` (OpenImageIO in a native build, else the pure-Rust codecs) and,
//! in a native build, `spar::image::pure` as well.

use crate::support::image::{backends, Backend};
use spar::image::{self, Cause, Image, ImageError, PixelType, WriteOptions};
use std::fs;
use std::path::Path;

fn rgb(w: usize, h: usize) -> Image {
    let data = (0..w * h * 3).map(|i| (i % 7) as f32 / 7.0).collect();
    Image::new(w, h, vec!["R".into(), "G".into(), "B".into()], data).unwrap()
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

/// The error names `path`; returns its message.
fn names_file(err: &ImageError, path: &Path) -> String {
    let message = err.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "message does not name {}: {message}",
        path.display()
    );
    message
}

fn write_err(b: &Backend, path: &Path, img: &Image, options: WriteOptions) -> (Cause, String) {
    match (b.write)(path, img, options) {
        Ok(()) => panic!("{}: writing {} succeeded", b.name, path.display()),
        Err(err) => {
            let message = names_file(&err, path);
            match err {
                ImageError::Write { cause, .. } => (cause, message),
                other => panic!("not a write error: {other:?}"),
            }
        }
    }
}

fn read_err(b: &Backend, path: &Path) -> (Cause, String) {
    match (b.read)(path) {
        Ok(_) => panic!("{}: reading {} succeeded", b.name, path.display()),
        Err(err) => {
            let message = names_file(&err, path);
            match err {
                ImageError::Read { cause, .. } => (cause, message),
                other => panic!("not a read error: {other:?}"),
            }
        }
    }
}

#[test]
fn missing_or_unwritable_directory() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let img = rgb(4, 4);
        // A directory that does not exist: OpenImageIO reports it, the
        // pure-Rust backend passes on the file system's error.
        let path = dir.path().join("no/such/dir/out.exr");
        let (cause, _) = write_err(&b, &path, &img, WriteOptions::default());
        if b.oiio {
            assert!(matches!(cause, Cause::Backend(_)), "{cause:?}");
        } else {
            assert!(
                matches!(&cause, Cause::Io(e) if e.kind() == std::io::ErrorKind::NotFound),
                "{cause:?}"
            );
        }
        // A "directory" that is a file.
        fs::write(dir.path().join("plain"), b"x").unwrap();
        let path = dir.path().join("plain/out.png");
        write_err(&b, &path, &img, WriteOptions::new(PixelType::U8));
        assert_eq!(entries(dir.path()), ["plain"]);

        // A directory without write permission. Root (as in CI containers)
        // writes anyway, so this part only means something for other users.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let locked = dir.path().join("locked");
            fs::create_dir(&locked).unwrap();
            fs::set_permissions(&locked, fs::Permissions::from_mode(0o555)).unwrap();
            if fs::write(locked.join("probe"), b"").is_ok() {
                eprintln!("SKIPPED: permission part (running as a user who ignores permissions)");
            } else {
                write_err(&b, &locked.join("out.exr"), &img, WriteOptions::default());
                assert!(entries(&locked).is_empty());
            }
            fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
        }
    }
}

#[test]
fn unknown_or_missing_extension() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let img = rgb(4, 4);
        let path = dir.path().join("out.notaformat");
        let (cause, message) = write_err(&b, &path, &img, WriteOptions::default());
        assert!(matches!(cause, Cause::Backend(_)), "{cause:?}");
        assert!(
            !message.contains(".tmp-"),
            "the temporary's name leaked: {message}"
        );
        let path = dir.path().join("no_extension");
        let (cause, _) = write_err(&b, &path, &img, WriteOptions::default());
        assert!(matches!(cause, Cause::Invalid(_)), "{cause:?}");
        assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
    }
}

#[test]
fn formats_refuse_what_they_cannot_store_and_leave_nothing() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let img = rgb(4, 4);
        let rgba = Image::new(
            2,
            1,
            vec!["R".into(), "G".into(), "B".into(), "A".into()],
            vec![0.5; 8],
        )
        .unwrap();
        // The pure-Rust backend refuses JPEG altogether, which is also a
        // refusal of these.
        for (file, image, options) in [
            ("float.png", &img, WriteOptions::new(PixelType::F32)),
            ("half.png", &img, WriteOptions::new(PixelType::Half)),
            ("bytes.exr", &img, WriteOptions::new(PixelType::U8)),
            ("sixteen.exr", &img, WriteOptions::new(PixelType::U16)),
            ("sixteen.jpg", &img, WriteOptions::new(PixelType::U16)),
            ("alpha.jpg", &rgba, WriteOptions::new(PixelType::U8)),
            (
                "linear.jpg",
                &img,
                WriteOptions::new(PixelType::U8).with_encoding(image::Encoding::Linear),
            ),
        ] {
            let (cause, message) = write_err(&b, &dir.path().join(file), image, options);
            assert!(matches!(cause, Cause::Backend(_)), "{file}: {cause:?}");
            eprintln!("{}: {message}", b.name);
        }
        // Half and float files hold linear values only.
        let srgb_half = WriteOptions::new(PixelType::Half).with_encoding(image::Encoding::Srgb);
        let (cause, _) = write_err(&b, &dir.path().join("srgb.exr"), &img, srgb_half);
        assert!(matches!(cause, Cause::Invalid(_)), "{cause:?}");
        assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
    }
}

#[test]
fn a_failed_write_keeps_the_previous_file() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("keep.png");
        (b.write)(&path, &rgb(4, 4), WriteOptions::new(PixelType::U8)).unwrap();
        let before = fs::read(&path).unwrap();
        write_err(&b, &path, &rgb(8, 8), WriteOptions::new(PixelType::F32));
        assert_eq!(fs::read(&path).unwrap(), before);
        assert_eq!(entries(dir.path()), ["keep.png"]);
        // The destination is a directory: the rename fails after the write.
        let target = dir.path().join("taken.exr");
        fs::create_dir(&target).unwrap();
        let (cause, _) = write_err(&b, &target, &rgb(4, 4), WriteOptions::default());
        assert!(matches!(cause, Cause::Io(_)), "{cause:?}");
        assert_eq!(entries(dir.path()), ["keep.png", "taken.exr"]);
    }
}

#[test]
fn reserved_metadata_keys_and_nul_characters_are_refused() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        for file in ["meta.exr", "meta.png"] {
            let path = dir.path().join(file);
            let options = WriteOptions::new(if file.ends_with("png") {
                PixelType::U8
            } else {
                PixelType::F32
            });
            for key in ["oiio:ColorSpace", "OIIO:anything", ""] {
                let img = rgb(2, 2).with_metadata(key, "ACEScg");
                let (cause, _) = write_err(&b, &path, &img, options);
                assert!(matches!(cause, Cause::Invalid(_)), "{key}: {cause:?}");
            }
            let img = rgb(2, 2).with_metadata("spar:note", "nul\0byte");
            let (cause, _) = write_err(&b, &path, &img, options);
            assert!(matches!(cause, Cause::Invalid(_)), "{cause:?}");
            let img = rgb(2, 2).with_metadata("spar:\0key", "value");
            write_err(&b, &path, &img, options);
        }
        let img = Image::new(1, 1, vec!["S\u{0}0".into()], vec![1.0]).unwrap();
        let (cause, _) = write_err(&b, &dir.path().join("c.exr"), &img, WriteOptions::default());
        assert!(matches!(cause, Cause::Invalid(_)), "{cause:?}");
        assert!(entries(dir.path()).is_empty());
    }
}

#[test]
fn missing_input() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("absent.exr");
        let (cause, _) = read_err(&b, &path);
        match cause {
            Cause::Io(e) => assert_eq!(e.kind(), std::io::ErrorKind::NotFound),
            other => panic!("{other:?}"),
        }
        read_err(&b, dir.path());
    }
}

#[test]
fn corrupt_input() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let garbage: Vec<u8> = (0..4096u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        for name in ["garbage.png", "garbage.exr", "garbage.tif", "garbage.jpg"] {
            let path = dir.path().join(name);
            fs::write(&path, &garbage).unwrap();
            let (cause, _) = read_err(&b, &path);
            assert!(matches!(cause, Cause::Backend(_)), "{name}: {cause:?}");
        }
        fs::write(dir.path().join("empty.exr"), b"").unwrap();
        read_err(&b, &dir.path().join("empty.exr"));
        // Real files with a good signature and header, then garbage or
        // nothing: the pixels do not survive.
        for (name, options) in [
            ("cut.png", WriteOptions::new(PixelType::U8)),
            ("cut.exr", WriteOptions::new(PixelType::F32)),
            ("cut_half.exr", WriteOptions::new(PixelType::Half)),
        ] {
            let path = dir.path().join(name);
            (b.write)(&path, &rgb(64, 64), options).unwrap();
            let bytes = fs::read(&path).unwrap();
            for keep in [bytes.len() / 2, bytes.len() - 13, 40] {
                fs::write(&path, &bytes[..keep]).unwrap();
                let (cause, message) = read_err(&b, &path);
                assert!(
                    matches!(cause, Cause::Backend(_)),
                    "{name} cut at {keep}: {message}"
                );
            }
            let mut scrambled = bytes.clone();
            let n = scrambled.len();
            for (i, byte) in scrambled[n / 2..].iter_mut().enumerate() {
                *byte = garbage[i % garbage.len()];
            }
            fs::write(&path, &scrambled).unwrap();
            read_err(&b, &path);
        }
    }
}

#[test]
fn missing_channel_names_the_file_and_the_channel() {
    for b in backends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stokes.exr");
        let img = Image::new(1, 1, vec!["S0".into(), "S1".into()], vec![1.0, 0.5]).unwrap();
        (b.write)(&path, &img, WriteOptions::default()).unwrap();
        let back = (b.read)(&path).unwrap();
        let err = back.channel("S2").unwrap_err();
        let message = names_file(&err, &path);
        assert!(
            message.contains("'S2'") && message.contains("S0, S1"),
            "{message}"
        );
        assert!(matches!(err, ImageError::MissingChannel { .. }));
        // No colour channels: the texture accessor says which is missing.
        let err = back.rgba().unwrap_err();
        assert!(err.to_string().contains("'R'"), "{err}");
    }
}
