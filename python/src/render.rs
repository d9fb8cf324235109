//! `Scene.render`: the command line's render, without files. The modes
//! and wavelengths are checked as `spar render` checks them
//! (`cli::common`), the render is `render::render_part` with a stop flag,
//! and each mode is developed by the code that develops the command
//! line's files (`render::output`), so the arrays hold the values the
//! files hold (the Stokes EXR's, bit for bit).
//!
//! The render runs on a thread of its own with the GIL released; the
//! calling thread wakes every 50 ms to let Python handle signals. Ctrl-C
//! (KeyboardInterrupt, or any exception a signal handler raises) sets the
//! render's stop flag, waits for the tiles in flight, and raises.

use crate::arrays;
use crate::errors;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spar::accel::AccelKind;
use spar::cli::args::check_accel;
use spar::cli::common::{
    check_film_memory, check_finite, check_threads, check_wavelength, thread_pool, wavelength_use,
};
use spar::cli::error::CliError;
use spar::cli::render::DEFAULT_WAVELENGTH;
use spar::farm::part::RenderInfo;
use spar::render::film::Film;
use spar::render::integrator::Stats;
use spar::render::output::{develop, develop_files, OutputMode, Storage};
use spar::render::{prepare, render_part, Control, Outcome, PartSpec, RawPart};
use spar::scene::Scene;
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What `Scene.render` was asked for beyond the scene's settings.
pub struct Request {
    /// Mode names as given.
    pub modes: Vec<String>,
    /// The single-wavelength modes' wavelength, nm (`--wavelength`).
    pub wavelength: Option<f64>,
    /// `embree` or `rust` (`--accel`).
    pub accel: Option<String>,
    /// Worker threads, 0 or None for one per core (`--threads`).
    pub threads: Option<usize>,
    /// A progress bar on standard error.
    pub progress: bool,
}

/// The result of a render: one array per mode, the wavelengths, the
/// metadata the command line's files carry, and what the rays did.
#[pyclass(module = "spar", name = "Render", frozen)]
pub struct Render {
    /// The modes rendered, in the order asked.
    #[pyo3(get)]
    modes: Vec<String>,
    /// mode name → NumPy float32 array.
    #[pyo3(get)]
    images: Py<PyDict>,
    /// The wavelengths of the Stokes array (nm, float64); without the
    /// stokes mode, every traced wavelength.
    #[pyo3(get)]
    wavelengths: PyObject,
    /// The single-wavelength modes' wavelength, nm.
    #[pyo3(get)]
    wavelength: f64,
    /// spar:version, spar:scene, spar:scene_hash, spar:settings: the
    /// metadata of the command line's files for the same render.
    #[pyo3(get)]
    metadata: Py<PyDict>,
    /// Rays, nodes, pruned, rouletted, depth_cut, coherent, lost; accel_seconds,
    /// render_seconds.
    #[pyo3(get)]
    stats: Py<PyDict>,
}

#[pymethods]
impl Render {
    /// The array of one mode.
    fn __getitem__(&self, py: Python<'_>, mode: &str) -> PyResult<PyObject> {
        match self.images.bind(py).get_item(mode)? {
            Some(a) => Ok(a.unbind()),
            None => Err(pyo3::exceptions::PyKeyError::new_err(format!(
                "no {mode} image: this render has {}",
                self.modes.join(", ")
            ))),
        }
    }

    /// The Stokes array, (wavelengths, height, width, 4): S0..S3 per
    /// pixel, per wavelength of `wavelengths`.
    #[getter]
    fn stokes(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.__getitem__(py, "stokes")
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let shapes: Vec<String> = self
            .modes
            .iter()
            .map(|m| {
                let shape = self
                    .images
                    .bind(py)
                    .get_item(m)
                    .ok()
                    .flatten()
                    .and_then(|a| a.getattr("shape").ok())
                    .map(|s| s.to_string())
                    .unwrap_or_default();
                format!("{m}{shape}")
            })
            .collect();
        format!("<spar.Render {}>", shapes.join(", "))
    }
}

