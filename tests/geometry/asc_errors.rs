//! Malformed `.asc` files give an error naming the file and the line, and
//! nothing a file contains makes the reader or the stone builder panic:
//! garbage lines, truncations and flipped bytes of a real design, and
//! random designs.

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use spar::geometry::asc::{parse_asc, AscError};
use std::path::Path;

const HEAD: &str = "GemCad 5.0\r\ng 96 0.0\r\ny 8 y\r\nI 1.54\r\nH A test design\r\n";

fn trichecker() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems/trichecker12.asc"))
        .unwrap()
}

/// The error for `HEAD + body`: its line and message.
fn error(body: &str) -> (usize, String) {
    let text = format!("{HEAD}{body}");
    match parse_asc(text.as_bytes(), "bad.asc") {
        Err(AscError::Syntax {
            file,
            line,
            message,
        }) => {
            assert_eq!(file, "bad.asc");
            (line, message)
        }
        other => panic!("{body:?}: expected a syntax error, got {other:?}"),
    }
}

#[test]
fn malformed_lines_are_named_with_their_line_number() {
    // HEAD has five lines; the body starts on line 6.
    let cases: &[(&str, usize, &str)] = &[
        ("a -41.0\r\n", 6, "missing tier distance"),
        (
            "a -41.0 0.6 96\r\na x 0.5 1\r\n",
            7,
            "tier angle `x` is not a finite number",
        ),
        ("a 95 0.5 1\r\n", 6, "outside"),
        ("a -41 0.6\r\n", 6, "at least one index"),
        ("a -41 0.6 n P1 4\r\n", 6, "before any index"),
        ("a -41 0.6 4 n\r\n", 6, "`n` must be followed"),
        ("a -41 0.6 4 n P1 n P2\r\n", 6, "named twice"),
        ("a -41 0.6 4 8 zz 12\r\n", 6, "found `zz`"),
        ("a -41 0.6 4 NaN\r\n", 6, "expected an index"),
        ("a -41 inf 4\r\n", 6, "not a finite number"),
        ("\r\n12 24 36\r\n", 7, "no tier line precedes"),
        (
            "a -41 0.6 4\r\nH x\r\n12 24\r\n",
            8,
            "no tier line precedes",
        ),
        ("G Meet culet\r\n", 6, "no tier line precedes"),
        ("g 96 0\r\n", 6, "second gear line (the first is line 2)"),
        ("Q 1 2 3\r\n", 6, "unknown record `Q`"),
        ("a -41 0.6 4\r\ny 0 y\r\n", 7, "symmetry order 0"),
        ("y 8 maybe\r\n", 6, "must be y or n"),
        ("I -1.5\r\n", 6, "must be positive"),
        ("I\r\n", 6, "missing refractive index"),
        ("", 5, "without any facet tier"),
    ];
    for &(body, line, words) in cases {
        let (got_line, message) = error(body);
        assert_eq!(got_line, line, "{body:?}: {message}");
        assert!(
            message.contains(words),
            "{body:?}: `{message}` lacks `{words}`"
        );
    }
    // The Display form is `file:line: message`.
    let e = parse_asc(format!("{HEAD}a -41.0\n").as_bytes(), "dir/bad.asc").unwrap_err();
    assert!(e.to_string().starts_with("dir/bad.asc:6: "), "{e}");
}

#[test]
fn gear_line_errors() {
    for (text, words) in [
        ("g 0 0\na 0 1 0\n", "non-zero whole number"),
        ("g 96.5 0\na 0 1 0\n", "non-zero whole number"),
        ("g 96 zero\na 0 1 0\n", "gear offset `zero`"),
        ("g 96 0 7\na 0 1 0\n", "g <teeth> <offset>"),
    ] {
        match parse_asc(text.as_bytes(), "g.asc") {
            Err(AscError::Syntax {
                line: 1, message, ..
            }) => assert!(message.contains(words), "{message}"),
            other => panic!("{text:?}: {other:?}"),
        }
    }
}

#[test]
fn line_numbers_count_every_line_ending() {
    // CR LF, lone CR and LF all end a line; Windows-1252 bytes do not
    // disturb the count.
    let text = b"GemCad 5.0\rH D\xE9sign \x96 1\r\nH x\n\na -41 0.6 zz\r\n";
    match parse_asc(text, "w.asc") {
        Err(AscError::Syntax { line, .. }) => assert_eq!(line, 5),
        other => panic!("{other:?}"),
    }
    let d = parse_asc(b"GemCad 5.0\rH D\xE9sign \x96 1\rg 8 0\ra 0 1 0\r", "w.asc").unwrap();
    assert_eq!(d.headers, ["Désign – 1"]);
}

#[test]
fn designs_that_enclose_nothing_say_so() {
    // Trichecker-12 without its crown: open toward +z.
    let text = String::from_utf8(trichecker()).unwrap();
    let open: String = text
        .lines()
        .filter(|l| !l.starts_with("a 2") && !l.starts_with("a 1"))
        .map(|l| format!("{l}\n"))
        .collect();
    let e = parse_asc(open.as_bytes(), "open.asc")
        .unwrap()
        .stone()
        .unwrap_err();
    let m = e.to_string();
    assert!(
        m.starts_with("open.asc: ") && m.contains("do not enclose"),
        "{m}"
    );
    // Distances are non-negative, so only planes through the centre can
    // leave nothing: a table and a culet both at distance 0.
    let e = parse_asc(
        b"g 96 0\na 0 0 0\na -0 0 0\na 90 1 0 24 48 72\n",
        "empty.asc",
    )
    .unwrap()
    .stone()
    .unwrap_err();
    assert!(e.to_string().contains("enclose nothing"), "{e}");
}

