//! `spar render [SCENE]`: render a scene file (or the embedded default
//! scene) in one or more camera modes, or one unit of work of a render
//! farm as a raw EXR part (`--region`, `--tile`, `--samples k0..k1`,
//! `--raw`; see docs/farm.md).

use super::args::{check_isa, AccelArgs, FarmArgs, SceneOverrides};
use super::common::{
    check_film_memory, check_finite, check_output, check_threads, check_wavelength, load_scene,
    mode_files, thread_pool, wavelength_use, write_modes, ModeFile, Signals,
};
use super::error::CliError;
use crate::accel::AccelKind;
use crate::farm::checkpoint;
use crate::farm::part::{part_image, RenderInfo};
use crate::farm::progress::{ProgressMode, Reporter};
use crate::image::{PixelType, WriteOptions};
use crate::render::blocks::SampleRange;
use crate::render::film::Film;
use crate::render::integrator::Stats;
use crate::render::output::OutputMode;
use crate::render::prepare;
use crate::render::region::{self, Rect};
use crate::render::{
    render_part, Control, Outcome, PartSpec, RawPart, RenderOptions, TileData, TILE,
};
use crate::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML). Without one, the embedded default scene: a calcite
    /// gem over a textured light.
    pub scene: Option<PathBuf>,
    /// Camera modes, comma-separated: color, mono, dop, ellipticity,
    /// ellipticity-paper, azimuth, stokes (JCGT 2021 spectral EXR),
    /// stokes-rgb (Mitsuba 3's S0.R..S3.B), aolp, dolp, polvis-stokes,
    /// polvis-dop, polvis-top, polvis-lin, polvis-cir (false colours with
    /// legends), polcam (four images behind polarizers at 0, 45, 90, 135
    /// degrees), polcam-mosaic (them as a polarization sensor's 2x2
    /// mosaic), sheet (color, DoP and AoLP side by side, labelled),
    /// dichroscope (color behind polarizers along image right and image
    /// up, side by side: a dichroic stone's two colours).
    /// Default: sheet without a scene file (the first run), color with
    /// one or for a raw output. With a raw output they choose the
    /// wavelengths traced.
    #[arg(long, short, value_delimiter = ',')]
    pub mode: Vec<OutputMode>,
    /// Output file (default: spar, with each mode's own extension). Its
    /// extension must fit the mode: .exr for stokes; .png (.tif, .jpg with
    /// OpenImageIO) for display images; .exr (floats) or .png for polcam
    /// and polcam-mosaic. polcam appends -000, -045, -090, -135. With
    /// several modes, each mode's name is appended to the stem
    /// (spar-color.png, spar-stokes.exr) and the extension is used by the
    /// modes it fits. A raw output is one .exr file.
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// Wavelength of the single-wavelength modes (mono, dop, ellipticity,
    /// ellipticity-paper, azimuth, aolp, dolp, the polvis maps, polcam,
    /// polcam-mosaic, the sheet's maps), nm; default 580. Given with
    /// stokes, the Stokes EXR holds this wavelength only. Refused when no
    /// mode asked for uses it (color or stokes-rgb alone).
    #[arg(long)]
    pub wavelength: Option<f64>,
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
    /// Keep no checkpoint (set by `spar tilt`, whose frames are rendered
    /// whole or not at all): a stopped render writes nothing.
    #[arg(skip)]
    pub no_checkpoint: bool,
}

/// A finished render and what it cost.
pub struct Rendered {
    pub film: Film,
    pub stats: Stats,
    pub options: RenderOptions,
    pub accel_time: std::time::Duration,
    pub render_time: std::time::Duration,
}

/// Renders what `modes` need: the scene's colour wavelengths for the
/// spectral modes, `mono_nm` for the others; `threads` 0 means all cores;
/// `accel` traces; `convex_exit` false sends every ray to it, the rays
/// inside convex stones too (`spar compare --backend-only`; renders pass
/// true).
pub fn render_film(
    scene: &Scene,
    modes: &[OutputMode],
    mono_nm: f64,
    threads: usize,
    progress: bool,
    accel: AccelKind,
    convex_exit: bool,
) -> Result<Rendered, CliError> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = prepare::lambdas(scene, modes, mono_nm).len();
    check_film_memory(
        w as u64 * h as u64,
        n,
        1,
        scene.settings.adaptive.edges_on(),
        &format!("a {w}x{h} render of {n} wavelength(s)"),
    )?;
    let pool = thread_pool(threads)?;
    let t0 = Instant::now();
    let accel = prepare::accel(scene, accel, pool.current_num_threads(), None)?;
    let accel_time = t0.elapsed();
    let mut options = prepare::options(scene, modes, mono_nm, progress);
    options.tree.convex_exit = convex_exit;
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