/// The modes as `OutputMode`s, repeats removed.
fn parse_modes(names: &[String]) -> PyResult<Vec<OutputMode>> {
    let mut modes = Vec::new();
    for name in names {
        let m = <OutputMode as clap::ValueEnum>::from_str(name, false).map_err(|_| {
            let all: Vec<&str> = <OutputMode as clap::ValueEnum>::value_variants()
                .iter()
                .map(|m| m.name())
                .collect();
            errors::input(format!("mode `{name}`: expected one of {}", all.join(", ")))
        })?;
        if !modes.contains(&m) {
            modes.push(m);
        }
    }
    if modes.is_empty() {
        return Err(errors::input("mode: at least one mode is needed"));
    }
    Ok(modes)
}

/// A finished render and what it cost.
struct Done {
    part: RawPart,
    stats: Stats,
    accel_time: Duration,
    render_time: Duration,
}

/// What a render cost: the rays' statistics and the times.
struct Cost {
    stats: Stats,
    accel_time: Duration,
    render_time: Duration,
}

/// Renders `scene` (its settings already applied) as `request` asks.
pub fn render(py: Python<'_>, scene: &Scene, label: &str, request: &Request) -> PyResult<Render> {
    let modes = parse_modes(&request.modes)?;
    let threads = request.threads.unwrap_or(0);
    check_threads(threads).map_err(errors::cli)?;
    if let Some(nm) = request.wavelength {
        check_wavelength(nm).map_err(errors::cli)?;
    }
    if modes.contains(&OutputMode::Color) {
        spar::spectrum::Observer::new(&scene.settings.wavelengths)
            .map_err(|e| errors::input(format!("wavelengths for the color mode: {e}")))?;
    }
    let (traced, stokes_nm) = wavelength_use(request.wavelength, &modes).map_err(errors::cli)?;
    let mono_nm = request.wavelength.unwrap_or(DEFAULT_WAVELENGTH);
    let accel = match &request.accel {
        Some(name) => AccelKind::from_str(name).map_err(errors::input)?,
        None => AccelKind::default(),
    };
    check_accel(accel, None).map_err(errors::cli)?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let lambdas = prepare::lambdas(scene, &traced, mono_nm);
    check_film_memory(
        w as u64 * h as u64,
        lambdas.len(),
        1,
        scene.settings.adaptive.edges_on(),
        &format!("a {w}x{h} render of {} wavelength(s)", lambdas.len()),
    )
    .map_err(errors::cli)?;
    let options = prepare::options(scene, &traced, mono_nm, request.progress);
    let mut info = RenderInfo::new(scene, label, lambdas, mono_nm, None);
    // As `spar render` names its backend (parts of different backends
    // are different renders).
    info.accel = accel.name().into();
    if accel != AccelKind::Embree {
        info.isa = "none".into();
    }

    let done = interruptible(py, |stop| -> Result<Option<Done>, CliError> {
        let pool = thread_pool(threads)?;
        let t0 = Instant::now();
        let intersector = prepare::accel(scene, accel, pool.current_num_threads(), None)?;
        let accel_time = t0.elapsed();
        let control = Control {
            stop: Some(stop),
            ..Control::default()
        };
        let spec = PartSpec::whole(w, h, options.samples);
        let t1 = Instant::now();
        let outcome =
            pool.install(|| render_part(scene, intersector.as_ref(), &options, &spec, control));
        Ok(match outcome {
            Outcome::Done(part, stats) => Some(Done {
                part,
                stats,
                accel_time,
                render_time: t1.elapsed(),
            }),
            Outcome::Stopped(..) => None,
        })
    })?;
    let done = match done.map_err(errors::cli)? {
        Some(done) => done,
        // Stopped without a Python exception: only a stop flag set by
        // us stops a render, so this does not happen; say so if it does.
        None => return Err(errors::internal("the render stopped before it finished")),
    };
    check_finite(&done.part.data).map_err(errors::cli)?;
    if let Some(warning) = done.stats.lost_light_warning() {
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &std::ffi::CString::new(format!("{label}: {warning}")).unwrap_or_default(),
            1,
        )?;
    }
    let Done {
        part,
        stats,
        accel_time,
        render_time,
    } = done;
    let cost = Cost {
        stats,
        accel_time,
        render_time,
    };
    let film = part
        .into_film(w, h)
        .ok_or_else(|| errors::internal("the render did not cover the whole image"))?;
    develop_all(py, &film, scene, &modes, mono_nm, stokes_nm, &info, &cost)
}

