//! `spar render [SCENE]`: render a scene file (or the embedded default
//! scene) in one or more camera modes, or one unit of work of a render
//! farm as a raw EXR part (`--region`, `--tile`, `--samples k0..k1`,
//! `--raw`; see docs/farm.md).

use super::CliError;
use crate::accel::AccelKind;
use crate::farm::checkpoint;
use crate::farm::part::{part_image, RenderInfo};
use crate::farm::progress::{ProgressMode, Reporter};
use crate::image::{PixelType, WriteOptions};
use crate::render::approx::{self, BranchingArg, PolarizationArg, Spectral};
use crate::render::blocks::SampleRange;
use crate::render::film::Film;
use crate::render::integrator::Stats;
use crate::render::output::{develop, OutputMode};
use crate::render::prepare::{self, PrepareError};
use crate::render::quality::Quality;
use crate::render::region::{self, Rect, TileSpec};
use crate::render::{render_part, Control, Outcome, PartSpec, RenderOptions, TileData, TILE};
use crate::scene::{builtin, Scene};
use crate::spectrum::WavelengthSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML). Without one, the embedded default scene: a calcite
    /// gem over a textured light.
    pub scene: Option<PathBuf>,
    /// Camera modes, comma-separated: color, mono, dop, ellipticity,
    /// ellipticity-paper, azimuth, stokes. With a raw output they choose
    /// the wavelengths traced.
    #[arg(long, short, value_delimiter = ',', default_value = "color")]
    pub mode: Vec<OutputMode>,
    /// Output file. With several modes, each mode's name is appended to its
    /// stem (spar-color.png, spar-dop.png, spar-stokes.exr). A raw output
    /// is one .exr file.
    #[arg(long, short, default_value = "spar.png")]
    pub output: PathBuf,
    /// Wavelength of the single-wavelength modes (mono, dop, ellipticity,
    /// azimuth), nm.
    #[arg(long, default_value_t = 580.0)]
    pub wavelength: f64,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    #[command(flatten)]
    pub farm: FarmArgs,
    #[command(flatten)]
    pub accel: AccelArgs,
    /// Worker threads (default or 0: one per core; at most 8 per core, and
    /// at least 64 are always allowed).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress or summary.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `--accel`: the intersection backend of every command that traces.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct AccelArgs {
    /// Intersection backend: embree (Embree 3; the default in builds with
    /// the `native` feature) or rust (spar's own BVH; the default without
    /// it). They can hit different triangles at edges, so farm parts of
    /// different backends do not merge.
    #[arg(long, value_enum)]
    pub accel: Option<AccelKind>,
}

impl AccelArgs {
    /// The backend asked for (or this build's default), checked to be in
    /// this build and, with an `--isa`, to be Embree.
    pub fn kind(&self, isa: Option<&str>) -> Result<AccelKind, CliError> {
        let kind = self.accel.unwrap_or_default();
        check_accel(kind, isa)?;
        Ok(kind)
    }
}

/// Refuses a backend this build lacks, and `--isa` with any backend but
/// Embree (exit status 2).
pub fn check_accel(kind: AccelKind, isa: Option<&str>) -> Result<(), CliError> {
    if !kind.available() {
        return Err(CliError::Input(format!(
            "--accel {kind}: this spar was built without the `native` feature, so Embree is not \
             available; use --accel rust"
        )));
    }
    if let (Some(isa), false) = (isa, kind == AccelKind::Embree) {
        return Err(CliError::Input(format!(
            "--isa {isa} pins Embree's instruction set; it does not apply to --accel {kind}"
        )));
    }
    Ok(())
}

/// The render-farm flags of `spar render`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct FarmArgs {
    /// Render only the pixels x from X0 to X1 and y from Y0 to Y1 (ends
    /// exclusive; `--region 0,64,0,32` is the top-left 64x32) into a raw
    /// EXR part.
    #[arg(
        long,
        value_name = "X0,X1,Y0,Y1",
        value_parser = Rect::parse,
        conflicts_with = "tile",
        allow_hyphen_values = true
    )]
    pub region: Option<Rect>,
    /// Render tile I of the N-way split spar computes (I counts from 0)
    /// into a raw EXR part.
    #[arg(long, value_parser = TileSpec::parse)]
    pub tile: Option<TileSpec>,
    /// Write the raw per-pixel sums (float32 EXR) instead of images, also
    /// for a whole render; `spar develop` makes the images.
    #[arg(long)]
    pub raw: bool,
    /// Pin Embree's instruction set: sse2, sse4.2, avx, avx2, avx512.
    /// Machines of a farm that differ in ISA can hit different triangles
    /// at edges; pin one for all of them.
    #[arg(long)]
    pub isa: Option<String>,
    /// Progress: auto (a bar on a terminal, else plain lines), bar, plain
    /// (`spar: progress …` lines on stdout), openjd (`openjd_progress: N`),
    /// none.
    #[arg(long, value_enum, default_value_t = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// Checkpoint file written on SIGTERM, SIGINT or SIGUSR1 (default: the
    /// output's name with `.checkpoint` appended).
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Continue from the checkpoint if there is one (and start afresh if
    /// there is none).
    #[arg(long)]
    pub resume: bool,
}

