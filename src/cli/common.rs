//! Services the commands share that are not argument types: loading the
//! scene, checking outputs before any work and writing developed images,
//! worker threads, memory and sanity checks of a render, signal handling.

use super::error::CliError;
use crate::farm::progress::Reporter;
use crate::image::{Image, PixelType, WriteOptions};
use crate::render::film::Film;
use crate::render::output::{develop, develop_files, map_of, stokes_preview, OutputMode, Storage};
use crate::scene::{builtin, Scene};
use crate::spectrum::WavelengthSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// One file a mode writes: its path, how it holds its values, and which
/// of the mode's images ([`OutputMode::parts`]) it is.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeFile {
    pub mode: OutputMode,
    pub path: PathBuf,
    pub storage: Storage,
    pub part: usize,
}

/// The files `modes` write for `-o output` (`None`: `spar`), checked
/// before any work: exit status 2 for a name the modes cannot be written
/// as, naming the name to use.
///
/// - One mode: the name as given, if its extension fits the mode
///   ([`OutputMode::storage`]); no extension: the mode's own
///   ([`OutputMode::extension`]); `polcam` appends `-000` … `-135`.
/// - Several modes: the mode's name is appended to the stem
///   (`out-color.png`, `out-polcam-045.exr`); the name's extension is
///   each mode's format where it fits that mode and the mode's own where
///   it does not (`-o out.png --mode color,stokes` writes `out-color.png`
///   and `out-stokes.exr`), but it must fit at least one of them.
pub fn mode_files(output: Option<&Path>, modes: &[OutputMode]) -> Result<Vec<ModeFile>, CliError> {
    let output = output.unwrap_or(Path::new("spar"));
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "spar".into());
    let ext = output.extension().map(|e| e.to_string_lossy().into_owned());
    let several = modes.len() > 1;
    if let (Some(ext), true) = (&ext, several) {
        if modes.iter().all(|m| m.storage(ext).is_none()) {
            return Err(CliError::input(format!(
                "{}: none of the modes {} writes .{ext} files (give -o {} to have each mode's \
                 own)",
                output.display(),
                modes.iter().map(|m| m.name()).collect::<Vec<_>>().join(","),
                output.with_file_name(&stem).display()
            )));
        }
    }
    let mut files = Vec::new();
    for &mode in modes {
        let (ext, storage) = match ext.as_deref().map(|e| (e, mode.storage(e))) {
            Some((e, Some(storage))) => (e.to_string(), storage),
            Some((e, None)) if !several => {
                let fit = output.with_extension(mode.extension());
                return Err(CliError::input(format!(
                    "{}: the {} mode {}, not a .{e} file: use -o {}",
                    output.display(),
                    mode.name(),
                    writes(mode),
                    fit.display()
                )));
            }
            _ => {
                let e = mode.extension();
                (
                    e.to_string(),
                    mode.storage(e).expect("a mode's own extension fits"),
                )
            }
        };
        for (part, suffix) in mode.parts().iter().enumerate() {
            let mut name = stem.clone();
            if several {
                name = format!("{name}-{}", mode.name());
            }
            if !suffix.is_empty() {
                name = format!("{name}-{suffix}");
            }
            files.push(ModeFile {
                mode,
                path: output.with_file_name(format!("{name}.{ext}")),
                storage,
                part,
            });
        }
    }
    Ok(files)
}

