//! `spar develop RAW.exr --mode … -o …`: display images (and the Stokes
//! EXR) from a complete raw render — what `spar merge` or `spar render
//! --raw` wrote — through the same code as `spar render`.

use super::common::{check_memory, check_output, output_path, write_modes};
use super::error::CliError;
use crate::farm::part::{load_film, read_part};
use crate::farm::progress::{ProgressMode, Reporter};
use crate::render::output::OutputMode;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct DevelopArgs {
    /// A complete raw EXR (from `spar merge` or `spar render --raw`).
    pub raw: PathBuf,
    /// Camera modes, comma-separated (as for `spar render`); the raw file
    /// must hold their wavelengths.
    #[arg(long, short, value_delimiter = ',', default_value = "color")]
    pub mode: Vec<OutputMode>,
    /// Output file; with several modes each mode's name is appended.
    #[arg(long, short, default_value = "spar.png")]
    pub output: PathBuf,
    /// Wavelength of the single-wavelength modes, nm (default: the
    /// render's).
    #[arg(long)]
    pub wavelength: Option<f64>,
    /// Progress lines: auto, log, plain, openjd, none (events only: log and
    /// plain are the same here).
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// No messages.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: &DevelopArgs) -> Result<(), CliError> {
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() {
        return Err(CliError::input("--mode needs at least one mode"));
    }
    for &m in &modes {
        check_output(&output_path(&args.output, m, modes.len() > 1))?;
    }
    let part = read_part(&args.raw)?;
    // The film and each developed image are copies of about the raw size.
    check_memory(
        part.data.len() as f64 * 4.0 * (2 + modes.len()) as f64,
        &format!(
            "developing {} in {} mode(s)",
            args.raw.display(),
            modes.len()
        ),
    )?;
    let dev = load_film(part)?;
    let mono = args.wavelength.unwrap_or(dev.mono_nm);
    let reporter = Reporter::new(if args.quiet {
        ProgressMode::None
    } else {
        args.progress
    });
    write_modes(
        &dev.film,
        &modes,
        &dev.color,
        mono,
        &args.output,
        &dev.metadata,
        args.quiet,
        &reporter,
    )
}
