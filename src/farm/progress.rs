//! Progress for people and for farm managers.
//!
//! `--progress plain` prints lines to stdout, each flushed at once, each
//! starting `spar: ` and a keyword:
//!
//! ```text
//! spar: start render scene.toml region 0,256,0,256 samples 0..64/64 (256 tiles)
//! spar: progress 64/256 tiles 25.0% 12.3s
//! spar: checkpoint out.exr.checkpoint 64/256 tiles
//! spar: wrote out.exr
//! spar: done 49.1s
//! ```
//!
//! With `--progress plain` a `progress` line comes for every finished
//! tile (the farm's log: one line per tile; see [`Reporter::tiles`]).
//! `--progress log` prints the same lines, but only when the count of
//! finished tiles reaches another tenth of the tiles or 5 s have passed
//! since the last one, whichever comes first: at most 10 lines for a
//! render shorter than 5 s, one per 5 s beyond. Counts never go back and
//! never exceed the tiles
//! actually finished; the last line says 100%. Workers report finished
//! tiles concurrently, so their reports can arrive out of order: the count
//! printed is then the number of reports so far on top of the smallest
//! count reported (see [`TileCount`]), and a line can be left out only
//! when reports come out of order before the first one arrives.
//! `--progress openjd` prints the same events the way Open Job
//! Description's session runner reads them: `openjd_progress: 25.0` (a
//! percentage, whenever the count passes a whole one) and
//! `openjd_status: <text>` for the others.
//! `--progress bar` draws a bar on stderr; `none` prints nothing;
//! `auto` (the default) is `bar` when stderr is a terminal and `log`
//! otherwise (a job's log, CI, a pipe: a few lines, not one per tile).

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// `--progress log` prints a line at least each time this fraction of the
/// tiles has finished...
pub const LOG_FRACTION: f64 = 0.1;
/// ...or when this long has passed since its last line, whichever first.
pub const LOG_INTERVAL: Duration = Duration::from_secs(5);

/// `--progress`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Default)]
pub enum ProgressMode {
    #[default]
    Auto,
    Bar,
    /// A line every tenth of the tiles or every 5 s, whichever first.
    Log,
    /// A line per finished tile.
    Plain,
    Openjd,
    None,
}

impl ProgressMode {
    /// `Auto` made concrete: `Bar` if stderr is a terminal, else `Log`.
    pub fn resolve(self) -> ProgressMode {
        match self {
            ProgressMode::Auto if std::io::stderr().is_terminal() => ProgressMode::Bar,
            ProgressMode::Auto => ProgressMode::Log,
            m => m,
        }
    }
}

/// Finished-tile counts from reports `(done, total)` that arrive out of
/// order. Workers take the values `done` from one atomic counter, so they
/// are distinct and consecutive from `resumed + 1`, but a worker can report
/// after another that counted later. After reports `S`, the count is
/// `min(S) − 1 + |S|`, never less than before: at most `max(S)` (the `|S|`
/// distinct values from `min(S)` up), so never more than the tiles
/// finished, and `total` once every report is in. When the first report
/// to arrive is the smallest, the count is exact: one more per report.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TileCount {
    reports: usize,
    min: usize,
    count: usize,
}

impl TileCount {
    /// Takes one report of `done` tiles and returns the count to show.
    pub fn report(&mut self, done: usize) -> usize {
        self.reports += 1;
        self.min = if self.reports == 1 {
            done
        } else {
            self.min.min(done)
        };
        self.count = self.count.max(self.min.saturating_sub(1) + self.reports);
        self.count
    }
}

/// Tile counts and what was printed last: the count, the whole
/// percentage (openjd), the tenth of the tiles and when (log).
#[derive(Debug)]
struct Shown {
    tiles: TileCount,
    count: usize,
    percent: i64,
    tenth: i64,
    at: Instant,
}

/// Whether `--progress log` prints a line for `done` of `total` tiles
/// `since` its last line, which was at `tenth` tenths of the tiles: when
/// another tenth is reached (the last tile is the tenth tenth) or
/// [`LOG_INTERVAL`] has passed.
pub fn log_wants_line(done: usize, total: usize, tenth: i64, since: Duration) -> bool {
    tenth_of(done, total) > tenth || since >= LOG_INTERVAL
}

/// How many whole tenths ([`LOG_FRACTION`]) of `total` tiles `done` is.
fn tenth_of(done: usize, total: usize) -> i64 {
    (done as f64 / (total as f64 * LOG_FRACTION) + 1e-9).floor() as i64
}

/// Prints progress lines in one of the line modes (log, plain, openjd);
/// does nothing in the others.
pub struct Reporter {
    mode: ProgressMode,
    start: Instant,
    shown: Mutex<Shown>,
}

impl Reporter {
    pub fn new(mode: ProgressMode) -> Reporter {
        Reporter {
            mode: mode.resolve(),
            start: Instant::now(),
            shown: Mutex::new(Shown {
                tiles: TileCount::default(),
                count: 0,
                percent: -1,
                tenth: 0,
                at: Instant::now(),
            }),
        }
    }