/// What a mode writes, for a refused output name.
fn writes(mode: OutputMode) -> String {
    let list = |e: Vec<&str>| {
        e.iter()
            .map(|e| format!(".{e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match mode {
        m if m.is_stokes() => "writes float Stokes values, an OpenEXR file (.exr)".into(),
        m if m.is_polcam() => format!(
            "writes linear float intensities (.exr) or a display image ({})",
            list(m.extensions().into_iter().filter(|&e| e != "exr").collect())
        ),
        m => format!(
            "writes a display image ({}; for values as floats, --mode stokes or polcam to .exr)",
            list(m.extensions())
        ),
    }
}

/// What `--wavelength` does for `modes`: the modes as traced (stokes
/// becomes mono's one wavelength when `--wavelength` is given) and the
/// Stokes EXR's wavelength. A `--wavelength` no mode uses (color or
/// stokes-rgb alone) is refused (exit status 2) rather than ignored.
pub fn wavelength_use(
    wavelength: Option<f64>,
    modes: &[OutputMode],
) -> Result<(Vec<OutputMode>, Option<f64>), CliError> {
    let Some(nm) = wavelength else {
        return Ok((modes.to_vec(), None));
    };
    if modes.iter().all(|&m| !m.uses_wavelength()) {
        let names: Vec<&str> = modes.iter().map(|m| m.name()).collect();
        let users: Vec<&str> = <OutputMode as clap::ValueEnum>::value_variants()
            .iter()
            .filter(|m| m.uses_wavelength())
            .map(|m| m.name())
            .collect();
        return Err(CliError::input(format!(
            "--wavelength {nm}: the {} mode uses the scene's wavelengths (render.wavelengths, \
             --wavelengths), not --wavelength; it sets the wavelength of {}",
            names.join(","),
            users.join(", ")
        )));
    }
    let stokes = modes.contains(&OutputMode::Stokes).then_some(nm);
    let traced = modes
        .iter()
        .map(|&m| match m {
            OutputMode::Stokes => OutputMode::Mono,
            m => m,
        })
        .collect();
    Ok((traced, stokes))
}

/// `--wavelength`'s default, nm.
pub const DEFAULT_WAVELENGTH: f64 = 580.0;

/// The single-wavelength modes' wavelength for commands that develop
/// `modes` from one render (`compare`, `contact-sheet`, `speed-error`):
/// `--wavelength` if given (checked, and refused with exit status 2 when
/// none of `modes` uses it, rather than ignored), else 580 nm.
pub fn mono_wavelength(wavelength: Option<f64>, modes: &[OutputMode]) -> Result<f64, CliError> {
    let Some(nm) = wavelength else {
        return Ok(DEFAULT_WAVELENGTH);
    };
    check_wavelength(nm)?;
    if modes.iter().all(|m| !m.uses_wavelength()) {
        let names: Vec<&str> = modes.iter().map(|m| m.name()).collect();
        return Err(CliError::input(format!(
            "--wavelength {nm}: no mode asked for uses it ({} use the scene's wavelengths, \
             render.wavelengths or --wavelengths); it sets the wavelength of mono, dop, \
             ellipticity, ellipticity-paper, azimuth, aolp, dolp and the polvis maps",
            names.join(",")
        )));
    }
    Ok(nm)
}

/// Refuses rendered values that are not finite (no NaN pixel is ever
/// written): an internal error, never the input's fault.
pub fn check_finite<'a>(values: impl IntoIterator<Item = &'a f32>) -> Result<(), CliError> {
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

/// Bytes edge-adaptive sampling keeps per render besides the film: each
/// pixel's sums after its first samples (four `f32` per wavelength), its
/// noise sums (`PixelNoise`, 168 bytes, kept with adaptive sampling on;
/// counted always) and what it and its border show (80 bytes).
pub fn edges_bytes(pixels: u64, lambdas: usize) -> f64 {
    pixels as f64 * (lambdas as f64 * 16.0 + 256.0)
}

/// Refuses a render whose film (and, with edge-adaptive sampling on, its
/// first samples' sums) cannot fit in the available memory, naming `what`
/// asks for it (the flags or scene fields of size and wavelengths).
pub fn check_film_memory(
    pixels: u64,
    lambdas: usize,
    nodes: usize,
    edges: bool,
    what: &str,
) -> Result<(), CliError> {
    let extra = if edges {
        edges_bytes(pixels, lambdas)
    } else {
        0.0
    };
    check_memory(film_bytes(pixels, lambdas, nodes) + extra, what)
}

/// Refuses work that needs more than the available memory, naming `what`
/// needs the `bytes`: the user asked for too much (exit status 2).
pub fn check_memory(bytes: f64, what: &str) -> Result<(), CliError> {
    crate::farm::memory::check(bytes, what).map_err(CliError::input)
}

pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, CliError> {
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

/// Develops `film` into each of `files` ([`mode_files`]) and writes them
/// (the one code path of `spar render` and `spar develop`). `stokes_nm`
/// puts only that wavelength into the Stokes EXR (`--wavelength` with the
/// stokes mode; the film must hold it). `metadata` goes into every file,
/// with `spar:mode`, and `spar:wavelengths_nm` (the Stokes EXR's
/// wavelengths) or `spar:wavelength_nm` (a polarization camera's).
#[allow(clippy::too_many_arguments)]
pub fn write_modes(
    film: &Film,
    files: &[ModeFile],
    colour: &WavelengthSet,
    mono_nm: f64,
    stokes_nm: Option<f64>,
    metadata: &[(String, String)],
    quiet: bool,
    reporter: &Reporter,
) -> Result<(), CliError> {
    let one;
    let stokes_film = match stokes_nm {
        Some(nm) => {
            one = film.only(nm).ok_or_else(|| {
                CliError::input(format!(
                    "--wavelength {nm}: the stokes mode's wavelength was not traced (the film \
                     holds {:?} nm)",
                    film.lambdas
                ))
            })?;
            &one
        }
        None => film,
    };
    // A mode's images, developed once for all its files.
    let mut developed: Option<(OutputMode, Vec<Image>)> = None;
    for f in files {
        if developed.as_ref().is_none_or(|(m, _)| *m != f.mode) {
            let film = match f.mode {
                OutputMode::Stokes => stokes_film,
                _ => film,
            };
            let images = if f.mode == OutputMode::Sheet {
                vec![super::legend::sheet(film, colour, mono_nm)?.0]
            } else {
                develop_files(film, f.mode, colour, mono_nm, f.storage).map_err(CliError::input)?
            };
            developed = Some((f.mode, images));
        }
        let mut image = developed.as_ref().expect("developed above").1[f.part].clone();
        // The Stokes file's RGB preview (JCGT 2021 layout), where the film
        // holds the colour wavelengths.
        if f.mode == OutputMode::Stokes {
            if let Some(rgb) = stokes_preview(stokes_film, colour) {
                let mut planes: Vec<(String, Vec<f32>)> = ["R", "G", "B"]
                    .iter()
                    .map(|c| c.to_string())
                    .zip(rgb)
                    .collect();
                for name in image.channels().to_vec() {
                    let plane = image.channel(&name)?;
                    planes.push((name, plane));
                }
                let metadata = image.metadata().clone();
                image = Image::from_planes(image.width(), image.height(), planes)?;
                for (k, v) in metadata {
                    image = image.with_metadata(k, v);
                }
            }
        }
        // The false-colour maps carry their legend in display images.
        if let (Storage::Display, Some(map)) = (f.storage, map_of(f.mode, f.part)) {
            image = super::legend::with_legend(&image, map)?;
        }
        for (k, v) in metadata {
            image = image.with_metadata(k.clone(), v.clone());
        }
        image = image.with_metadata("spar:mode", f.mode.name());
        match f.mode {
            OutputMode::Stokes => {
                let nms: Vec<String> = stokes_film.lambdas.iter().map(|l| l.to_string()).collect();
                image = image.with_metadata("spar:wavelengths_nm", nms.join(","));
            }
            OutputMode::StokesRgb => {
                let nms: Vec<String> = colour.lambdas().iter().map(|l| l.to_string()).collect();
                image = image.with_metadata("spar:wavelengths_nm", nms.join(","));
            }
            m if m.is_polcam() => {
                image = image.with_metadata("spar:wavelength_nm", mono_nm.to_string());
            }
            _ => {}
        }
        let options = match f.storage {
            Storage::Float => WriteOptions::new(PixelType::F32),
            Storage::Display => WriteOptions::new(PixelType::U8),
        };
        crate::image::write(&f.path, &image, options)?;
        reporter.event("wrote", &f.path.display().to_string());
        if !quiet && !reporter.prints_lines() {
            eprintln!("wrote {}", f.path.display());
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
