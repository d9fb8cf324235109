//! Quiet logs (issue 16 item 6): without a terminal, `spar render` prints a
//! progress line every tenth of the tiles or every 5 s, whichever first
//! (`--progress log`, what `auto` becomes when stderr is not a terminal),
//! and `--progress plain` one line per tile for farm logs.

use crate::support::farm::write_scene;
use crate::support::run::spar_ok;

/// The `spar: progress` lines of a run's stdout, as (done, total).
fn progress(out: &std::process::Output) -> Vec<(usize, usize)> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_prefix("spar: progress "))
        .map(|l| {
            let (done, total) = l.split(' ').next().unwrap().split_once('/').unwrap();
            (done.parse().unwrap(), total.parse().unwrap())
        })
        .collect()
}

/// Seconds the `spar: done` line reports.
fn seconds(out: &std::process::Output) -> f64 {
    let text = String::from_utf8_lossy(&out.stdout);
    let done = text
        .lines()
        .find_map(|l| l.strip_prefix("spar: done "))
        .unwrap_or_else(|| panic!("no done line: {text}"));
    done.trim_end_matches('s').parse().unwrap()
}

#[test]
fn without_a_terminal_progress_is_a_few_lines_and_plain_is_one_per_tile() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 256x256 pixels in 16x16 tiles: 256 tiles (the count).
    write_scene(d, 256, 256, 1);
    let base = [
        "render",
        "scene.toml",
        "--wavelengths",
        "550nm",
        "--max-depth",
        "4",
        "--raw",
    ];

    // stderr is a pipe here, not a terminal: auto is log.
    let out = spar_ok(d, &[&base[..], &["-o", "auto.exr"]].concat());
    let lines = progress(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("spar: start render scene.toml"), "{text}");
    // One line per tenth of the tiles, and one more per 5 s the render
    // took beyond that.
    let bound = 10 + (seconds(&out) / 5.0).ceil() as usize;
    assert!(
        !lines.is_empty() && lines.len() <= bound,
        "{} progress lines (at most {bound}):\n{text}",
        lines.len()
    );
    assert_eq!(*lines.last().unwrap(), (256, 256), "{text}");
    assert!(lines.windows(2).all(|w| w[0].0 < w[1].0), "{text}");
    // --progress log is the same.
    let out = spar_ok(
        d,
        &[&base[..], &["-o", "log.exr", "--progress", "log"]].concat(),
    );
    let bound = 10 + (seconds(&out) / 5.0).ceil() as usize;
    assert!((1..=bound).contains(&progress(&out).len()));

    // --progress plain: a line per tile (one worker, so the reports come
    // in order and none is merged into the next).
    let out = spar_ok(
        d,
        &[
            &base[..],
            &["-o", "plain.exr", "--progress", "plain", "--threads", "1"],
        ]
        .concat(),
    );
    let lines = progress(&out);
    assert_eq!(
        lines,
        (1..=256).map(|n| (n, 256)).collect::<Vec<_>>(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}
