//! Fuzzing the scene loader (stable Rust: a seeded, deterministic mutation
//! loop). Every scene file of the repository and the embedded default
//! scene, mutated — keys deleted, values of the wrong type, numeric
//! extremes (0, -1, 1e308, nan, inf, huge integers), garbage strings,
//! lines duplicated, moved or cut off — must load or fail with an error
//! naming the file and the line (or saying why no line applies), never
//! panic. A sample of the mutants goes through `spar render`: exit 0 or 2,
//! never a crash; no output file on 2; no NaN in an image written.

use crate::support::fuzz as fuzz_common;

use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use spar::scene::{builtin, Scene};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

/// (name, text) of every seed scene.
fn seeds() -> Vec<(String, String)> {
    let mut seeds: Vec<(String, String)> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    seeds.sort();
    seeds.push(("(default scene)".into(), builtin::DEFAULT_SCENE.to_string()));
    assert!(seeds.len() >= 5, "{seeds:?}");
    seeds
}

/// Errors without a line: the ones that concern the scene as a whole, or
/// a key that is not there.
const NO_LINE: [&str; 2] = [
    "the scene has no light and no background",
    "missing field `",
];

#[test]
fn mutated_scenes_load_or_name_file_and_line() {
    let mut rng = Pcg64Mcg::seed_from_u64(15);
    let seeds = seeds();
    let base = scenes_dir();
    let (mut ok, mut refused) = (0, 0);
    let mut no_line = Vec::new();
    let cases = 5000;
    for case in 0..cases {
        let (name, text) = &seeds[case % seeds.len()];
        let mutant = fuzz_common::mutate_text_n(&mut rng, text);
        let file = format!("mutant-{case}.toml");
        let result = catch_unwind(AssertUnwindSafe(|| Scene::parse(&mutant, &file, &base)));
        let result = result.unwrap_or_else(|_| {
            panic!("case {case} ({name}) panicked the scene loader; the mutant:\n{mutant}")
        });
        match result {
            Ok(_) => ok += 1,
            Err(e) => {
                refused += 1;
                let msg = e.to_string();
                assert!(
                    msg.starts_with(&format!("{file}:")),
                    "case {case} ({name}): `{msg}` does not name the file; the mutant:\n{mutant}"
                );
                if !(e.line.is_some() || NO_LINE.iter().any(|n| e.message.contains(n))) {
                    no_line.push(format!("case {case} ({name}): `{msg}`"));
                }
                if let Some(line) = e.line {
                    // An error at the end of input is on the line after
                    // the last newline.
                    assert!(
                        line >= 1 && line <= mutant.lines().count() + 1,
                        "case {case}: line {line} of a {}-line file: {msg}",
                        mutant.lines().count()
                    );
                }
            }
        }
    }
    assert!(
        no_line.is_empty(),
        "errors naming no line:\n{}",
        no_line.join("\n")
    );
    // The mutations must both break and keep scenes, or they test little.
    assert!(
        ok > cases / 20 && refused > cases / 4,
        "{ok} loaded, {refused} refused"
    );
}

/// Copies the scenes directory (meshes, textures) to `to`.
fn copy_scenes(to: &Path) {
    let from = scenes_dir();
    let mut stack = vec![from.clone()];
    while let Some(dir) = stack.pop() {
        let rel = dir.strip_prefix(&from).unwrap();
        std::fs::create_dir_all(to.join(rel)).unwrap();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                std::fs::copy(&path, to.join(rel).join(path.file_name().unwrap())).unwrap();
            }
        }
    }
}

#[test]
fn mutated_scenes_through_spar_render_exit_0_or_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_scenes(d);
    let mut rng = Pcg64Mcg::seed_from_u64(1515);
    let seeds = seeds();
    let mut codes = [0usize; 2];
    // 48 mutants: most fail to load (exit 2); enough render (exit 0) that
    // both outcomes are seen whatever the list of shipped scenes (with 24,
    // adding scenes/quartz-brilliant.toml left none that rendered).
    for case in 0..48 {
        let (name, text) = &seeds[case % seeds.len()];
        let mutant = fuzz_common::mutate_text_n(&mut rng, text);
        std::fs::write(d.join("mutant.toml"), &mutant).unwrap();
        // Depth 8 bounds a mutant's trees (a mutated max_depth with
        // pruning off could take hours, which is the scene's right).
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_spar"))
            .args([
                "render",
                "mutant.toml",
                "--resolution",
                "8x8",
                "--samples",
                "1",
                "--max-depth",
                "8",
                "--quiet",
                "--mode",
                "color,stokes",
                "-o",
                "out.png",
            ])
            .current_dir(d)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let code = out.status.code();
        let outputs = [d.join("out-color.png"), d.join("out-stokes.exr")];
        match code {
            Some(0) => {
                codes[0] += 1;
                for p in &outputs {
                    let img = spar::image::read(p).unwrap();
                    assert!(
                        img.data().iter().all(|v| v.is_finite()),
                        "case {case} ({name}): {} holds non-finite values; the mutant:\n{mutant}",
                        p.display()
                    );
                    std::fs::remove_file(p).unwrap();
                }
            }
            Some(2) => {
                codes[1] += 1;
                assert!(
                    err.contains("spar: error: mutant.toml"),
                    "case {case}: {err}"
                );
                for p in &outputs {
                    assert!(!p.exists(), "case {case}: exit 2 left {}", p.display());
                }
            }
            _ => panic!(
                "case {case} ({name}): {:?}: {err}; the mutant:\n{mutant}",
                out.status
            ),
        }
    }
    eprintln!("exit 0 / 2: {codes:?}");
    assert!(codes[0] > 0 && codes[1] > 0, "exit 0 / 2: {codes:?}");
}