pub use super::common::DEFAULT_WAVELENGTH;

/// What `spar render`'s flags ask for, checked before any work starts.
struct Job {
    scene: Scene,
    /// The scene as messages and metadata name it.
    label: String,
    /// The modes asked for (repeats removed) as the tracer sees them:
    /// stokes at one wavelength (`--wavelength` given) traces what mono
    /// traces.
    traced: Vec<OutputMode>,
    /// The single-wavelength modes' wavelength, nm.
    mono_nm: f64,
    /// The Stokes EXR's one wavelength, if `--wavelength` chose it.
    stokes_nm: Option<f64>,
    /// The files the modes write (empty for a raw output).
    files: Vec<ModeFile>,
    /// The raw output's path (with images, the first file's).
    output: PathBuf,
    accel: AccelKind,
    /// The pixels and samples to render.
    spec: PartSpec,
    /// A raw EXR (a farm part or `--raw`) instead of images.
    raw: bool,
}

/// With colour on the first ⌈S/N⌉ samples (`spectral = …/N`) and no
/// single-wavelength mode, the other samples trace nothing: said, since
/// fewer samples would give the same image sooner.
fn idle_samples_note(options: &RenderOptions) -> Option<String> {
    let spectral = options.approx.spectral;
    let traced = spectral.colour_samples(options.samples);
    (options.colour_lambdas >= options.lambdas.len() && traced < options.samples).then(|| {
        format!(
            "spectral = {spectral} traces colour on {traced} of {} samples per pixel and no \
             single-wavelength mode uses the others, so they trace nothing (`/N` pays with \
             dop, mono, ellipticity, … rendered beside colour)",
            options.samples
        )
    })
}

/// Edge-adaptive sampling that cannot stop a pixel early: its first
/// samples are all the pixel's samples (`min_samples` ≥ `samples`).
fn idle_edges_note(options: &RenderOptions) -> Option<String> {
    let a = options.adaptive;
    (a.edges_on() && a.min_samples >= options.samples).then(|| {
        format!(
            "edges = {} changes nothing: every pixel takes its first {} samples, and there are \
             {} (lower --min-samples: 8 or 16 pay)",
            a.edges, a.min_samples, options.samples
        )
    })
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let started = Instant::now();
    let job = checked_job(args)?;
    let lambdas = prepare::lambdas(&job.scene, &job.traced, job.mono_nm);
    let info = render_info(args, &job, lambdas.clone());
    let progress_mode = if args.quiet {
        ProgressMode::None
    } else {
        args.farm.progress
    };
    let reporter = Reporter::new(progress_mode);
    let options = prepare::options(&job.scene, &job.traced, job.mono_nm, reporter.wants_bar());
    debug_assert_eq!(options.lambdas, lambdas);
    for n in [idle_samples_note(&options), idle_edges_note(&options)]
        .into_iter()
        .flatten()
    {
        if !args.quiet {
            eprintln!("spar: note: {}: {n}", job.label);
        }
    }
    let ckpt = Checkpoint::new(args, &job, &info, &options);
    let resume = ckpt.resume(args, &reporter)?;
    let done = render(args, &job, &options, &ckpt, resume, &reporter)?;
    write_outputs(args, &job, &info, done.part, &reporter)?;
    // The outputs are complete: the checkpoint has served.
    if !args.no_checkpoint {
        let _ = std::fs::remove_file(&ckpt.path);
    }
    if !args.quiet {
        print_summary(
            &job,
            &options,
            &done.stats,
            done.accel_time,
            done.render_time,
        );
    }
    // Lost light is reported even with --quiet: the image is wrong.
    if let Some(w) = done.stats.lost_light_warning() {
        eprintln!("spar: warning: {}: {w}", job.label);
    }
    reporter.event("done", &format!("{:.1}s", started.elapsed().as_secs_f64()));
    Ok(())
}

/// Checks everything `args` ask for (exit status 2) without rendering or
/// writing anything: what `spar tilt` does for every frame before the
/// first.
pub fn check(args: &RenderArgs) -> Result<(), CliError> {
    checked_job(args).map(|_| ())
}