    /// Whether this reporter prints lines (log, plain or openjd).
    pub fn prints_lines(&self) -> bool {
        matches!(
            self.mode,
            ProgressMode::Log | ProgressMode::Plain | ProgressMode::Openjd
        )
    }

    /// The mode, `auto` resolved.
    pub fn mode(&self) -> ProgressMode {
        self.mode
    }

    /// Whether a bar on stderr is wanted.
    pub fn wants_bar(&self) -> bool {
        self.mode == ProgressMode::Bar
    }

    fn line(&self, text: &str) {
        let mut out = std::io::stdout().lock();
        // A closed stdout must not stop a render.
        let _ = writeln!(out, "{text}");
        let _ = out.flush();
    }

    /// An event: `spar: <keyword> <text>` or `openjd_status: <keyword> <text>`.
    pub fn event(&self, keyword: &str, text: &str) {
        match self.mode {
            ProgressMode::Log | ProgressMode::Plain => {
                self.line(&format!("spar: {keyword} {text}"))
            }
            ProgressMode::Openjd => self.line(&format!("openjd_status: {keyword} {text}")),
            _ => {}
        }
    }

    /// A worker finished a tile: `done` of `total` tiles are finished (its
    /// count; reports may arrive out of order, see [`TileCount`]). Plain
    /// prints a line whenever the count goes up (one per tile), log when
    /// [`log_wants_line`], openjd when it passes a whole percentage.
    pub fn tiles(&self, done: usize, total: usize) {
        if !self.prints_lines() || total == 0 {
            return;
        }
        // Count, check and print under one lock, so lines come out in order.
        let mut shown = self.shown.lock().expect("not poisoned");
        let done = shown.tiles.report(done).min(total);
        if done <= shown.count {
            return;
        }
        shown.count = done;
        let percent = 100.0 * done as f64 / total as f64;
        let whole = percent.floor() as i64;
        let print = match self.mode {
            ProgressMode::Plain => true,
            ProgressMode::Log => log_wants_line(done, total, shown.tenth, shown.at.elapsed()),
            _ => whole > shown.percent,
        };
        if !print {
            return;
        }
        shown.percent = whole;
        shown.tenth = tenth_of(done, total);
        shown.at = Instant::now();
        match self.mode {
            ProgressMode::Log | ProgressMode::Plain => self.line(&format!(
                "spar: progress {done}/{total} tiles {percent:.1}% {:.1}s",
                self.start.elapsed().as_secs_f64()
            )),
            ProgressMode::Openjd => self.line(&format!("openjd_progress: {percent:.1}")),
            _ => {}
        }
    }

    /// Seconds since the reporter was made.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(reports: &[usize]) -> Vec<usize> {
        let mut c = TileCount::default();
        reports.iter().map(|&d| c.report(d)).collect()
    }

    #[test]
    fn out_of_order_reports_count_up_one_by_one() {
        // Tile 3's worker reported before tile 2's (the CI failure: a
        // line was left out).
        assert_eq!(counts(&[1, 3, 2, 4, 6, 5]), [1, 2, 3, 4, 5, 6]);
        // After a resume of 4 tiles.
        assert_eq!(counts(&[5, 7, 6, 8]), [5, 6, 7, 8]);
    }

    #[test]
    fn log_prints_each_tenth_or_after_5_s() {
        let quick = Duration::from_millis(10);
        // 256 tiles reported at once: a line at 26, 52, …, 256 (each a
        // tenth more), 10 in all.
        let mut tenth = 0;
        let mut lines = Vec::new();
        for done in 1..=256 {
            if log_wants_line(done, 256, tenth, quick) {
                tenth = tenth_of(done, 256);
                lines.push(done);
            }
        }
        assert_eq!(lines.len(), 10, "{lines:?}");
        assert_eq!(lines[0], 26);
        assert_eq!(*lines.last().unwrap(), 256);
        // Three tiles: every one is a tenth more.
        assert!((1..=3).all(|d| log_wants_line(d, 3, tenth_of(d - 1, 3), quick)));
        // Within a tenth, only time brings a line.
        assert!(!log_wants_line(27, 256, 1, Duration::from_millis(4999)));
        assert!(log_wants_line(27, 256, 1, LOG_INTERVAL));
    }

    #[test]
    fn counts_never_go_back_nor_past_the_finished_tiles() {
        let mut rng = 0x2545_f491_4f6c_dd1du64;
        for trial in 0..2000 {
            let resumed = trial % 5;
            let total = resumed + 1 + trial % 17;
            let mut order: Vec<usize> = (resumed + 1..=total).collect();
            for i in (1..order.len()).rev() {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                order.swap(i, (rng % (i as u64 + 1)) as usize);
            }
            let shown = counts(&order);
            let mut seen_max = 0;
            for (k, (&c, &d)) in shown.iter().zip(&order).enumerate() {
                seen_max = seen_max.max(d);
                assert!(c <= seen_max, "{order:?} → {shown:?}");
                assert!(k == 0 || c >= shown[k - 1], "{order:?} → {shown:?}");
            }
            assert_eq!(*shown.last().unwrap(), total, "{order:?}");
        }
    }
}