/// Develops each mode into its array and gathers the result.
#[allow(clippy::too_many_arguments)]
fn develop_all(
    py: Python<'_>,
    film: &Film,
    scene: &Scene,
    modes: &[OutputMode],
    mono_nm: f64,
    stokes_nm: Option<f64>,
    info: &RenderInfo,
    cost: &Cost,
) -> PyResult<Render> {
    let colour = &scene.settings.wavelengths;
    let images = PyDict::new(py);
    let mut wavelengths = film.lambdas.clone();
    for &mode in modes {
        let array = match mode {
            OutputMode::Stokes => {
                let one;
                let film = match stokes_nm {
                    Some(nm) => {
                        one = film.only(nm).ok_or_else(|| {
                            errors::internal(format!("wavelength {nm} nm was not traced"))
                        })?;
                        &one
                    }
                    None => film,
                };
                wavelengths = film.lambdas.clone();
                let image = develop(film, mode, colour, mono_nm).map_err(errors::input)?;
                arrays::stokes(py, &image, film.lambdas.len())?
            }
            OutputMode::Polcam | OutputMode::PolcamMosaic => {
                let images = develop_files(film, mode, colour, mono_nm, Storage::Float)
                    .map_err(errors::input)?;
                arrays::grey(py, &images)?
            }
            _ => {
                let image = develop(film, mode, colour, mono_nm).map_err(errors::input)?;
                arrays::interleaved(py, &image)?
            }
        };
        images.set_item(mode.name(), array)?;
    }
    let metadata = PyDict::new(py);
    for (k, v) in info.metadata() {
        metadata.set_item(k, v)?;
    }
    let s = &cost.stats;
    let stats = PyDict::new(py);
    stats.set_item("rays", s.rays)?;
    stats.set_item("nodes", s.nodes)?;
    stats.set_item("pruned", s.pruned)?;
    stats.set_item("rouletted", s.rouletted)?;
    stats.set_item("depth_cut", s.depth_cut)?;
    stats.set_item("coherent", s.coherent)?;
    stats.set_item("lost", s.lost)?;
    stats.set_item("accel_seconds", cost.accel_time.as_secs_f64())?;
    stats.set_item("render_seconds", cost.render_time.as_secs_f64())?;
    Ok(Render {
        modes: modes.iter().map(|m| m.name().to_string()).collect(),
        images: images.unbind(),
        wavelengths: arrays::vector(py, wavelengths),
        wavelength: mono_nm,
        metadata: metadata.unbind(),
        stats: stats.unbind(),
    })
}

/// Runs `work` on a thread of its own with the GIL released, handing it
/// a stop flag; the calling thread wakes every 50 ms to run Python's
/// signal handlers. If one raises (Ctrl-C's KeyboardInterrupt), the flag
/// is set, `work` is waited for (it must return soon once the flag is
/// set), and the exception is returned.
fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let caller = std::thread::current();
    std::thread::scope(|s| {
        let stop = &stop;
        let handle = s.spawn(move || {
            let result = work(stop);
            caller.unpark();
            result
        });
        let mut interrupted = None;
        while !handle.is_finished() {
            py.allow_threads(|| std::thread::park_timeout(Duration::from_millis(50)));
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    stop.store(true, Ordering::SeqCst);
                    interrupted = Some(e);
                }
            }
        }
        let result = handle
            .join()
            .map_err(|_| errors::internal("the render thread panicked"));
        match interrupted {
            Some(e) => Err(e),
            None => result,
        }
    })
}