/// The scene with the overrides applied and everything the flags ask for,
/// checked (exit status 2) before anything is rendered or written.
fn checked_job(args: &RenderArgs) -> Result<Job, CliError> {
    if let Some(t) = args.threads {
        check_threads(t)?;
    }
    let mut scene = load_scene(args.scene.as_deref())?;
    let block = args.overrides.apply_with_block(&mut scene)?;
    if let Some(nm) = args.wavelength {
        check_wavelength(nm)?;
    }
    let raw =
        args.farm.raw || args.farm.region.is_some() || args.farm.tile.is_some() || block.is_some();
    // Without --mode: the first-run sheet for the default scene, color
    // for a scene file or a raw output (docs/outputs.md).
    let mut modes = if !args.mode.is_empty() {
        args.mode.clone()
    } else if args.scene.is_none() && !raw {
        vec![OutputMode::Sheet]
    } else {
        vec![OutputMode::Color]
    };
    modes.dedup();
    if let Some(m) = modes.iter().find(|m| {
        matches!(
            m,
            OutputMode::Color | OutputMode::StokesRgb | OutputMode::Sheet | OutputMode::Dichroscope
        )
    }) {
        crate::spectrum::Observer::new(&scene.settings.wavelengths)
            .map_err(|e| CliError::input(format!("wavelengths for the {} mode: {e}", m.name())))?;
    }
    let (traced, stokes_nm) = wavelength_use(args.wavelength, &modes)?;
    let mono_nm = args.wavelength.unwrap_or(DEFAULT_WAVELENGTH);
    let farm = &args.farm;
    if let Some(isa) = &farm.isa {
        check_isa(isa)?;
    }
    let accel = args.accel.kind(farm.isa.as_deref())?;
    let region = region_of(farm, scene.camera.width, scene.camera.height)?;
    let samples = block.unwrap_or(SampleRange::all(scene.samples));
    let spec = PartSpec { region, samples };
    check_film_memory(
        spec.region.area() as u64,
        prepare::lambdas(&scene, &traced, mono_nm).len(),
        spec.samples.nodes().len(),
        scene.settings.adaptive.edges_on(),
        &film_what(
            &scene,
            args.scene.as_deref(),
            &args.overrides,
            spec.region,
            &traced,
            mono_nm,
        ),
    )?;
    let (output, files) = check_outputs(args, raw, &modes)?;
    let label = args
        .scene
        .as_ref()
        .map_or("(default scene)".into(), |p| p.display().to_string());
    Ok(Job {
        scene,
        label,
        traced,
        mono_nm,
        stokes_nm,
        files,
        output,
        accel,
        spec,
        raw,
    })
}

/// The pixels `--region` or `--tile` ask for (checked against the `w`×`h`
/// image), or the whole image.
fn region_of(farm: &FarmArgs, w: u32, h: u32) -> Result<Rect, CliError> {
    Ok(match (farm.region, farm.tile) {
        (Some(r), _) => {
            if !r.fits(w, h) {
                return Err(CliError::input(format!(
                    "--region {r} is not inside the {w}x{h} image (x0,x1,y0,y1, ends exclusive)"
                )));
            }
            r
        }
        (None, Some(t)) => region::split(w, h, t.count)
            .map_err(|e| CliError::input(format!("--tile {}/{}: {e}", t.index, t.count)))?
            [t.index as usize],
        (None, None) => Rect::full(w, h),
    })
}

/// Refuses to start a long render whose output cannot be written: a raw
/// output must be an .exr, each mode's name must fit it ([`mode_files`]),
/// and every file's directory must exist. Returns the raw output's path
/// (`spar.exr` by default) and the modes' files (none for a raw output).
fn check_outputs(
    args: &RenderArgs,
    raw: bool,
    modes: &[OutputMode],
) -> Result<(PathBuf, Vec<ModeFile>), CliError> {
    if raw {
        let output = args.output.clone().unwrap_or_else(|| "spar.exr".into());
        if output
            .extension()
            .is_none_or(|e| !e.eq_ignore_ascii_case("exr"))
        {
            return Err(CliError::input(format!(
                "{}: a raw part (--region, --tile, --samples k0..k1, --raw) is an .exr file",
                output.display()
            )));
        }
        check_output(&output)?;
        Ok((output, Vec::new()))
    } else {
        let files = mode_files(args.output.as_deref(), modes)?;
        for f in &files {
            check_output(&f.path)?;
        }
        let output = files[0].path.clone();
        Ok((output, files))
    }
}

