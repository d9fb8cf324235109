//! `spar render [SCENE]`: render a scene file (or the embedded default
//! scene) in one or more camera modes.

use super::CliError;
use crate::accel::{Intersector, TriangleMesh};
use crate::image::{PixelType, WriteOptions};
use crate::render::integrator::TreeSettings;
use crate::render::output::{develop, OutputMode};
use crate::render::{render, RenderOptions};
use crate::scene::{builtin, Scene};
use crate::spectrum::WavelengthSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML). Without one, the embedded default scene: a calcite
    /// gem over a textured light.
    pub scene: Option<PathBuf>,
    /// Camera modes, comma-separated: color, mono, dop, ellipticity,
    /// ellipticity-paper, azimuth, stokes.
    #[arg(long, short, value_delimiter = ',', default_value = "color")]
    pub mode: Vec<OutputMode>,
    /// Output file. With several modes, each mode's name is appended to its
    /// stem (spar-color.png, spar-dop.png, spar-stokes.exr).
    #[arg(long, short, default_value = "spar.png")]
    pub output: PathBuf,
    /// Wavelength of the single-wavelength modes (mono, dop, ellipticity,
    /// azimuth), nm.
    #[arg(long, default_value_t = 580.0)]
    pub wavelength: f64,
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar or summary.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Settings that override a scene file's.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneOverrides {
    /// Wavelengths of the color mode: a count over 380–780 nm, one
    /// wavelength (580nm) or a list (450,550,650). Overrides the scene.
    #[arg(long)]
    pub wavelengths: Option<String>,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    pub samples: Option<u32>,
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
}

impl SceneOverrides {
    /// Applies the overrides to a scene, checked like the scene's own values.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), CliError> {
        let input = CliError::Input;
        if let Some(spec) = &self.wavelengths {
            scene.settings.wavelengths =
                WavelengthSet::parse(spec).map_err(|e| input(format!("--wavelengths: {e}")))?;
        }
        if let Some(s) = self.samples {
            if s == 0 {
                return Err(input("--samples must be at least 1".into()));
            }
            scene.samples = s;
        }
        if let Some((w, h)) = self.resolution {
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
        Ok(())
    }
}

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT"))?;
    let p = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|&v| (1..=65536).contains(&v))
    };
    match (p(w), p(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be whole numbers from 1 to 65536"
        )),
    }
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

fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A finished render and what it cost.
pub struct Rendered {
    pub film: crate::render::film::Film,
    pub stats: crate::render::integrator::Stats,
    pub options: RenderOptions,
    pub accel_time: std::time::Duration,
    pub render_time: std::time::Duration,
}