#[test]
fn facets_that_do_not_survive_are_reported() {
    let mut text = String::from_utf8(trichecker()).unwrap();
    // A table far above the crown's point, and a girdle facet repeated.
    text.push_str("a 0.000000 2.0 96 n T\r\na -90.000000 1.07325092 92\r\n");
    let stone = parse_asc(text.as_bytes(), "t.asc")
        .unwrap()
        .stone()
        .unwrap();
    assert_eq!(stone.mesh.facets.len(), 48);
    assert_eq!(stone.notes.len(), 2, "{:?}", stone.notes);
    assert!(
        stone.notes[0].contains("T@96") && stone.notes[0].contains("never reaches"),
        "{}",
        stone.notes[0]
    );
    assert!(
        stone.notes[1].contains("same plane as facet 2@92"),
        "{}",
        stone.notes[1]
    ); // Like the reader's warnings, the notes name the file (and the line).
    for n in &stone.notes {
        assert!(
            n.starts_with("t.asc: facet ") && n.contains("(line "),
            "{n}"
        );
    }
}

/// Parses and builds; only checks that nothing panics and that any stone
/// built is closed.
fn survive(bytes: &[u8]) -> bool {
    match parse_asc(bytes, "fuzz.asc") {
        Ok(design) => match design.stone() {
            Ok(stone) => {
                stone.mesh.check_closed_and_oriented().unwrap();
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with("fuzz.asc: "), "{e}");
                false
            }
        },
        Err(e) => {
            assert!(e.to_string().starts_with("fuzz.asc"), "{e}");
            false
        }
    }
}

#[test]
fn fuzzed_files_never_panic() {
    let base = trichecker();
    let lines: Vec<&[u8]> = base.split(|&b| b == b'\n').collect();
    let mut rng = Pcg64::seed_from_u64(7);
    let junk: [&[u8]; 12] = [
        b"a",
        b"n",
        b"G",
        b"-0",
        b"1e308",
        b"-1e-320",
        b"NaN",
        b"\xFF\xFE",
        b"92",
        b"\t",
        b"a -90 1e-9 3",
        b"0 0 0",
    ];
    let mut built = 0;
    for round in 0..3000 {
        let mut bytes = base.clone();
        match round % 4 {
            // Truncate anywhere.
            0 => bytes.truncate(rng.gen_range(0..=base.len())),
            // Flip a few bytes.
            1 => {
                for _ in 0..rng.gen_range(1..4) {
                    let i = rng.gen_range(0..bytes.len());
                    bytes[i] = rng.gen();
                }
            }
            // Insert a garbage line made of tokens.
            2 => {
                let at = rng.gen_range(0..lines.len());
                let mut out = Vec::new();
                for (i, l) in lines.iter().enumerate() {
                    if i == at {
                        for _ in 0..rng.gen_range(1..6) {
                            out.extend_from_slice(junk[rng.gen_range(0..junk.len())]);
                            out.push(b' ');
                        }
                        out.push(b'\n');
                    }
                    out.extend_from_slice(l);
                    out.push(b'\n');
                }
                bytes = out;
            }
            // Perturb one number of a tier.
            _ => {
                let text = String::from_utf8_lossy(&base).into_owned();
                let mut words: Vec<String> = text.split(' ').map(str::to_owned).collect();
                let i = rng.gen_range(0..words.len());
                if let Ok(x) = words[i].parse::<f64>() {
                    words[i] = format!("{}", x * rng.gen_range(-2.0..2.0));
                }
                bytes = words.join(" ").into_bytes();
            }
        }
        built += survive(&bytes) as usize;
    }
    // Most mutations leave a buildable design; some must not.
    assert!(built > 300 && built < 3000, "{built} of 3000 built");
}

#[test]
fn random_designs_never_panic() {
    let mut rng = Pcg64::seed_from_u64(11);
    let mut built = 0;
    for _ in 0..400 {
        let mut text = format!(
            "GemCad 5.0\ng {} {}\n",
            [64, 72, 80, 96, 120, -96][rng.gen_range(0..6)],
            rng.gen_range(0..3)
        );
        for _ in 0..rng.gen_range(1..12) {
            let angle: f64 = rng.gen_range(-90.0..90.0);
            let distance: f64 = rng.gen_range(0.2..1.2);
            let n = rng.gen_range(1..17);
            let first: u32 = rng.gen_range(0..96);
            let indices: Vec<String> = (0..n)
                .map(|k| ((first + k * 96 / n) % 96).to_string())
                .collect();
            text.push_str(&format!(
                "a {angle:.6} {distance:.8} {}\n",
                indices.join(" ")
            ));
        }
        if rng.gen_bool(0.7) {
            text.push_str("a 0 0.4 96\na -0 -0.8 96\na 90 1 0 24 48 72\n");
        }
        built += survive(text.as_bytes()) as usize;
    }
    assert!(built > 100, "{built} of 400 built");
}
