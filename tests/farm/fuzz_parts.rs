//! Fuzzing `spar merge`'s reading of parts (stable Rust: a seeded,
//! deterministic mutation loop). Valid parts of one render, made with
//! `spar render --tile` and `--samples`, are damaged — bytes truncated,
//! flipped, inserted; header fields overwritten; metadata changed or
//! removed; pixels set to NaN or infinity; the image resized — and merged
//! with their good siblings. In process (through `read_part` and `merge`):
//! no panic, and an error names the damaged file (or the pixels and
//! samples no part holds). Through the binary: exit 0 or 2, never a
//! crash, no output on 2.

use crate::support::farm::write_scene;
use crate::support::run::spar_ok;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use spar::farm::merge::merge;
use spar::farm::part::read_part;
use spar::farm::MergeError;
use spar::image::{Image, PixelType, WriteOptions};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// The good parts: two tiles, the second also as two sample blocks.
const TILES: [&str; 2] = ["t0.exr", "t1.exr"];
const BLOCKS: [&str; 3] = ["t0.exr", "t1a.exr", "t1b.exr"];

fn make_parts(d: &Path) {
    write_scene(d, 16, 12, 2);
    for (args, out) in [
        (vec!["--tile", "0/2"], "t0.exr"),
        (vec!["--tile", "1/2"], "t1.exr"),
        (vec!["--tile", "1/2", "--samples", "0..1"], "t1a.exr"),
        (vec!["--tile", "1/2", "--samples", "1..2"], "t1b.exr"),
    ] {
        let mut a = vec!["render", "scene.toml", "-q", "-o", out];
        a.extend(args);
        spar_ok(d, &a);
    }
}

/// Metadata values to try, whatever the key.
const META: [&str; 14] = [
    "",
    "x",
    "0,8,0,12",
    "0,16,0,12",
    "8,16,0,12",
    "0,99999,0,12",
    "0..1/2",
    "0..2/2",
    "0..1/4294967295",
    "1000000x1000000",
    "16x12",
    "0-1,1-2",
    "S0_450nm",
    "spar-raw-2",
];
const KEYS: [&str; 8] = [
    "spar:region",
    "spar:samples",
    "spar:nodes",
    "spar:channels",
    "spar:resolution",
    "spar:format",
    "spar:settings",
    "spar:lambdas",
];

/// A damaged copy of the part `from` written to `to`.
fn damage(rng: &mut Pcg64Mcg, d: &Path, from: &str, to: &Path) -> String {
    let bytes = std::fs::read(d.join(from)).unwrap();
    let kind = rng.gen_range(0..9);
    let mut b = bytes.clone();
    let what = match kind {
        0 => {
            let n = rng.gen_range(0..b.len());
            b.truncate(n);
            format!("truncated to {n} bytes")
        }
        1 => {
            let k = rng.gen_range(1..=8);
            for _ in 0..k {
                let i = rng.gen_range(0..b.len());
                b[i] ^= 1 << rng.gen_range(0..8);
            }
            format!("{k} bits flipped")
        }
        2 => {
            // The header (attributes, offsets): the first kilobytes.
            let end = b.len().min(4096);
            let i = rng.gen_range(8..end);
            let v: u8 = [0x00, 0xff, 0x7f, 0x80][rng.gen_range(0..4)];
            for j in i..(i + 4).min(b.len()) {
                b[j] = v;
            }
            format!("header bytes {i}.. set to {v:#x}")
        }
        3 => {
            let i = rng.gen_range(0..b.len());
            let n = rng.gen_range(1..64);
            if rng.gen_bool(0.5) {
                b.splice(i..i, std::iter::repeat_n(0xa5, n));
                format!("{n} bytes inserted at {i}")
            } else {
                let end = (i + n).min(b.len());
                b.drain(i..end);
                format!("bytes {i}..{end} removed")
            }
        }
        _ => {
            // Through the image: metadata, pixels, size.
            let mut img = spar::image::read(&d.join(from)).unwrap();
            let what = match kind {
                4 | 5 => {
                    let key = KEYS[rng.gen_range(0..KEYS.len())];
                    if rng.gen_bool(0.2) {
                        img.metadata_mut().remove(key);
                        format!("{key} removed")
                    } else {
                        let v = META[rng.gen_range(0..META.len())];
                        img.metadata_mut().insert(key.into(), v.into());
                        format!("{key} = {v}")
                    }
                }
                6 | 7 => {
                    let v = [
                        f32::NAN,
                        f32::INFINITY,
                        f32::NEG_INFINITY,
                        f32::MAX,
                        -f32::MAX,
                    ][rng.gen_range(0..5)];
                    let n = img.data().len();
                    let i = rng.gen_range(0..n);
                    img.data_mut()[i] = v;
                    format!("value {i} = {v}")
                }
                _ => {
                    let (w, h, nch) = (img.width(), img.height(), img.channels().len());
                    let (nw, nh) = (rng.gen_range(1..=w + 2), rng.gen_range(1..=h + 2));
                    let mut data = vec![0.5f32; nw * nh * nch];
                    for y in 0..nh.min(h) {
                        for x in 0..nw.min(w) {
                            data[(y * nw + x) * nch..(y * nw + x + 1) * nch]
                                .copy_from_slice(img.pixel(x, y));
                        }
                    }
                    let mut resized = Image::new(nw, nh, img.channels().to_vec(), data).unwrap();
                    for (k, v) in img.metadata() {
                        resized.metadata_mut().insert(k.clone(), v.clone());
                    }
                    img = resized;
                    format!("resized to {nw}x{nh}")
                }
            };
            spar::image::write(to, &img, WriteOptions::new(PixelType::F32)).unwrap();
            return what;
        }
    };
    std::fs::write(to, &b).unwrap();
    what
}