/// The identity of this render (what parts of one render share), with
/// the backend it traces with.
fn render_info(args: &RenderArgs, job: &Job, lambdas: Vec<f64>) -> RenderInfo {
    let mut info = RenderInfo::new(
        &job.scene,
        &job.label,
        lambdas,
        job.mono_nm,
        args.farm.isa.as_deref(),
    );
    // Backends may hit different triangles at edges: parts of different
    // backends are different renders (the ISA is Embree's alone).
    info.accel = job.accel.name().into();
    if job.accel != AccelKind::Embree {
        info.isa = "none".into();
    }
    info
}

/// The checkpoint of a render: named after the output; valid only for
/// this render, part and tile size.
struct Checkpoint {
    path: PathBuf,
    key: String,
}

impl Checkpoint {
    fn new(args: &RenderArgs, job: &Job, info: &RenderInfo, options: &RenderOptions) -> Self {
        let spec = &job.spec;
        let path = args.farm.checkpoint.clone().unwrap_or_else(|| {
            // Named after -o as given (the first mode's file without it).
            let output = args.output.as_ref().unwrap_or(&job.output);
            let mut name = output.as_os_str().to_owned();
            name.push(".checkpoint");
            PathBuf::from(name)
        });
        let key = format!(
            "{} region {} samples {} tile {TILE} channels {}",
            info.key(),
            spec.region,
            spec.samples.label(),
            options.lambdas.len() * 4
        );
        Checkpoint { path, key }
    }

    /// The tiles done already: the checkpoint's with `--resume` (none if
    /// there is no file), else none (with a note if a checkpoint exists).
    fn resume(&self, args: &RenderArgs, reporter: &Reporter) -> Result<Vec<TileData>, CliError> {
        let path = self.path.display();
        if !args.farm.resume {
            if self.path.exists() && !args.quiet && !args.no_checkpoint {
                eprintln!("spar: note: {path} exists; pass --resume to continue from it");
            }
            return Ok(Vec::new());
        }
        Ok(match checkpoint::load(&self.path, &self.key)? {
            Some(tiles) => {
                reporter.event("resume", &format!("{path} ({} tiles done)", tiles.len()));
                tiles
            }
            None => {
                reporter.event(
                    "resume",
                    &format!("no checkpoint at {path}: starting afresh"),
                );
                Vec::new()
            }
        })
    }

    /// Saves `tiles` of the `grid_len` of the part; a failure is reported
    /// and kept in `error` (the render goes on).
    fn save(
        &self,
        tiles: &[&TileData],
        grid_len: usize,
        reporter: &Reporter,
        error: &Mutex<Option<String>>,
    ) {
        match checkpoint::save(&self.path, &self.key, tiles) {
            Ok(()) => reporter.event(
                "checkpoint",
                &format!("{} {}/{grid_len} tiles", self.path.display(), tiles.len()),
            ),
            Err(e) => {
                let msg = format!("cannot write checkpoint {}: {e}", self.path.display());
                eprintln!("spar: {msg}");
                *error.lock().expect("not poisoned") = Some(msg);
            }
        }
    }
}

/// A rendered part and what it cost.
struct Done {
    part: RawPart,
    stats: Stats,
    accel_time: Duration,
    render_time: Duration,
}

