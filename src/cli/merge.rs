//! `spar merge PARTS… -o OUT.exr`: the raw parts of one render (tiles,
//! regions, sample blocks) into the whole raw render, bit for bit what one
//! machine would have rendered. Refuses parts of other renders, overlaps,
//! gaps, half-float and lossy files (exit 2, the error named first).

use super::error::CliError;
use crate::farm::merge::merge;
use crate::farm::part::{carried_metadata, raw_image, read_part};
use crate::farm::progress::{ProgressMode, Reporter};
use crate::image::{PixelType, WriteOptions};
use crate::render::PartSpec;
use rayon::prelude::*;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Raw EXR parts written by `spar render --tile/--region/--samples`.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged raw EXR (develop it with `spar develop`).
    #[arg(long, short)]
    pub output: PathBuf,
    /// Progress lines: auto, log, plain, openjd, none (a merge prints events
    /// only: log and plain are the same here; bar prints none).
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// No messages.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: &MergeArgs) -> Result<(), CliError> {
    if args
        .output
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("exr"))
    {
        return Err(CliError::input(format!(
            "{}: the merged raw file is an .exr file",
            args.output.display()
        )));
    }
    super::common::check_output(&args.output)?;
    let reporter = Reporter::new(if args.quiet {
        ProgressMode::None
    } else {
        args.progress
    });
    reporter.event("start", &format!("merge {} parts", args.parts.len()));
    let parts = args
        .parts
        .par_iter()
        .map(|p| read_part(p))
        .collect::<Result<Vec<_>, _>>()?;
    let merged = merge(&parts)?;
    let spec = PartSpec::whole(merged.width, merged.height, merged.samples.total);
    let image = raw_image(
        &spec,
        &merged.samples.nodes(),
        &merged.channels,
        &merged.data,
        &carried_metadata(&parts[0]),
    )
    // The merged values are checked: an image of them that cannot be
    // made is spar's failure.
    .map_err(CliError::internal)?;
    crate::image::write(&args.output, &image, WriteOptions::new(PixelType::F32))?;
    reporter.event("wrote", &args.output.display().to_string());
    if !args.quiet && !reporter.prints_lines() {
        eprintln!(
            "merged {} parts into {}",
            parts.len(),
            args.output.display()
        );
    }
    Ok(())
}
