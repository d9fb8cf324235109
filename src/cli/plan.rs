//! `spar plan SCENE --tiles N --slurm|--openjd`: print a job that renders
//! the scene as N tiles on a farm and merges them (docs/farm.md).

use super::args::{check_isa, AccelArgs, SamplesArg, SceneOverrides};
use super::common::{check_wavelength, mode_files, wavelength_use};
use super::error::CliError;
use crate::farm::plan::Plan;
use crate::render::output::OutputMode;
use crate::render::region;
use crate::scene::Scene;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct PlanArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Number of tiles (units of work) to split the image into.
    #[arg(long)]
    pub tiles: u32,
    /// Print a Slurm submission script (a job array and a merge job).
    #[arg(long, conflicts_with = "openjd", required_unless_present = "openjd")]
    pub slurm: bool,
    /// Print an Open Job Description job template (YAML).
    #[arg(long)]
    pub openjd: bool,
    /// Directory for parts, logs and results (default: the current one).
    #[arg(long, default_value = ".")]
    pub out_dir: PathBuf,
    /// Camera modes of the final images (and so the wavelengths traced).
    #[arg(long, short, value_delimiter = ',', default_value = "color")]
    pub mode: Vec<OutputMode>,
    /// Wavelength of the single-wavelength modes, nm (default 580; as
    /// `spar render --wavelength`, passed on only when given).
    #[arg(long)]
    pub wavelength: Option<f64>,
    /// Name of the final image in the output directory (default: image.png,
    /// or image.exr for the stokes mode alone); its extension must fit the
    /// modes, as for `spar render -o`.
    #[arg(long)]
    pub image: Option<String>,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Pin Embree's instruction set on every machine (sse2, sse4.2, avx,
    /// avx2, avx512).
    #[arg(long)]
    pub isa: Option<String>,
    // The intersection backend of every tile (`spar render --accel`).
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Threads (CPUs) per tile.
    #[arg(long, default_value_t = 1)]
    pub threads: u32,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm time limit per job (e.g. 1:00:00).
    #[arg(long)]
    pub time: Option<String>,
    /// The spar the jobs run (default: this one).
    #[arg(long)]
    pub spar: Option<PathBuf>,
}

fn absolute(p: &Path) -> Result<PathBuf, CliError> {
    std::path::absolute(p).map_err(|e| CliError::input(format!("{}: {e}", p.display())))
}

pub fn run(args: &PlanArgs, out: &mut dyn Write) -> Result<(), CliError> {
    if let Some(SamplesArg::Block { .. }) = args.overrides.samples {
        return Err(CliError::input(
            "spar plan splits the image into tiles: give --samples a count",
        ));
    }
    let mut scene = Scene::load(&args.scene)?;
    args.overrides.apply(&mut scene)?;
    if args.threads == 0 {
        return Err(CliError::input("--threads must be at least 1"));
    }
    if let Some(isa) = &args.isa {
        check_isa(isa)?;
    }
    args.accel.kind(args.isa.as_deref())?;
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() {
        return Err(CliError::input("--mode needs at least one mode"));
    }
    if let Some(nm) = args.wavelength {
        check_wavelength(nm)?;
    }
    wavelength_use(args.wavelength, &modes)?;
    let image = match &args.image {
        Some(i) => i.clone(),
        None if modes.len() == 1 => format!("image.{}", modes[0].extension()),
        None => "image.png".into(),
    };
    region::split(scene.camera.width, scene.camera.height, args.tiles)
        .map_err(|e| CliError::input(format!("--tiles {}: {e}", args.tiles)))?;
    if image.is_empty() || image.contains('/') {
        return Err(CliError::input("--image is a file name inside --out-dir"));
    }
    mode_files(Some(Path::new(&image)), &modes)?;
    let spar = match &args.spar {
        Some(p) => absolute(p)?,
        None => std::env::current_exe()
            .map_err(|e| CliError::internal(format!("cannot find this spar's path: {e}")))?,
    };
    let scene_path = absolute(&args.scene)?;
    let out_dir = absolute(&args.out_dir)?;
    let mode_list = modes.iter().map(|m| m.name()).collect::<Vec<_>>().join(",");
    let mut render_args = args.overrides.to_args();
    render_args.extend(["--mode".into(), mode_list.clone()]);
    if let Some(nm) = args.wavelength {
        render_args.extend(["--wavelength".into(), format!("{nm:?}")]);
    }
    if let Some(isa) = &args.isa {
        render_args.extend(["--isa".into(), isa.clone()]);
    }
    if let Some(kind) = args.accel.accel {
        render_args.extend(["--accel".into(), kind.name().into()]);
    }
    let mut develop_args = vec!["--mode".into(), mode_list];
    if let Some(nm) = args.wavelength {
        develop_args.extend(["--wavelength".into(), format!("{nm:?}")]);
    }
    let plan = Plan {
        spar: &spar,
        scene: &scene_path,
        out_dir: &out_dir,
        tiles: args.tiles,
        render_args,
        develop_args,
        threads: args.threads,
        partition: args.partition.clone(),
        time: args.time.clone(),
        image: image.clone(),
    };
    let text = if args.slurm {
        plan.slurm()
    } else {
        plan.openjd()
    };
    out.write_all(text.as_bytes())
        .map_err(|e| CliError::internal(format!("cannot write the plan: {e}")))
}
