//! `spar develop RAW.exr --mode … -o …`: display images (and the Stokes
//! EXR) from a complete raw render — what `spar merge` or `spar render
//! --raw` wrote — through the same code as `spar render`.

use super::common::{
    check_memory, check_output, check_wavelength, mode_files, wavelength_use, write_modes,
};
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
    /// Output file (default: spar, with each mode's own extension); its
    /// extension must fit the mode, as for `spar render`; with several
    /// modes each mode's name is appended.
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Wavelength of the single-wavelength modes, nm (default: the
    /// render's). Given with stokes, the Stokes EXR holds this wavelength
    /// only (the raw file must hold it). Refused with color alone.
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
    if let Some(nm) = args.wavelength {
        check_wavelength(nm)?;
    }
    let (_, stokes_nm) = wavelength_use(args.wavelength, &modes)?;
    let files = mode_files(args.output.as_deref(), &modes)?;
    for f in &files {
        check_output(&f.path)?;
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
        &files,
        &dev.color,
        mono,
        stokes_nm,
        &dev.metadata,
        args.quiet,
        &reporter,
    )
}