/// Whether a merge error is about `mutant`, or one that names pixels and
/// samples instead of a file.
fn names_it(e: &MergeError, mutant: &str) -> bool {
    e.to_string().contains(mutant)
        || matches!(e, MergeError::Missing { .. } | MergeError::Overflow { .. })
}

#[test]
fn damaged_parts_are_refused_by_name_in_process() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    make_parts(d);
    let mut rng = Pcg64Mcg::seed_from_u64(15);
    let (mut merged, mut refused) = (0, 0);
    let cases = 2000;
    for case in 0..cases {
        let set: &[&str] = if case % 2 == 0 { &TILES } else { &BLOCKS };
        let target = rng.gen_range(0..set.len());
        let name = format!("mutant-{case}.exr");
        let path = d.join(&name);
        let what = damage(&mut rng, d, set[target], &path);
        let mut files: Vec<std::path::PathBuf> = set.iter().map(|p| d.join(p)).collect();
        files[target] = path.clone();
        // The mutant first or last: the first part is the one the others
        // are compared with.
        if rng.gen_bool(0.5) {
            files.swap(0, target);
        }
        let result = catch_unwind(AssertUnwindSafe(|| {
            let parts = files
                .iter()
                .map(|p| read_part(p))
                .collect::<Result<Vec<_>, _>>()?;
            merge(&parts)
        }))
        .unwrap_or_else(|_| panic!("case {case}: {} {what}: panicked", set[target]));
        match result {
            Ok(m) => {
                merged += 1;
                assert!(m.data.iter().all(|v| v.is_finite()), "case {case}: {what}");
            }
            Err(e) => {
                refused += 1;
                assert!(
                    names_it(&e, &name),
                    "case {case}: {} {what}: `{e}` does not name it",
                    set[target]
                );
            }
        }
        std::fs::remove_file(&path).unwrap();
    }
    assert!(
        refused > cases / 2 && merged > 0,
        "{merged} merged, {refused} refused"
    );
}

#[test]
fn damaged_parts_through_spar_merge_exit_0_or_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    make_parts(d);
    let mut rng = Pcg64Mcg::seed_from_u64(1515);
    let mut codes = [0usize; 2];
    for case in 0..20 {
        let set: &[&str] = if case % 2 == 0 { &TILES } else { &BLOCKS };
        let target = rng.gen_range(0..set.len());
        let name = format!("mutant-{case}.exr");
        let what = damage(&mut rng, d, set[target], &d.join(&name));
        let mut args: Vec<&str> = vec!["merge", "-q", "-o", "out.exr"];
        args.extend(
            set.iter()
                .enumerate()
                .map(|(i, p)| if i == target { name.as_str() } else { p }),
        );
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_spar"))
            .args(&args)
            .current_dir(d)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        match out.status.code() {
            Some(0) => {
                codes[0] += 1;
                let img = spar::image::read(&d.join("out.exr")).unwrap();
                assert!(
                    img.data().iter().all(|v| v.is_finite()),
                    "case {case}: {what}"
                );
                std::fs::remove_file(d.join("out.exr")).unwrap();
            }
            Some(2) => {
                codes[1] += 1;
                assert!(
                    err.contains(&name)
                        || err.contains("error: missing: ")
                        || err.contains("error: overflow: "),
                    "case {case}: {what}: {err}"
                );
                assert!(
                    !d.join("out.exr").exists(),
                    "case {case}: exit 2 left out.exr"
                );
            }
            _ => panic!(
                "case {case}: {} {what}: {:?}: {err}",
                set[target], out.status
            ),
        }
    }
    assert!(codes[1] > 0, "exit 0 / 2: {codes:?}");
}
