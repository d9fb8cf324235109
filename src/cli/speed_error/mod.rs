//! `spar speed-error SCENE`: renders a scene under a sweep of settings
//! (depth, pruning, samples, wavelengths, spectral sampling, branching,
//! polarization model, dispersion), times each, measures its error against
//! a converged reference in every asked mode, and writes a CSV and a plot of
//! error against time with the Pareto front marked
//! (docs/speed-vs-error.md).

pub mod metrics;
pub mod reference;
pub mod results;
pub mod sweep;

use super::args::{AccelArgs, SceneOverrides};
use super::common::{load_scene, mono_wavelength};
use super::error::CliError;
use crate::render::output::OutputMode;
use crate::scene::Scene;
use metrics::Measure;
use reference::{Plan, Reference, Setup};
use std::path::{Path, PathBuf};
use sweep::Sweep;

#[derive(clap::Args, Debug)]
pub struct SpeedErrorArgs {
    /// Scene file (default: the embedded default scene).
    pub scene: Option<PathBuf>,
    /// Modes whose error is measured: color, mono, dop, ellipticity,
    /// ellipticity-paper, azimuth (display values in [0, 1]).
    #[arg(long, short, value_delimiter = ',', default_value = "color,dop")]
    pub mode: Vec<OutputMode>,
    /// Output directory: results.csv, pareto.png.
    #[arg(long, short, default_value = "speed-error")]
    pub output: PathBuf,
    /// Settings to measure, one per flag: space-separated `key=value`
    /// (depth, prune, spp, wavelengths, spectral, branching, polarization,
    /// dispersion, quality, seed, coherence, bundle, roulette, adaptive,
    /// min_samples, edges, max_samples). Default: a built-in sweep around
    /// the scene's settings
    /// (docs/speed-vs-error.md).
    #[arg(long = "config")]
    pub configs: Vec<String>,
    /// Raw reference film (EXR). Read if it exists (it must have been made
    /// for this scene and these settings); otherwise rendered and saved
    /// there.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Reference settings, `key=value` as for --config.
    #[arg(long, default_value = "depth=30 prune=1e-6 spp=16")]
    pub reference_config: String,
    /// Measure errors on every K-th pixel row only (rows K/2, K/2 + K, …):
    /// the reference renders only those rows, so a reference of a large
    /// image costs 1/K; every configuration is still rendered and timed
    /// whole.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub error_rows: u32,
    /// Paired measurement: the reference and every configuration use the
    /// scene's seed, so they share their sample positions and the error is
    /// the change the settings alone make (their model error, without most
    /// of the antialiasing noise). The reference is rendered in one piece
    /// (no noise estimate).
    #[arg(long)]
    pub paired: bool,
    /// Wavelength of the single-wavelength modes, nm; default 580.
    /// Refused when no mode asked for uses it (color alone).
    #[arg(long)]
    pub wavelength: Option<f64>,
    #[command(flatten)]
    pub accel: AccelArgs,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Render nothing: merge the results.csv of earlier runs (on one
    /// reference, e.g. a sweep split over machines) into one results.csv,
    /// plot and table, fronts taken over all of them.
    #[arg(long = "from-csv", conflicts_with_all = ["configs", "reference", "paired"])]
    pub from_csv: Vec<PathBuf>,
    /// No progress or table.
    #[arg(long, short)]
    pub quiet: bool,
}

pub fn run(args: &SpeedErrorArgs) -> Result<(), CliError> {
    if !args.from_csv.is_empty() {
        return replot(args);
    }
    let modes = display_modes(&args.mode)?;
    let mono_nm = mono_wavelength(args.wavelength, &modes)?;
    let scene = checked_scene(args)?;
    let sweep = Sweep::new(&scene, &args.configs, &args.reference_config, args.paired)?;
    create_dir(&args.output)?;
    let setup = Setup {
        modes,
        mono_nm,
        threads: args.threads.unwrap_or(0),
        accel: args.accel.kind(None)?,
        quiet: args.quiet,
    };
    let plan = Plan {
        path: args.reference.as_deref(),
        paired: args.paired,
        error_rows: args.error_rows,
    };
    let reference = Reference::obtain(
        &setup,
        &scene,
        &sweep.reference,
        &sweep.reference_scene,
        &plan,
    )?;
    setup.say(reference.about.trim_end());
    let mut measured = Vec::new();
    for (config, s) in sweep.configs.iter().zip(&sweep.scenes) {
        let m = reference.measure(&setup, config, s)?;
        setup.say(&results::row(&m, &reference.measures));
        measured.push(m);
    }
    results::write(
        &args.output,
        &measured,
        &reference.measures,
        Some(&reference.about),
        args.quiet,
    )
}

/// The modes asked for, repeats removed: display modes only.
fn display_modes(asked: &[OutputMode]) -> Result<Vec<OutputMode>, CliError> {
    let mut modes = asked.to_vec();
    modes.dedup();
    if modes.is_empty() || modes.iter().any(|m| m.is_stokes() || m.is_polcam()) {
        return Err(CliError::input(
            "--mode: give display modes (color, mono, dop, ellipticity, ellipticity-paper, \
             azimuth, aolp, dolp, polvis-dop, polvis-top, polvis-lin, polvis-cir); stokes, \
             stokes-rgb, polcam, polcam-mosaic, polvis-stokes and sheet have no display error",
        ));
    }
    Ok(modes)
}

/// The scene with the overrides applied.
fn checked_scene(args: &SpeedErrorArgs) -> Result<Scene, CliError> {
    let mut scene = load_scene(args.scene.as_deref())?;
    args.overrides.apply(&mut scene)?;
    Ok(scene)
}

/// Creates the output directory (and its parents) if need be.
fn create_dir(dir: &Path) -> Result<(), CliError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        CliError::input(format!(
            "{}: cannot create the directory: {e}",
            dir.display()
        ))
    })
}

/// `--from-csv`: the merged results of earlier runs, written and plotted.
fn replot(args: &SpeedErrorArgs) -> Result<(), CliError> {
    let mut measures: Option<Vec<Measure>> = None;
    let mut rows = Vec::new();
    for path in &args.from_csv {
        let (m, r) = results::read_csv(path).map_err(CliError::input)?;
        match &measures {
            Some(first) if *first != m => {
                return Err(CliError::input(format!(
                    "{}: other measures than {} ({})",
                    path.display(),
                    args.from_csv[0].display(),
                    m.iter().map(Measure::name).collect::<Vec<_>>().join(", ")
                )))
            }
            _ => measures = Some(m),
        }
        rows.extend(r);
    }
    let measures = measures.expect("at least one file");
    create_dir(&args.output)?;
    results::write(&args.output, &rows, &measures, None, args.quiet)
}
