//! Fuzzing the mesh loaders (OBJ and GemCAD `.asc`) on stable Rust: a
//! seeded, deterministic mutation loop over the shipped gems (byte flips,
//! line deletions, duplications and swaps, numbers replaced by extremes
//! such as 1e30, nan and -0, truncation, junk lines). Every case runs
//! in-process through the loader and validator, which must not panic and
//! must either give a usable mesh or an error naming the file and a line
//! (or one of the whole-file reasons); a sample of cases runs through
//! `spar render`, which must exit 0 or 2 (never a signal or a panic) and
//! leave no output file when it exits 2.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::geometry::validate::{mesh_from_bytes, LoadedMesh};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use crate::support::mesh as mesh_common;

/// A mesh file: its name and bytes.
type Case = (String, Vec<u8>);

/// The shipped gem meshes.
fn seeds() -> Vec<Case> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems");
    let mut out: Vec<Case> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("obj" | "asc")))
        .map(|p| {
            (
                p.file_name().unwrap().to_str().unwrap().to_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    out.sort();
    out.push((
        "needle_cube.obj".into(),
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/needle_cube.obj"))
            .unwrap(),
    ));
    out
}

/// Numbers that stress a loader.
const EXTREMES: [&str; 14] = [
    "1e30",
    "-1e30",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "-0",
    "0",
    "1e-320",
    "1e15",
    "2e15",
    "1e400",
    "99999999999999999999",
    "0x10",
];

/// Junk that may become a line.
const JUNK: [&str; 10] = [
    "f",
    "v",
    "g",
    "f 1",
    "f 1 2 999999",
    "f -1 -2 -3",
    "v 1 2",
    "\u{FEFF}",
    "a -90 1e-9 3",
    "f 0 0 0",
];

fn split_lines(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect()
}

fn join_lines(lines: &[Vec<u8>]) -> Vec<u8> {
    lines.join(&b'\n')
}

/// One mutation of `base`, chosen by `kind`.
fn mutate(base: &[u8], kind: usize, rng: &mut Pcg64) -> Vec<u8> {
    let mut lines = split_lines(base);
    let pick = |rng: &mut Pcg64, n: usize| rng.gen_range(0..n.max(1));
    match kind {
        // Truncate anywhere.
        0 => base[..rng.gen_range(0..=base.len())].to_vec(),
        // Flip a few bytes.
        1 => {
            let mut b = base.to_vec();
            for _ in 0..rng.gen_range(1..4) {
                let i = pick(rng, b.len());
                b[i] = rng.gen();
            }
            b
        }
        // Delete a line.
        2 => {
            let i = pick(rng, lines.len());
            lines.remove(i);
            join_lines(&lines)
        }
        // Duplicate a line.
        3 => {
            let i = pick(rng, lines.len());
            let l = lines[i].clone();
            lines.insert(i, l);
            join_lines(&lines)
        }
        // Swap two lines.
        4 => {
            let (i, j) = (pick(rng, lines.len()), pick(rng, lines.len()));
            lines.swap(i, j);
            join_lines(&lines)
        }
        // Insert a junk line.
        5 => {
            let i = pick(rng, lines.len());
            lines.insert(i, JUNK[pick(rng, JUNK.len())].as_bytes().to_vec());
            join_lines(&lines)
        }
        // Replace one number by an extreme, or perturb it slightly.
        _ => {
            let text = String::from_utf8_lossy(base).into_owned();
            let mut words: Vec<String> = text.split(' ').map(str::to_owned).collect();
            let numeric: Vec<usize> = (0..words.len())
                .filter(|&i| words[i].trim().parse::<f64>().is_ok())
                .collect();
            if numeric.is_empty() {
                return base.to_vec();
            }
            let i = numeric[pick(rng, numeric.len())];
            let end = if words[i].ends_with('\n') { "\n" } else { "" };
            let x: f64 = words[i].trim().parse().unwrap();
            words[i] = if rng.gen_bool(0.6) {
                format!("{}{end}", EXTREMES[pick(rng, EXTREMES.len())])
            } else {
                format!("{}{end}", x * (1.0 + rng.gen_range(-1e-3..1e-3)))
            };
            words.join(" ").into_bytes()
        }
    }
}

/// Errors every mesh file can have that no single line causes.
const WHOLE_FILE: [&str; 6] = [
    "no faces",
    "encloses negative volume",
    "do not enclose a stone",
    "unknown mesh format",
    "there are no planes",
    "do not form a closed surface",
];

/// Does an error name its file and a line (or say why it cannot)?
fn located(message: &str, file: &str) -> bool {
    let Some(rest) = message.strip_prefix(file) else {
        return false;
    };
    let numbered_line = rest.strip_prefix(':').is_some_and(|r| {
        r.split(':')
            .next()
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    });
    numbered_line || rest.contains("line ") || WHOLE_FILE.iter().any(|w| rest.contains(w))
}

/// Loads in-process; panics (failing the test) on a panic or an unlocated
/// error; returns whether the mesh loaded.
fn check(bytes: &[u8], file: &str, case: usize) -> bool {
    let result = catch_unwind(AssertUnwindSafe(|| mesh_from_bytes(bytes, file)));
    let result = result.unwrap_or_else(|_| {
        panic!(
            "case {case}: the loader panicked on {file}:\n{}",
            String::from_utf8_lossy(bytes)
        )
    });
    match result {
        Ok(LoadedMesh { mesh, warnings, .. }) => {
            assert!(!mesh.triangles.is_empty(), "case {case}: no triangles");
            assert!(
                mesh.positions.iter().all(|p| p.is_finite()),
                "case {case}: a non-finite vertex loaded"
            );
            assert!(
                mesh.facets
                    .iter()
                    .all(|f| f.normal.is_finite() && f.offset.is_finite()),
                "case {case}: a non-finite facet plane"
            );
            for w in &warnings {
                assert!(
                    w.starts_with(file),
                    "case {case}: warning without its file: {w}"
                );
            }
            true
        }
        Err(e) => {
            assert!(
                located(&e, file),
                "case {case}: error without a location: {e}"
            );
            false
        }
    }
}

#[test]
fn mutated_gems_load_or_fail_with_a_location_and_never_panic() {
    let seeds = seeds();
    let mut rng = Pcg64::seed_from_u64(15);
    let (mut loaded, mut refused) = (0, 0);
    let cases = 4000;
    for case in 0..cases {
        let (name, base) = &seeds[case % seeds.len()];
        let bytes = mutate(base, rng.gen_range(0..8), &mut rng);
        if check(&bytes, name, case) {
            loaded += 1;
        } else {
            refused += 1;
        }
    }
    // The mutations are neither all harmless nor all fatal.
    assert!(
        loaded > cases / 10 && refused > cases / 10,
        "{loaded} loaded, {refused} refused"
    );
}

fn spar_render(dir: &Path, mesh: &str) -> i32 {
    let out = mesh_common::render_mesh(dir, mesh);
    match out.status.code() {
        Some(code) => code,
        None => panic!(
            "spar render {mesh} died by a signal:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ),
    }
}

#[test]
fn mutated_gems_through_spar_render_exit_0_or_2_and_write_nothing_on_2() {
    let seeds = seeds();
    let mut rng = Pcg64::seed_from_u64(1515);
    // Ten cases the loader refuses and ten it accepts.
    let (mut bad, mut good): (Vec<Case>, Vec<Case>) = (vec![], vec![]);
    let mut case = 0;
    while bad.len() < 10 || good.len() < 10 {
        let (name, base) = &seeds[case % seeds.len()];
        let bytes = mutate(base, rng.gen_range(0..8), &mut rng);
        let list = if check(&bytes, name, case) {
            &mut good
        } else {
            &mut bad
        };
        if list.len() < 10 {
            list.push((name.clone(), bytes));
        }
        case += 1;
        assert!(case < 10_000, "the mutations never gave ten of each");
    }
    for (expected, (name, bytes)) in bad
        .iter()
        .map(|c| (2, c))
        .chain(good.iter().map(|c| (0, c)))
    {
        let dir = tempfile::tempdir().unwrap();
        let path: PathBuf = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let code = spar_render(dir.path(), name);
        assert!(code == 0 || code == 2, "{name}: exit {code}");
        // What the loader refuses, spar refuses; what it accepts may still
        // be refused by the scene's own checks.
        if expected == 2 {
            assert_eq!(code, 2, "{name}: the loader refused it, spar exited {code}");
        }
        if code == 2 {
            assert!(
                !dir.path().join("out.png").exists(),
                "{name}: output left behind"
            );
        }
    }
}
