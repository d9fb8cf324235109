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
//! `progress` lines come whenever the percentage passes a whole number.
//! `--progress openjd` prints the same events the way Open Job
//! Description's session runner reads them: `openjd_progress: 25.0` (a
//! percentage) and `openjd_status: <text>` for the others.
//! `--progress bar` draws a bar on stderr; `none` prints nothing;
//! `auto` (the default) is `bar` on a terminal and `plain` otherwise.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::Instant;

/// `--progress`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Default)]
pub enum ProgressMode {
    #[default]
    Auto,
    Bar,
    Plain,
    Openjd,
    None,
}

impl ProgressMode {
    /// `Auto` made concrete: `Bar` if stderr is a terminal, else `Plain`.
    pub fn resolve(self) -> ProgressMode {
        match self {
            ProgressMode::Auto if std::io::stderr().is_terminal() => ProgressMode::Bar,
            ProgressMode::Auto => ProgressMode::Plain,
            m => m,
        }
    }
}

/// Prints progress lines in one of the line modes (plain, openjd); does
/// nothing in the others.
pub struct Reporter {
    mode: ProgressMode,
    start: Instant,
    last_percent: Mutex<i64>,
}

impl Reporter {
    pub fn new(mode: ProgressMode) -> Reporter {
        Reporter {
            mode: mode.resolve(),
            start: Instant::now(),
            last_percent: Mutex::new(-1),
        }
    }

    /// Whether this reporter prints lines (plain or openjd).
    pub fn prints_lines(&self) -> bool {
        matches!(self.mode, ProgressMode::Plain | ProgressMode::Openjd)
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
            ProgressMode::Plain => self.line(&format!("spar: {keyword} {text}")),
            ProgressMode::Openjd => self.line(&format!("openjd_status: {keyword} {text}")),
            _ => {}
        }
    }

    /// `done` of `total` tiles finished.
    pub fn tiles(&self, done: usize, total: usize) {
        if !self.prints_lines() || total == 0 {
            return;
        }
        let percent = 100.0 * done as f64 / total as f64;
        // Check and print under one lock, so lines come out in order.
        let mut last = self.last_percent.lock().expect("not poisoned");
        let whole = percent.floor() as i64;
        if whole <= *last {
            return;
        }
        *last = whole;
        match self.mode {
            ProgressMode::Plain => self.line(&format!(
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