/// Renders the part, saving a checkpoint on SIGUSR1 and, stopped by a
/// signal, before it returns the error saying so.
fn render(
    args: &RenderArgs,
    job: &Job,
    options: &RenderOptions,
    ckpt: &Checkpoint,
    resume: Vec<TileData>,
    reporter: &Reporter,
) -> Result<Done, CliError> {
    let signals = Signals::install()?;
    let threads = args.threads.unwrap_or(0);
    let pool = thread_pool(threads)?;
    let t_accel = Instant::now();
    let accel = prepare::accel(
        &job.scene,
        job.accel,
        pool.current_num_threads(),
        args.farm.isa.as_deref(),
    )?;
    let accel_time = t_accel.elapsed();
    let spec = &job.spec;
    let grid_len = crate::render::tiles(spec.region, TILE).len();
    reporter.event(
        "start",
        &format!(
            "render {} region {} samples {} ({grid_len} tiles, {} threads)",
            job.label,
            spec.region,
            spec.samples.label(),
            pool.current_num_threads()
        ),
    );
    let save_error = Mutex::new(None::<String>);
    let save = |tiles: &[&TileData]| ckpt.save(tiles, grid_len, reporter, &save_error);
    let on_progress = |done: usize, total: usize| reporter.tiles(done, total);
    let keep = !args.no_checkpoint;
    let control = Control {
        tile_size: TILE,
        stop: Some(&signals.stop),
        checkpoint: keep.then_some(&signals.save),
        on_checkpoint: keep.then_some(&save),
        on_progress: Some(&on_progress),
        resume,
    };
    let t_render = Instant::now();
    let outcome = pool.install(|| render_part(&job.scene, accel.as_ref(), options, spec, control));
    let render_time = t_render.elapsed();
    match outcome {
        Outcome::Done(part, stats) => Ok(Done {
            part,
            stats,
            accel_time,
            render_time,
        }),
        Outcome::Stopped(tiles, _) if !keep => Err(CliError::internal(format!(
            "stopped by {} after {}/{grid_len} tiles: nothing written",
            signals.name(),
            tiles.len()
        ))),
        Outcome::Stopped(tiles, _) => {
            let refs: Vec<&TileData> = tiles.iter().collect();
            save(&refs);
            let saved = save_error.lock().expect("not poisoned").is_none();
            Err(CliError::internal(if saved {
                format!(
                    "stopped by {} after {}/{grid_len} tiles; checkpoint {} saved: run the same \
                     command with --resume to continue",
                    signals.name(),
                    tiles.len(),
                    ckpt.path.display()
                )
            } else {
                format!(
                    "stopped by {} and the checkpoint could not be written",
                    signals.name()
                )
            }))
        }
    }
}

/// Writes the part: as a raw EXR, or developed into each mode's image.
fn write_outputs(
    args: &RenderArgs,
    job: &Job,
    info: &RenderInfo,
    part: RawPart,
    reporter: &Reporter,
) -> Result<(), CliError> {
    check_finite(&part.data)?;
    if job.raw {
        // The part's values are spar's own: an image of them that cannot
        // be made is its failure.
        let image = part_image(&part, info).map_err(CliError::internal)?;
        crate::image::write(&job.output, &image, WriteOptions::new(PixelType::F32))?;
        reporter.event("wrote", &job.output.display().to_string());
        if !args.quiet && !reporter.prints_lines() {
            eprintln!("wrote {}", job.output.display());
        }
        return Ok(());
    }
    let (w, h) = (job.scene.camera.width, job.scene.camera.height);
    let film = part.into_film(w, h).expect("a whole render");
    let metadata: Vec<(String, String)> = info
        .metadata()
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    write_modes(
        &film,
        &job.files,
        &job.scene.settings.wavelengths,
        job.mono_nm,
        job.stokes_nm,
        &metadata,
        args.quiet,
        reporter,
    )
}

/// The summary line of a render: its size, part, times and what its rays
/// did.
fn print_summary(
    job: &Job,
    options: &RenderOptions,
    stats: &Stats,
    accel_time: Duration,
    render_time: Duration,
) {
    let secs = render_time.as_secs_f64();
    let samples = if options.adaptive.edges_on() {
        let most = match options.adaptive.max_samples {
            0 => String::new(),
            m => format!(", up to {m}"),
        };
        format!(
            "{} (edges {}{most}: {:.2} per pixel)",
            job.spec.samples.label(),
            options.adaptive.edges,
            stats.samples as f64 / job.spec.region.area().max(1) as f64
        )
    } else if options.adaptive.is_on() {
        format!(
            "{} (adaptive {}: {:.2} per pixel)",
            job.spec.samples.label(),
            options.adaptive.noise,
            stats.samples as f64 / job.spec.region.area().max(1) as f64
        )
    } else {
        job.spec.samples.label()
    };
    eprintln!(
        "{}x{} px, region {}, samples {}, {} wavelength(s): accel {} {:.2} s, render {:.2} s, {} rays ({:.2} M rays/s), {} nodes, {} pruned{}, {} cut by depth, {} coherent, {} lost{}",
        job.scene.camera.width,
        job.scene.camera.height,
        job.spec.region,
        samples,
        options.lambdas.len(),
        job.accel,
        accel_time.as_secs_f64(),
        secs,
        stats.rays,
        stats.rays as f64 / secs / 1e6,
        stats.nodes,
        stats.pruned,
        if options.approx.strategy.roulette > 0.0 {
            format!(", {} ended by roulette", stats.rouletted)
        } else {
            String::new()
        },
        stats.depth_cut,
        stats.coherent,
        stats.lost,
        if stats.lost > 0 {
            format!(" ({})", stats.lost_breakdown())
        } else {
            String::new()
        }
    );
}
