//! Services the commands share that are not argument types: loading the
//! scene, checking outputs before any work and writing developed images,
//! worker threads, memory and sanity checks of a render, signal handling.

use super::error::CliError;
use crate::farm::progress::Reporter;
use crate::image::{Image, PixelType, WriteOptions};
use crate::render::film::Film;
use crate::render::output::{develop, OutputMode};
use crate::scene::{builtin, Scene};
use crate::spectrum::WavelengthSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

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

/// Refuses rendered values that are not finite (no NaN pixel is ever
/// written): an internal error, never the input's fault.
pub(crate) fn check_finite<'a>(values: impl IntoIterator<Item = &'a f32>) -> Result<(), CliError> {
    match crate::farm::non_finite(values) {
        Some((first, count)) => Err(CliError::internal(format!(
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
        return Err(CliError::input(format!(
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
    check_memory(film_bytes(pixels, lambdas, nodes), what)
}

/// Refuses work that needs more than the available memory, naming `what`
/// needs the `bytes`: the user asked for too much (exit status 2).
pub fn check_memory(bytes: f64, what: &str) -> Result<(), CliError> {
    crate::farm::memory::check(bytes, what).map_err(CliError::input)
}

pub(crate) fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, CliError> {
    check_threads(threads)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::internal(format!("cannot start worker threads: {e}")))
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
        return Err(CliError::output(format!(
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
        return Err(CliError::output(format!(
            "{}: the directory {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    if path.is_dir() {
        return Err(CliError::output(format!(
            "{}: is a directory, not a file name",
            path.display()
        )));
    }
    Ok(())
}

/// Develops `film` into the image of `mode`. What develop refuses (a
/// colour set too sparse to carry colour, a wavelength the film lacks)
/// comes from the scene, the flags or the raw file: an input error.
pub fn develop_image(
    film: &Film,
    mode: OutputMode,
    colour: &WavelengthSet,
    mono_nm: f64,
) -> Result<Image, CliError> {
    develop(film, mode, colour, mono_nm).map_err(CliError::input)
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
        let mut image = develop_image(film, m, colour, mono_nm)?;
        for (k, v) in metadata {
            image = image.with_metadata(k.clone(), v.clone());
        }
        let image = image.with_metadata("spar:mode", m.name());
        let options = match m {
            OutputMode::Stokes => WriteOptions::new(PixelType::F32),
            _ => WriteOptions::new(PixelType::U8),
        };
        crate::image::write(&path, &image, options)?;
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
            let fail =
                |e: std::io::Error| CliError::internal(format!("cannot handle signals: {e}"));
            flag::register_conditional_shutdown(SIGINT, 130, s.stop.clone()).map_err(fail)?;
            for sig in [SIGTERM, SIGINT] {
                flag::register_usize(sig, s.which.clone(), sig as usize).map_err(fail)?;
                flag::register(sig, s.stop.clone()).map_err(fail)?;
            }
            flag::register(SIGUSR1, s.save.clone()).map_err(fail)?;
        }
        Ok(s)
    }

    /// The signal that stopped the render, by name.
    pub fn name(&self) -> &'static str {
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
        Some(path) => Ok(Scene::load(path)?),
        // The embedded scene is spar's own: failing to read it is too.
        None => Scene::parse(builtin::DEFAULT_SCENE, "(default scene)", Path::new("."))
            .map_err(|e| CliError::internal(e.to_string())),
    }
}

/// Checks `--wavelength` (a single-wavelength mode's wavelength).
pub fn check_wavelength(nm: f64) -> Result<(), CliError> {
    if nm.is_finite() && (360.0..=830.0).contains(&nm) {
        Ok(())
    } else {
        Err(CliError::input(format!(
            "--wavelength {nm} is outside 360–830 nm"
        )))
    }
}