/// `--samples`: a count per pixel, or a block of samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplesArg {
    /// `N`: samples per pixel.
    Count(u32),
    /// `k0..k1` or `k0..k1/N`: samples k0 to k1 (exclusive) of the
    /// scene's count, or of N.
    Block {
        start: u32,
        end: u32,
        total: Option<u32>,
    },
}

fn parse_samples(s: &str) -> Result<SamplesArg, String> {
    let num = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{s}` is not N, k0..k1 or k0..k1/N"))
    };
    if !s.contains("..") {
        return Ok(SamplesArg::Count(num(s)?));
    }
    let (range, total) = s.split_once('/').map_or((s, None), |(r, t)| (r, Some(t)));
    let (a, b) = range.split_once("..").expect("checked above");
    let (start, end) = (num(a)?, num(b)?);
    let total = total.map(num).transpose()?;
    if start >= end {
        return Err(format!("`{s}`: a sample block k0..k1 needs k0 < k1"));
    }
    Ok(SamplesArg::Block { start, end, total })
}

/// Settings that override a scene file's.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneOverrides {
    /// Wavelengths of the color mode: a count over 380–780 nm, one
    /// wavelength (580nm) or a list (450,550,650). Overrides the scene.
    #[arg(long)]
    pub wavelengths: Option<String>,
    /// Samples per pixel (overrides the scene); for `spar render`, also a
    /// block of them: `k0..k1` (of the scene's count) or `k0..k1/N`.
    #[arg(long, value_parser = parse_samples)]
    pub samples: Option<SamplesArg>,
    /// Image size WIDTHxHEIGHT (overrides the scene).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Largest number of surface interactions along a path (overrides the
    /// scene).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Pruning threshold: skip subtrees that can contribute less than this
    /// fraction of the brightest emitter; 0 disables (overrides the scene).
    #[arg(long)]
    pub prune: Option<f64>,
    /// Random seed (overrides the scene).
    #[arg(long)]
    pub seed: Option<u64>,
    /// A preset of depth, pruning and approximations (branching,
    /// polarization model, spectral sampling, dispersion) chosen from the
    /// measured speed-against-error front (docs/speed-vs-error.md): draft
    /// (dispersion off, pruning 1e-3), default (the exact tree, pruning
    /// 1e-4) or reference (pruning 1e-6), all at depth 30. Wavelengths and
    /// samples are left as they are. Other flags given with it win.
    #[arg(long, value_parser = clap::value_parser!(Quality))]
    pub quality: Option<Quality>,
    /// Branch strategy: full (every feeder), stochastic (one feeder per
    /// node, chosen by energy: unbiased, noisy) or hybrid:K (full for K
    /// interactions, then stochastic). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(BranchingArg))]
    pub branching: Option<BranchingArg>,
    /// Polarization model: full (coherence matrices) or scalar (unpolarized
    /// intensities, an approximation). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(PolarizationArg))]
    pub polarization: Option<PolarizationArg>,
    /// Spectral sampling of the colour wavelengths: all (every one for
    /// every sample) or hero:K (K stratified wavelengths per sample,
    /// rotating across samples). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(Spectral))]
    pub spectral: Option<Spectral>,
    /// Dispersion on, off (every wavelength follows the paths of
    /// 587.56 nm) or bands:K (K bands of wavelength, each following the
    /// paths of its middle). Overrides the scene.
    #[arg(long, value_parser = clap::value_parser!(approx::DispersionMode))]
    pub dispersion: Option<approx::DispersionMode>,
}

impl SceneOverrides {
    /// Applies the overrides to a scene, checked like the scene's own values.
    /// A sample block is refused (only `spar render` takes one).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), CliError> {
        if let Some(SamplesArg::Block { .. }) = self.samples {
            return Err(CliError::Input(
                "--samples k0..k1 (a sample block) is for spar render; give a count".into(),
            ));
        }
        self.apply_with_block(scene).map(|_| ())
    }

    /// Applies the overrides and returns the sample block asked for, if
    /// any, checked against the scene's sample count.
    pub fn apply_with_block(&self, scene: &mut Scene) -> Result<Option<SampleRange>, CliError> {
        let input = CliError::Input;
        if let Some(q) = self.quality {
            q.apply(&mut scene.settings);
        }
        if let Some(b) = self.branching {
            scene.settings.approx.strategy.branching = b.0;
        }
        if let Some(p) = self.polarization {
            scene.settings.approx.strategy.polarization = p.0;
        }
        if let Some(s) = self.spectral {
            scene.settings.approx.spectral = s;
        }
        if let Some(d) = self.dispersion {
            scene.settings.approx.dispersion = d;
        }
        if let Some(spec) = &self.wavelengths {
            check_wavelength_count(spec)?;
            scene.settings.wavelengths =
                WavelengthSet::parse(spec).map_err(|e| input(format!("--wavelengths: {e}")))?;
        }
        let mut block = None;
        match self.samples {
            Some(SamplesArg::Count(0)) | Some(SamplesArg::Block { total: Some(0), .. }) => {
                return Err(input("--samples must be at least 1".into()));
            }
            Some(SamplesArg::Count(s)) => scene.samples = s,
            Some(SamplesArg::Block { start, end, total }) => {
                if let Some(t) = total {
                    scene.samples = t;
                }
                block = Some(SampleRange::new(start, end, scene.samples).ok_or_else(|| {
                    input(format!(
                        "--samples {start}..{end}: the block must lie within the {} samples per pixel",
                        scene.samples
                    ))
                })?);
            }
            None => {}
        }
        if let Some((w, h)) = self.resolution {
            if w > MAX_SIDE || h > MAX_SIDE {
                let n = scene.settings.wavelengths.len();
                let need = film_bytes(w as u64 * h as u64, n, 1) / crate::farm::memory::GIB;
                return Err(input(format!(
                    "--resolution {w}x{h}: at most {MAX_SIDE} pixels per side (its film at {n} \
                     wavelength(s) would need about {need:.1} GiB of memory; {})",
                    crate::farm::memory::available().describe()
                )));
            }
            scene.camera = scene.camera.clone().with_resolution(w, h);
        }
        if let Some(d) = self.max_depth {
            if d > 1000 {
                return Err(input("--max-depth must be at most 1000".into()));
            }
            scene.settings.max_depth = d;
        }
        if let Some(p) = self.prune {
            if !(p.is_finite() && p >= 0.0) {
                return Err(input("--prune must be a number ≥ 0".into()));
            }
            scene.settings.prune = p;
        }
        if let Some(s) = self.seed {
            scene.settings.seed = s;
        }
        Ok(block)
    }

    /// The overrides as command-line arguments (for job scripts).
    pub fn to_args(&self) -> Vec<String> {
        let mut a = Vec::new();
        if let Some(w) = &self.wavelengths {
            a.extend(["--wavelengths".into(), w.clone()]);
        }
        match self.samples {
            Some(SamplesArg::Count(n)) => a.extend(["--samples".into(), n.to_string()]),
            Some(SamplesArg::Block { start, end, total }) => a.extend([
                "--samples".into(),
                match total {
                    Some(t) => format!("{start}..{end}/{t}"),
                    None => format!("{start}..{end}"),
                },
            ]),
            None => {}
        }
        if let Some((w, h)) = self.resolution {
            a.extend(["--resolution".into(), format!("{w}x{h}")]);
        }
        if let Some(d) = self.max_depth {
            a.extend(["--max-depth".into(), d.to_string()]);
        }
        if let Some(p) = self.prune {
            a.extend(["--prune".into(), format!("{p:?}")]);
        }
        if let Some(s) = self.seed {
            a.extend(["--seed".into(), s.to_string()]);
        }
        if let Some(q) = self.quality {
            a.extend(["--quality".into(), q.to_string()]);
        }
        if let Some(b) = self.branching {
            a.extend(["--branching".into(), b.to_string()]);
        }
        if let Some(p) = self.polarization {
            a.extend(["--polarization".into(), p.to_string()]);
        }
        if let Some(s) = self.spectral {
            a.extend(["--spectral".into(), s.to_string()]);
        }
        if let Some(d) = self.dispersion {
            a.extend(["--dispersion".into(), d.to_string()]);
        }
        a
    }
}

/// The largest image side (scene files' `camera.resolution` has the same
/// bound).
pub const MAX_SIDE: u32 = 65536;

/// Refuses a `--wavelengths` count above the scene format's bound before
/// the set is built (its list alone could exhaust memory).
fn check_wavelength_count(spec: &str) -> Result<(), CliError> {
    let max = crate::scene::file::MAX_WAVELENGTHS;
    match spec.trim().parse::<u128>() {
        Ok(n) if n > max as u128 => Err(CliError::Input(format!(
            "--wavelengths {n}: at most {max} wavelengths (0.04 nm apart; a 256x256 film of \
             {n} would need about {:.1} GiB of memory)",
            film_bytes(256 * 256, n.min(usize::MAX as u128) as usize, 1) / crate::farm::memory::GIB
        ))),
        _ => Ok(()),
    }
}

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT"))?;
    let p = |v: &str| v.trim().parse::<u32>().ok().filter(|&v| v >= 1);
    // The side limit is checked with the scene (SceneOverrides), where
    // the message can say what the film would cost.
    match (p(w), p(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be whole numbers from 1 to {MAX_SIDE}"
        )),
    }
}

/// Embree ISA names `--isa` takes (Embree 3's device config; it silently
/// falls back to SSE2 for any other name, so spar checks them).
pub const ISAS: [&str; 5] = ["sse2", "sse4.2", "avx", "avx2", "avx512"];

/// Checks an `--isa` name and that this CPU has the instruction set.
pub fn check_isa(name: &str) -> Result<(), String> {
    if !ISAS.contains(&name) {
        return Err(format!(
            "--isa {name}: unknown instruction set; Embree 3 takes {}",
            ISAS.join(", ")
        ));
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        let missing: Vec<&str> = match name {
            "sse2" => vec![],
            "sse4.2" => [("sse4.2", has!("sse4.2"))]
                .iter()
                .filter(|f| !f.1)
                .map(|f| f.0)
                .collect(),
            "avx" => [("avx", has!("avx"))]
                .iter()
                .filter(|f| !f.1)
                .map(|f| f.0)
                .collect(),
            "avx2" => [
                ("avx2", has!("avx2")),
                ("fma", has!("fma")),
                ("bmi1", has!("bmi1")),
                ("bmi2", has!("bmi2")),
                ("lzcnt", has!("lzcnt")),
            ]
            .iter()
            .filter(|f| !f.1)
            .map(|f| f.0)
            .collect(),
            _ => [
                ("avx512f", has!("avx512f")),
                ("avx512dq", has!("avx512dq")),
                ("avx512cd", has!("avx512cd")),
                ("avx512bw", has!("avx512bw")),
                ("avx512vl", has!("avx512vl")),
            ]
            .iter()
            .filter(|f| !f.1)
            .map(|f| f.0)
            .collect(),
        };
        if !missing.is_empty() {
            return Err(format!(
                "--isa {name}: this CPU lacks {}",
                missing.join(", ")
            ));
        }
        Ok(())
    }
    #[cfg(not(target_arch = "x86_64"))]
    Err(format!(
        "--isa {name}: instruction sets can be pinned on x86-64 only"
    ))
}

/// The output path of `mode` when `modes` are rendered together.
pub fn output_path(output: &Path, mode: OutputMode, several: bool) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "spar".into());
    let name = if several {
        format!("{stem}-{}.{}", mode.name(), mode.extension())
    } else if mode.extension() == "png" && output.extension().is_some() {
        output
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    } else {
        format!("{stem}.{}", mode.extension())
    };
    output.with_file_name(name)
}

/// A finished render and what it cost.
pub struct Rendered {
    pub film: Film,
    pub stats: Stats,
    pub options: RenderOptions,
    pub accel_time: std::time::Duration,
    pub render_time: std::time::Duration,
}

/// Refuses rendered values that are not finite (no NaN pixel is ever
/// written): an internal error, never the input's fault.
pub(crate) fn check_finite<'a>(values: impl IntoIterator<Item = &'a f32>) -> Result<(), CliError> {
    match crate::farm::non_finite(values) {
        Some((first, count)) => Err(CliError::Failed(format!(
            "internal error: the render produced {count} non-finite value(s), the first at raw \
             value {first}"
        ))),
        None => Ok(()),
    }
}

/// The most worker threads `--threads` may ask for: 8 per core this machine
/// has, and at least 64. More only contend for the cores (and thousands of
/// them starve the machine and delay a SIGTERM's checkpoint while they
/// start).
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    (8 * cores).max(64)
}

/// Refuses a `--threads` count above [`max_threads`] (exit status 2); 0
/// means one per core.
pub fn check_threads(threads: usize) -> Result<(), CliError> {
    let max = max_threads();
    if threads > max {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        return Err(CliError::Input(format!(
            "--threads {threads}: at most {max} on this machine ({cores} cores; 0 or no \
             --threads means one per core)"
        )));
    }
    Ok(())
}

/// Bytes a render holds at its peak, about: its f32 raw values (pixels ×
/// wavelengths × 4 Stokes × stored nodes) four times over (the tiles, the
/// assembled part or film, the image handed to the writer, developed
/// modes). A 500x500 render of 21 wavelengths peaked at 289 MiB resident
/// (PNG), 319 MiB (raw EXR) and 371 MiB (colour and Stokes); this gives
/// 320 MiB.
pub fn film_bytes(pixels: u64, lambdas: usize, nodes: usize) -> f64 {
    pixels as f64 * lambdas as f64 * 4.0 * nodes.max(1) as f64 * 4.0 * 4.0
}

/// Refuses a render whose film cannot fit in the available memory, naming
/// `what` asks for it (the flags or scene fields of size and wavelengths).
pub fn check_film_memory(
    pixels: u64,
    lambdas: usize,
    nodes: usize,
    what: &str,
) -> Result<(), CliError> {
    crate::farm::memory::check(film_bytes(pixels, lambdas, nodes), what).map_err(CliError::Input)
}

pub(crate) fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, CliError> {
    check_threads(threads)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start worker threads: {e}")))
}

/// Renders what `modes` need: the scene's colour wavelengths for the
/// spectral modes, `mono_nm` for the others; `threads` 0 means all cores;
/// `accel` traces.
pub fn render_film(
    scene: &Scene,
    modes: &[OutputMode],
    mono_nm: f64,
    threads: usize,
    progress: bool,
    accel: AccelKind,
) -> Result<Rendered, CliError> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = prepare::lambdas(scene, modes, mono_nm).len();
    check_film_memory(
        w as u64 * h as u64,
        n,
        1,
        &format!("a {w}x{h} render of {n} wavelength(s)"),
    )?;
    let pool = thread_pool(threads)?;
    let t0 = Instant::now();
    let accel = prepare::accel(scene, accel, pool.current_num_threads(), None)?;
    let accel_time = t0.elapsed();
    let options = prepare::options(scene, modes, mono_nm, progress);
    let t1 = Instant::now();
    let (film, stats) = pool.install(|| crate::render::render(scene, accel.as_ref(), &options));
    let render_time = t1.elapsed();
    check_finite(film.data.iter().flatten())?;
    // compare, speed-error and contact-sheet render through here: lost
    // light is reported as spar render reports it.
    if let Some(w) = stats.lost_light_warning() {
        eprintln!("spar: warning: {w}");
    }
    Ok(Rendered {
        film,
        stats,
        options,
        accel_time,
        render_time,
    })
}

/// A render that cannot be prepared: a backend this build lacks, or an
/// ISA for another backend than Embree, is an input error (exit status 2;
/// [`check_accel`] refuses both first); a backend that refuses the meshes
/// a failure (exit status 1).
impl From<PrepareError> for CliError {
    fn from(e: PrepareError) -> CliError {
        match e {
            PrepareError::Unavailable(_) | PrepareError::IsaNotEmbree { .. } => {
                CliError::Input(e.to_string())
            }
            PrepareError::Build(_) => CliError::Failed(e.to_string()),
        }
    }
}

/// Says which flags or scene fields set a render's size and wavelengths,
/// for a memory refusal.
fn film_what(
    scene: &Scene,
    file: Option<&Path>,
    o: &SceneOverrides,
    region: Rect,
    modes: &[OutputMode],
    mono_nm: f64,
) -> String {
    let file = file.map_or("(default scene)".into(), |p| p.display().to_string());
    let (w, h) = (scene.camera.width, scene.camera.height);
    let size = match o.resolution {
        Some(_) => format!("--resolution {w}x{h}"),
        None => format!("{file}: camera.resolution [{w}, {h}]"),
    };
    let n = prepare::lambdas(scene, modes, mono_nm).len();
    let lambdas = match &o.wavelengths {
        Some(s) => format!("--wavelengths {s} ({n} traced)"),
        None => format!("{file}: render.wavelengths ({n} traced)"),
    };
    let part = if region == Rect::full(w, h) {
        String::new()
    } else {
        format!(", region {region}")
    };
    format!("{size}{part} with {lambdas}")
}

/// Refuses an image output whose directory does not exist, that names a
/// directory or (in the pure-Rust build) a format it cannot write, before
/// any work starts.
pub fn check_output(path: &Path) -> Result<(), CliError> {
    check_output_location(path)?;
    // The pure-Rust image backend writes EXR and PNG only.
    #[cfg(not(feature = "native"))]
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png") || e.eq_ignore_ascii_case("exr"))
    {
        return Err(CliError::Input(format!(
            "{}: this spar was built without the `native` feature and writes .png and .exr \
             files only",
            path.display()
        )));
    }
    Ok(())
}

/// Refuses an output whose directory does not exist or that names a
/// directory, before any work starts (every command that writes a file).
pub fn check_output_location(path: &Path) -> Result<(), CliError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return Err(CliError::Input(format!(
            "{}: the directory {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    if path.is_dir() {
        return Err(CliError::Input(format!(
            "{}: is a directory, not a file name",
            path.display()
        )));
    }
    Ok(())
}

/// Develops `film` in each mode and writes the images (the one code path
/// of `spar render` and `spar develop`). `metadata` goes into every file,
/// with `spar:mode`.
#[allow(clippy::too_many_arguments)]
pub fn write_modes(
    film: &Film,
    modes: &[OutputMode],
    colour: &WavelengthSet,
    mono_nm: f64,
    output: &Path,
    metadata: &[(String, String)],
    quiet: bool,
    reporter: &Reporter,
) -> Result<(), CliError> {
    for &m in modes {
        let path = output_path(output, m, modes.len() > 1);
        let mut image = develop(film, m, colour, mono_nm).map_err(CliError::Input)?;
        for (k, v) in metadata {
            image = image.with_metadata(k.clone(), v.clone());
        }
        let image = image.with_metadata("spar:mode", m.name());
        let options = match m {
            OutputMode::Stokes => WriteOptions::new(PixelType::F32),
            _ => WriteOptions::new(PixelType::U8),
        };
        crate::image::write(&path, &image, options).map_err(|e| CliError::Input(e.to_string()))?;
        reporter.event("wrote", &path.display().to_string());
        if !quiet && !reporter.prints_lines() {
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// Signal flags: SIGTERM and SIGINT stop (after the tiles in flight) and
/// save a checkpoint; SIGUSR1 saves one and goes on. A second SIGINT
/// ends the process at once.
pub struct Signals {
    pub stop: Arc<AtomicBool>,
    pub save: Arc<AtomicBool>,
    /// The signal that stopped the render, 0 if none.
    pub which: Arc<AtomicUsize>,
}

impl Signals {
    pub fn install() -> Result<Signals, CliError> {
        let s = Signals {
            stop: Arc::new(AtomicBool::new(false)),
            save: Arc::new(AtomicBool::new(false)),
            which: Arc::new(AtomicUsize::new(0)),
        };
        #[cfg(unix)]
        {
            use signal_hook::consts::{SIGINT, SIGTERM, SIGUSR1};
            use signal_hook::flag;
            let fail = |e: std::io::Error| CliError::Failed(format!("cannot handle signals: {e}"));
            flag::register_conditional_shutdown(SIGINT, 130, s.stop.clone()).map_err(fail)?;
            for sig in [SIGTERM, SIGINT] {
                flag::register_usize(sig, s.which.clone(), sig as usize).map_err(fail)?;
                flag::register(sig, s.stop.clone()).map_err(fail)?;
            }
            flag::register(SIGUSR1, s.save.clone()).map_err(fail)?;
        }
        Ok(s)
    }

    fn name(&self) -> &'static str {
        #[cfg(unix)]
        {
            match self.which.load(Ordering::SeqCst) as i32 {
                signal_hook::consts::SIGINT => "SIGINT",
                _ => "SIGTERM",
            }
        }
        #[cfg(not(unix))]
        "a signal"
    }
}

/// The scene file at `path` (a user error if it is bad), or the embedded
/// default scene.
pub fn load_scene(path: Option<&Path>) -> Result<Scene, CliError> {
    match path {
        Some(path) => Scene::load(path).map_err(|e| CliError::Input(e.to_string())),
        None => Scene::parse(builtin::DEFAULT_SCENE, "(default scene)", Path::new("."))
            .map_err(|e| CliError::Failed(e.to_string())),
    }
}

/// Checks `--wavelength` (a single-wavelength mode's wavelength).
pub fn check_wavelength(nm: f64) -> Result<(), CliError> {
    if nm.is_finite() && (360.0..=830.0).contains(&nm) {
        Ok(())
    } else {
        Err(CliError::Input(format!(
            "--wavelength {nm} is outside 360–830 nm"
        )))
    }
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let input = CliError::Input;
    let started = Instant::now();
    if let Some(t) = args.threads {
        check_threads(t)?;
    }
    let mut scene = load_scene(args.scene.as_deref())?;
    let block = args.overrides.apply_with_block(&mut scene)?;
    check_wavelength(args.wavelength)?;
    if args.mode.contains(&OutputMode::Color) {
        crate::spectrum::Observer::new(&scene.settings.wavelengths)
            .map_err(|e| input(format!("wavelengths for the color mode: {e}")))?;
    }
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() {
        return Err(input("--mode needs at least one mode".into()));
    }
    let farm = &args.farm;
    if let Some(isa) = &farm.isa {
        check_isa(isa).map_err(input)?;
    }
    let accel_kind = args.accel.kind(farm.isa.as_deref())?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let region = match (farm.region, farm.tile) {
        (Some(r), _) => {
            if !r.fits(w, h) {
                return Err(input(format!(
                    "--region {r} is not inside the {w}x{h} image (x0,x1,y0,y1, ends exclusive)"
                )));
            }
            r
        }
        (None, Some(t)) => region::split(w, h, t.count)
            .map_err(|e| input(format!("--tile {}/{}: {e}", t.index, t.count)))?[t.index as usize],
        (None, None) => Rect::full(w, h),
    };
    let samples = block.unwrap_or(SampleRange::all(scene.samples));
    let spec = PartSpec { region, samples };
    check_film_memory(
        spec.region.area() as u64,
        prepare::lambdas(&scene, &modes, args.wavelength).len(),
        spec.samples.nodes().len(),
        &film_what(
            &scene,
            args.scene.as_deref(),
            &args.overrides,
            spec.region,
            &modes,
            args.wavelength,
        ),
    )?;
    let raw = farm.raw || farm.region.is_some() || farm.tile.is_some() || block.is_some();
    // Refuse to start a long render whose output cannot be written.
    if raw {
        if args
            .output
            .extension()
            .is_none_or(|e| !e.eq_ignore_ascii_case("exr"))
        {
            return Err(input(format!(
                "{}: a raw part (--region, --tile, --samples k0..k1, --raw) is an .exr file",
                args.output.display()
            )));
        }
        check_output(&args.output)?;
    } else {
        for &m in &modes {
            check_output(&output_path(&args.output, m, modes.len() > 1))?;
        }
    }

    let scene_label = args
        .scene
        .as_ref()
        .map_or("(default scene)".into(), |p| p.display().to_string());
    let lambdas = prepare::lambdas(&scene, &modes, args.wavelength);
    let mut info = RenderInfo::new(
        &scene,
        &scene_label,
        lambdas.clone(),
        args.wavelength,
        farm.isa.as_deref(),
    );
    // Backends may hit different triangles at edges: parts of different
    // backends are different renders (the ISA is Embree's alone).
    info.accel = accel_kind.name().into();
    if accel_kind != AccelKind::Embree {
        info.isa = "none".into();
    }
    let progress_mode = if args.quiet {
        ProgressMode::None
    } else {
        farm.progress
    };
    let reporter = Reporter::new(progress_mode);
    let options = prepare::options(&scene, &modes, args.wavelength, reporter.wants_bar());
    debug_assert_eq!(options.lambdas, lambdas);

    // Checkpoint: named after the output; valid only for this render,
    // part and tile size.
    let ckpt_path = farm.checkpoint.clone().unwrap_or_else(|| {
        let mut name = args.output.as_os_str().to_owned();
        name.push(".checkpoint");
        PathBuf::from(name)
    });
    let ckpt_key = format!(
        "{} region {} samples {} tile {TILE} channels {}",
        info.key(),
        spec.region,
        spec.samples.label(),
        options.lambdas.len() * 4
    );
    let resume = if farm.resume {
        match checkpoint::load(&ckpt_path, &ckpt_key).map_err(|e| input(e.to_string()))? {
            Some(tiles) => {
                reporter.event(
                    "resume",
                    &format!("{} ({} tiles done)", ckpt_path.display(), tiles.len()),
                );
                tiles
            }
            None => {
                reporter.event(
                    "resume",
                    &format!("no checkpoint at {}: starting afresh", ckpt_path.display()),
                );
                Vec::new()
            }
        }
    } else {
        if ckpt_path.exists() && !args.quiet {
            eprintln!(
                "spar: note: {} exists; pass --resume to continue from it",
                ckpt_path.display()
            );
        }
        Vec::new()
    };

    let signals = Signals::install()?;
    let threads = args.threads.unwrap_or(0);
    let pool = thread_pool(threads)?;
    let t_accel = Instant::now();
    let accel = prepare::accel(
        &scene,
        accel_kind,
        pool.current_num_threads(),
        farm.isa.as_deref(),
    )?;
    let t_accel = t_accel.elapsed();
    let grid_len = crate::render::tiles(spec.region, TILE).len();
    reporter.event(
        "start",
        &format!(
            "render {scene_label} region {} samples {} ({grid_len} tiles, {} threads)",
            spec.region,
            spec.samples.label(),
            pool.current_num_threads()
        ),
    );
    let save_error = std::sync::Mutex::new(None::<String>);
    let save = |tiles: &[&TileData]| match checkpoint::save(&ckpt_path, &ckpt_key, tiles) {
        Ok(()) => reporter.event(
            "checkpoint",
            &format!("{} {}/{grid_len} tiles", ckpt_path.display(), tiles.len()),
        ),
        Err(e) => {
            let msg = format!("cannot write checkpoint {}: {e}", ckpt_path.display());
            eprintln!("spar: {msg}");
            *save_error.lock().expect("not poisoned") = Some(msg);
        }
    };
    let on_progress = |done: usize, total: usize| reporter.tiles(done, total);
    let control = Control {
        tile_size: TILE,
        stop: Some(&signals.stop),
        checkpoint: Some(&signals.save),
        on_checkpoint: Some(&save),
        on_progress: Some(&on_progress),
        resume,
    };
    let t_render = Instant::now();
    let outcome = pool.install(|| render_part(&scene, accel.as_ref(), &options, &spec, control));
    let t_render = t_render.elapsed();
    let (part, stats) = match outcome {
        Outcome::Done(part, stats) => (part, stats),
        Outcome::Stopped(tiles, _) => {
            let refs: Vec<&TileData> = tiles.iter().collect();
            save(&refs);
            let saved = save_error.lock().expect("not poisoned").is_none();
            return Err(CliError::Failed(if saved {
                format!(
                    "stopped by {} after {}/{grid_len} tiles; checkpoint {} saved: run the same \
                     command with --resume to continue",
                    signals.name(),
                    tiles.len(),
                    ckpt_path.display()
                )
            } else {
                format!(
                    "stopped by {} and the checkpoint could not be written",
                    signals.name()
                )
            }));
        }
    };
    check_finite(&part.data)?;
    if raw {
        let image = part_image(&part, &info).map_err(CliError::Failed)?;
        crate::image::write(&args.output, &image, WriteOptions::new(PixelType::F32))
            .map_err(|e| input(e.to_string()))?;
        reporter.event("wrote", &args.output.display().to_string());
        if !args.quiet && !reporter.prints_lines() {
            eprintln!("wrote {}", args.output.display());
        }
    } else {
        let film = part.into_film(w, h).expect("a whole render");
        let metadata: Vec<(String, String)> = info
            .metadata()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        write_modes(
            &film,
            &modes,
            &scene.settings.wavelengths,
            args.wavelength,
            &args.output,
            &metadata,
            args.quiet,
            &reporter,
        )?;
    }
    // The outputs are complete: the checkpoint has served.
    let _ = std::fs::remove_file(&ckpt_path);
    if !args.quiet {
        let secs = t_render.as_secs_f64();
        eprintln!(
            "{}x{} px, region {}, samples {}, {} wavelength(s): accel {} {:.2} s, render {:.2} s, {} rays ({:.2} M rays/s), {} nodes, {} pruned, {} cut by depth, {} lost{}",
            w,
            h,
            spec.region,
            spec.samples.label(),
            options.lambdas.len(),
            accel_kind,
            t_accel.as_secs_f64(),
            secs,
            stats.rays,
            stats.rays as f64 / secs / 1e6,
            stats.nodes,
            stats.pruned,
            stats.depth_cut,
            stats.lost,
            if stats.lost > 0 {
                format!(" ({})", stats.lost_breakdown())
            } else {
                String::new()
            }
        );
    }
    // Lost light is reported even with --quiet: the image is wrong.
    if let Some(w) = stats.lost_light_warning() {
        eprintln!("spar: warning: {scene_label}: {w}");
    }
    reporter.event("done", &format!("{:.1}s", started.elapsed().as_secs_f64()));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_take_a_count_or_a_block() {
        assert_eq!(parse_samples("64"), Ok(SamplesArg::Count(64)));
        assert_eq!(
            parse_samples("16..32"),
            Ok(SamplesArg::Block {
                start: 16,
                end: 32,
                total: None
            })
        );
        assert_eq!(
            parse_samples("0..8/64"),
            Ok(SamplesArg::Block {
                start: 0,
                end: 8,
                total: Some(64)
            })
        );
        assert!(parse_samples("8..8").is_err());
        assert!(parse_samples("a..8").is_err());
        assert!(parse_samples("-1").is_err());
    }

    #[test]
    fn isa_names_are_checked() {
        assert!(check_isa("sse2").is_ok());
        assert!(check_isa("avx512skx").is_err());
        assert!(check_isa("bogus").unwrap_err().contains("sse4.2"));
    }
}
