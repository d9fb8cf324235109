//! Seeded, deterministic mutations of text and bytes for the fuzz tests
//! (stable Rust: a mutation loop under `cargo test`, no fuzzing engine).

use rand::Rng;
use rand_pcg::Pcg64Mcg;

/// Values that break assumptions: zeros, negatives, extremes, non-finite
/// numbers, huge integers, wrong types, garbage strings.
pub const VALUES: [&str; 24] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "99999999999999999999",
    "\"\"",
    "\"x\"",
    "\"builtin:nope\"",
    "\"../../../../../../dev/null\"",
    "\"\\u0000\\u00ff\"",
    "true",
    "[]",
    "[1, 2, 3, 4]",
    "[[0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]]",
    "[nan, inf, -inf]",
    "{}",
    "1979-05-27T07:32:00Z",
];

/// One mutation of TOML-like text: a line deleted, duplicated or moved, a
/// value replaced by one of [`VALUES`] or its type swapped, a number
/// inside an array replaced, the text truncated, garbage inserted.
pub fn mutate_text(rng: &mut Pcg64Mcg, text: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return "x".into();
    }
    let pick = rng.gen_range(0..lines.len());
    match rng.gen_range(0..9) {
        0 => {
            lines.remove(pick);
        }
        1 => {
            let l = lines[pick].clone();
            lines.insert(pick, l);
        }
        2 | 3 => {
            // A value replaced, on a line that has one.
            let with_value: Vec<usize> = (0..lines.len())
                .filter(|&i| lines[i].contains('='))
                .collect();
            if let Some(&i) = with_value.get(rng.gen_range(0..with_value.len().max(1))) {
                let key = lines[i].split('=').next().unwrap().to_string();
                let v = VALUES[rng.gen_range(0..VALUES.len())];
                lines[i] = format!("{key}= {v}");
            }
        }
        4 => {
            // A number replaced wherever numbers are (inside arrays and
            // inline tables too).
            let l = &lines[pick];
            let starts: Vec<usize> = l
                .char_indices()
                .filter(|&(i, c)| {
                    (c.is_ascii_digit() || c == '-')
                        && !l[..i]
                            .ends_with(|p: char| p.is_ascii_alphanumeric() || p == '.' || p == '_')
                })
                .map(|(i, _)| i)
                .collect();
            if let Some(&s) = starts.get(rng.gen_range(0..starts.len().max(1))) {
                let end = l[s + 1..]
                    .find(|c: char| {
                        !(c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '+')
                    })
                    .map_or(l.len(), |e| s + 1 + e);
                let v = [
                    "0",
                    "-1",
                    "1e308",
                    "nan",
                    "inf",
                    "-0.0",
                    "1e-308",
                    "4294967295",
                    "1e20",
                ][rng.gen_range(0..9)];
                lines[pick] = format!("{}{v}{}", &l[..s], &l[end..]);
            }
        }
        5 => {
            // Type swap: the value quoted, or a string unquoted.
            if let Some((k, v)) = lines[pick].clone().split_once('=') {
                let v = v.trim();
                lines[pick] =
                    if let Some(inner) = v.strip_prefix('"').and_then(|v| v.strip_suffix('"')) {
                        format!("{k}= {inner}")
                    } else {
                        format!("{k}= \"{v}\"")
                    };
            }
        }
        6 => {
            let to = rng.gen_range(0..lines.len());
            let l = lines.remove(pick);
            lines.insert(to.min(lines.len()), l);
        }
        7 => {
            let joined = lines.join("\n");
            let mut cut = rng.gen_range(0..joined.len().max(1));
            while !joined.is_char_boundary(cut) {
                cut -= 1;
            }
            return joined[..cut].to_string();
        }
        _ => {
            let garbage = [
                "[",
                "]]",
                "=",
                "\"",
                "{",
                "[[object]]",
                "[camera]",
                "\u{0}",
                "é",
                "#",
                "\\",
            ];
            let g = garbage[rng.gen_range(0..garbage.len())];
            let l = &mut lines[pick];
            let mut at = rng.gen_range(0..=l.len());
            while !l.is_char_boundary(at) {
                at -= 1;
            }
            l.insert_str(at, g);
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
}

/// Applies 1–3 mutations.
pub fn mutate_text_n(rng: &mut Pcg64Mcg, text: &str) -> String {
    let mut t = text.to_string();
    for _ in 0..rng.gen_range(1..=3) {
        t = mutate_text(rng, &t);
    }
    t
}
