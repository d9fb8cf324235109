//! Farm files with values that are no sums: `spar merge` refuses a part
//! holding NaN or infinite pixels, and `spar develop` a raw render holding
//! them — exit status 2, the file, the first pixel, the channel and the
//! count named, no output written.

use crate::support::farm::write_scene;
use crate::support::run::{spar, spar_ok};
use spar::image::{PixelType, WriteOptions};
use std::path::Path;

/// Copies the raw file `from` to `to` with `value` at pixel (x, y) of
/// channel `c` (and in `extra` more values of that channel).
fn poison(
    dir: &Path,
    from: &str,
    to: &str,
    (x, y, c): (usize, usize, usize),
    value: f32,
    extra: usize,
) -> String {
    let mut img = spar::image::read(&dir.join(from)).unwrap();
    let (w, nch) = (img.width(), img.channels().len());
    let name = img.channels()[c].clone();
    let data = img.data_mut();
    data[(y * w + x) * nch + c] = value;
    for k in 1..=extra {
        data[(y * w + x + k) * nch + c] = value;
    }
    spar::image::write(&dir.join(to), &img, WriteOptions::new(PixelType::F32)).unwrap();
    name
}

fn refused(dir: &Path, args: &[&str], out: &str, also: &[&str]) {
    let o = spar(dir, args);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    for a in also {
        assert!(err.contains(a), "{args:?}: `{a}` not in {err}");
    }
    assert!(!dir.join(out).exists(), "{args:?} wrote {out}");
}

#[test]
fn merge_and_develop_refuse_non_finite_values() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, 16, 12, 2);
    for (tile, out) in [("0/2", "t0.exr"), ("1/2", "t1.exr")] {
        spar_ok(
            d,
            &["render", "scene.toml", "-q", "--tile", tile, "-o", out],
        );
    }
    spar_ok(d, &["render", "scene.toml", "-q", "--raw", "-o", "raw.exr"]);
    // Tile 1 of 2 is the right half: x from 8.
    let ch = poison(d, "t1.exr", "t1-nan.exr", (2, 5, 3), f32::NAN, 2);
    refused(
        d,
        &["merge", "t0.exr", "t1-nan.exr", "-o", "m.exr"],
        "m.exr",
        &[
            "spar: error: non-finite: ",
            "t1-nan.exr",
            "3 value(s)",
            "x,y = 10,5",
            &format!("channel {ch}"),
        ],
    );
    let ch = poison(d, "t0.exr", "t0-inf.exr", (0, 0, 0), f32::INFINITY, 0);
    refused(
        d,
        &["merge", "t0-inf.exr", "t1.exr", "-o", "m.exr"],
        "m.exr",
        &[
            "non-finite: ",
            "t0-inf.exr",
            "1 value(s)",
            "x,y = 0,0",
            &format!("channel {ch}"),
        ],
    );
    // Finite parts whose sum overflows float32.
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--tile",
            "0/2",
            "--samples",
            "0..1",
            "-o",
            "a.exr",
        ],
    );
    spar_ok(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--tile",
            "0/2",
            "--samples",
            "1..2",
            "-o",
            "b.exr",
        ],
    );
    let cha = poison(d, "a.exr", "a-max.exr", (1, 1, 0), f32::MAX, 0);
    poison(d, "b.exr", "b-max.exr", (1, 1, 0), f32::MAX, 0);
    refused(
        d,
        &["merge", "a-max.exr", "b-max.exr", "t1.exr", "-o", "m.exr"],
        "m.exr",
        &["overflow: ", "x,y = 1,1", &format!("channel {cha}")],
    );
    // The merge of good parts goes through, and develops.
    spar_ok(d, &["merge", "t0.exr", "t1.exr", "-q", "-o", "m.exr"]);
    spar_ok(d, &["develop", "m.exr", "-q", "-o", "dev.png"]);

    // develop: a whole raw render with NaN.
    let ch = poison(d, "raw.exr", "raw-nan.exr", (15, 11, 1), f32::NAN, 0);
    refused(
        d,
        &[
            "develop",
            "raw-nan.exr",
            "--mode",
            "color,stokes",
            "-o",
            "nan.png",
        ],
        "nan-color.png",
        &[
            "non-finite: ",
            "raw-nan.exr",
            "x,y = 15,11",
            &format!("channel {ch}"),
            "1 value(s)",
        ],
    );
    assert!(!d.join("nan-stokes.exr").exists());
}
