//! `spar tilt SCENE --frames N --angle DEG -o out.png`: the stone tilted
//! from −DEG to +DEG about the camera's horizontal axis (the objects turn;
//! the lights and the camera stay: `render::tilt`), one numbered frame per
//! angle (`out-000.png`, `out-001.png`, …). Frame k is exactly what `spar
//! render SCENE --tilt θk` writes: each frame goes through `spar render`,
//! whose image files are written whole (a temporary file renamed into
//! place). Every frame's flags, scene and outputs are checked before the
//! first is rendered, so a bad flag writes nothing.

use super::args::{AccelArgs, FarmArgs, SceneOverrides};
use super::common::Signals;
use super::error::CliError;
use super::render::{self, RenderArgs};
use crate::farm::progress::ProgressMode;
use crate::render::output::OutputMode;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// The most frames a tilt sequence may have.
pub const MAX_FRAMES: u32 = 10_000;

#[derive(clap::Args, Debug)]
pub struct TiltArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Number of frames (at least 2): the angles run evenly from -DEG to
    /// +DEG, both included.
    #[arg(long, value_name = "N")]
    pub frames: u32,
    /// The largest tilt, degrees (above 0, at most 90); positive brings
    /// the stone's top (image up) toward the camera.
    #[arg(long, value_name = "DEG")]
    pub angle: f64,
    /// Camera modes, comma-separated, as for spar render (default color).
    #[arg(long, short, value_delimiter = ',')]
    pub mode: Vec<OutputMode>,
    /// Output file: frame k is written with -NNN (k, three digits or more)
    /// appended to its stem: -o tilt.png writes tilt-000.png, tilt-001.png,
    /// … (default spar-000.png …; several modes name each as spar render
    /// does: tilt-000-color.png).
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Wavelength of the single-wavelength modes, nm (as for spar render).
    #[arg(long)]
    pub wavelength: Option<f64>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Worker threads (default or 0: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress or summary.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The tilt of frame `k` of `frames` (≥ 2) for a largest tilt `angle`:
/// `angle × (2k − (frames − 1)) / (frames − 1)`, so the ends are exactly
/// ∓angle, frames k and frames − 1 − k exactly opposite, and the middle
/// frame of an odd count exactly 0 (the untilted scene).
pub fn frame_angle(angle: f64, k: u32, frames: u32) -> f64 {
    let last = (frames - 1) as f64;
    angle * ((2.0 * k as f64 - last) / last)
}

/// Frame `k`'s output: `k` (zero-padded to `digits`) appended to the stem
/// of `output` (default `spar`), the extension kept.
pub fn frame_path(output: Option<&Path>, k: u32, digits: usize) -> PathBuf {
    let output = output.unwrap_or(Path::new("spar"));
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "spar".into());
    let mut name = format!("{stem}-{k:0digits$}");
    if let Some(e) = output.extension() {
        name = format!("{name}.{}", e.to_string_lossy());
    }
    output.with_file_name(name)
}

/// The frame count's digits in file names: three, or more for more than
/// 1000 frames.
fn digits(frames: u32) -> usize {
    (frames - 1).to_string().len().max(3)
}

pub fn run(args: &TiltArgs) -> Result<(), CliError> {
    if !(2..=MAX_FRAMES).contains(&args.frames) {
        return Err(CliError::input(format!(
            "--frames {}: a tilt sequence has from 2 to {MAX_FRAMES} frames",
            args.frames
        )));
    }
    if !(args.angle.is_finite() && args.angle > 0.0 && args.angle <= 90.0) {
        return Err(CliError::input(format!(
            "--angle {}: the largest tilt is a number of degrees above 0 and at most 90",
            args.angle
        )));
    }
    if let Some(t) = args.overrides.tilt {
        return Err(CliError::input(format!(
            "--tilt {t}: spar tilt sets each frame's tilt from --angle and --frames; use spar \
             render --tilt for one view"
        )));
    }
    let n = args.frames;
    let frames: Vec<RenderArgs> = (0..n).map(|k| frame_args(args, k)).collect();
    // Everything checked before anything is written.
    for f in &frames {
        render::check(f)?;
    }
    let signals = Signals::install()?;
    for (k, f) in frames.iter().enumerate() {
        if signals.stop.load(Ordering::SeqCst) {
            return Err(stopped(&signals, k, n));
        }
        if !args.quiet {
            eprintln!(
                "spar: tilt frame {k}/{n}: {}°",
                f.overrides.tilt.expect("every frame has a tilt")
            );
        }
        render::run(f).map_err(|e| {
            if signals.stop.load(Ordering::SeqCst) {
                stopped(&signals, k, n)
            } else {
                CliError::new(
                    e.kind(),
                    format!("frame {k} of {n} (frames before it are written): {e}"),
                )
            }
        })?;
    }
    Ok(())
}

/// Stopped by a signal before or during frame `k`.
fn stopped(signals: &Signals, k: usize, n: u32) -> CliError {
    CliError::internal(format!(
        "stopped by {} at frame {k} of {n}: frames 0 to {k} (exclusive) are written, nothing \
         of the rest",
        signals.name()
    ))
}

/// `spar render`'s arguments for frame `k`.
fn frame_args(args: &TiltArgs, k: u32) -> RenderArgs {
    let mut overrides = args.overrides.clone();
    overrides.tilt = Some(frame_angle(args.angle, k, args.frames));
    RenderArgs {
        scene: Some(args.scene.clone()),
        mode: args.mode.clone(),
        output: Some(frame_path(args.output.as_deref(), k, digits(args.frames))),
        wavelength: args.wavelength,
        overrides,
        farm: FarmArgs {
            progress: if args.quiet {
                ProgressMode::None
            } else {
                ProgressMode::Auto
            },
            ..FarmArgs::default()
        },
        accel: args.accel,
        threads: args.threads,
        quiet: args.quiet,
        no_checkpoint: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_run_from_minus_to_plus_with_an_exact_middle() {
        let a: Vec<f64> = (0..5).map(|k| frame_angle(12.5, k, 5)).collect();
        assert_eq!(a, vec![-12.5, -6.25, 0.0, 6.25, 12.5]);
        for n in 2..40 {
            for k in 0..n {
                assert_eq!(
                    frame_angle(7.3, k, n),
                    -frame_angle(7.3, n - 1 - k, n),
                    "{k}/{n}"
                );
            }
            assert_eq!(frame_angle(7.3, 0, n), -7.3);
            assert_eq!(frame_angle(7.3, n - 1, n), 7.3);
        }
    }

    #[test]
    fn frames_are_numbered_after_the_stem() {
        assert_eq!(
            frame_path(Some(Path::new("out/tilt.png")), 7, 3),
            PathBuf::from("out/tilt-007.png")
        );
        assert_eq!(frame_path(None, 12, 4), PathBuf::from("spar-0012"));
        assert_eq!(digits(1000), 3);
        assert_eq!(digits(1001), 4);
    }
}