/// Renders what `modes` need: the scene's colour wavelengths for the
/// spectral modes, `mono_nm` for the others; `threads` 0 means all cores.
pub fn render_film(
    scene: &Scene,
    modes: &[OutputMode],
    mono_nm: f64,
    threads: usize,
    progress: bool,
) -> Result<Rendered, CliError> {
    let mut lambdas: Vec<f64> = Vec::new();
    if modes.iter().any(|m| m.is_spectral()) {
        lambdas.extend_from_slice(scene.settings.wavelengths.lambdas());
    }
    if modes.iter().any(|m| !m.is_spectral())
        && !lambdas.iter().any(|&l| (l - mono_nm).abs() < 1e-9)
    {
        lambdas.push(mono_nm);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start worker threads: {e}")))?;
    let t0 = Instant::now();
    let accel = build_accel(scene, pool.current_num_threads())?;
    let accel_time = t0.elapsed();
    let options = RenderOptions {
        lambdas,
        tree: TreeSettings {
            max_depth: scene.settings.max_depth,
            prune: scene.settings.prune,
        },
        samples: scene.samples,
        seed: scene.settings.seed,
        progress,
    };
    let t1 = Instant::now();
    let (film, stats) = pool.install(|| render(scene, accel.as_ref(), &options));
    let render_time = t1.elapsed();
    if film.data.iter().flatten().any(|v| !v.is_finite()) {
        return Err(CliError::Failed(
            "internal error: the render produced non-finite values".into(),
        ));
    }
    Ok(Rendered {
        film,
        stats,
        options,
        accel_time,
        render_time,
    })
}

/// Builds the Embree accelerator for a scene's objects.
#[cfg(feature = "native")]
pub fn build_accel(scene: &Scene, threads: usize) -> Result<Box<dyn Intersector>, CliError> {
    let verts: Vec<Vec<[f32; 3]>> = scene
        .objects
        .iter()
        .map(|o| o.mesh.vertices_f32())
        .collect();
    let meshes: Vec<TriangleMesh> = scene
        .objects
        .iter()
        .zip(&verts)
        .map(|(o, v)| TriangleMesh {
            vertices: v,
            triangles: &o.mesh.triangles,
        })
        .collect();
    let accel = crate::accel::embree::EmbreeAccel::build(&meshes, threads, None)
        .map_err(|e| CliError::Failed(e.to_string()))?;
    Ok(Box::new(accel))
}

#[cfg(not(feature = "native"))]
pub fn build_accel(_scene: &Scene, _threads: usize) -> Result<Box<dyn Intersector>, CliError> {
    let _ = TriangleMesh {
        vertices: &[],
        triangles: &[],
    };
    Err(CliError::Failed(
        "this build has no intersection backend (built without the `native` feature)".into(),
    ))
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let input = CliError::Input;
    let mut scene = match &args.scene {
        Some(path) => Scene::load(path).map_err(|e| input(e.to_string()))?,
        None => Scene::parse(builtin::DEFAULT_SCENE, "(default scene)", Path::new("."))
            .map_err(|e| CliError::Failed(e.to_string()))?,
    };
    args.overrides.apply(&mut scene)?;
    if !(args.wavelength.is_finite() && (360.0..=830.0).contains(&args.wavelength)) {
        return Err(input(format!(
            "--wavelength {} is outside 360–830 nm",
            args.wavelength
        )));
    }
    if args.mode.contains(&OutputMode::Color) {
        crate::spectrum::Observer::new(&scene.settings.wavelengths)
            .map_err(|e| input(format!("wavelengths for the color mode: {e}")))?;
    }
    let mut modes = args.mode.clone();
    modes.dedup();
    if modes.is_empty() {
        return Err(input("--mode needs at least one mode".into()));
    }
    // Refuse to start a long render whose output cannot be written.
    for &m in &modes {
        let path = output_path(&args.output, m, modes.len() > 1);
        let dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !dir.is_dir() {
            return Err(input(format!(
                "{}: the directory {} does not exist",
                path.display(),
                dir.display()
            )));
        }
    }

    let threads = args.threads.unwrap_or(0);
    let done = render_film(&scene, &modes, args.wavelength, threads, !args.quiet)?;
    let (film, stats, opts) = (&done.film, done.stats, &done.options);
    let (t_accel, t_render) = (done.accel_time, done.render_time);

    let settings = format!(
        "resolution={}x{} samples={} max_depth={} prune={} seed={} wavelengths={:?} mono_nm={}",
        scene.camera.width,
        scene.camera.height,
        scene.samples,
        opts.tree.max_depth,
        opts.tree.prune,
        opts.seed,
        scene.settings.wavelengths.lambdas(),
        args.wavelength
    );
    for &m in &modes {
        let path = output_path(&args.output, m, modes.len() > 1);
        let image = develop(film, m, &scene.settings.wavelengths, args.wavelength)
            .map_err(CliError::Failed)?
            .with_metadata("spar:version", crate::VERSION)
            .with_metadata("spar:mode", m.name())
            .with_metadata(
                "spar:scene",
                args.scene
                    .as_ref()
                    .map_or("(default scene)".into(), |p| p.display().to_string()),
            )
            .with_metadata("spar:scene_hash", format!("{:016x}", fnv1a(&scene.source)))
            .with_metadata("spar:settings", settings.clone());
        let options = match m {
            OutputMode::Stokes => WriteOptions::new(PixelType::F32),
            _ => WriteOptions::new(PixelType::U8),
        };
        crate::image::write(&path, &image, options).map_err(|e| input(e.to_string()))?;
        if !args.quiet {
            eprintln!("wrote {}", path.display());
        }
    }
    if !args.quiet {
        let secs = t_render.as_secs_f64();
        eprintln!(
            "{}x{} px, {} spp, {} wavelength(s): accel {:.2} s, render {:.2} s, {} rays ({:.2} M rays/s), {} nodes, {} pruned, {} cut by depth, {} lost",
            scene.camera.width,
            scene.camera.height,
            scene.samples,
            film.lambdas.len(),
            t_accel.as_secs_f64(),
            secs,
            stats.rays,
            stats.rays as f64 / secs / 1e6,
            stats.nodes,
            stats.pruned,
            stats.depth_cut,
            stats.lost
        );
    }
    Ok(())
}
