//! `spar.Scene`: a scene read from a file or from TOML text, whose
//! settings Python can read and change (each change checked by spar's
//! validator), and which renders.

use crate::errors;
use crate::render::{self, Request};
use crate::settings;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use spar::scene::Scene as SparScene;
use std::path::{Path, PathBuf};

/// A scene: its objects, lights and camera as the file gave them, and
/// settings that can be changed.
#[pyclass(module = "spar", name = "Scene")]
#[derive(Clone)]
pub struct Scene {
    pub inner: SparScene,
    /// How the scene is named in messages and metadata: the path as
    /// given, or `<string>` for TOML text.
    pub label: String,
}

/// Reads a scene: `source` is a path (str or os.PathLike) to a scene
/// file, or the TOML text of one (a str with a line break in it).
/// Relative paths inside TOML text resolve against `base_dir` (default:
/// the working directory); a file's, against the file's directory.
#[pyfunction]
#[pyo3(signature = (source, *, base_dir=None))]
pub fn load_scene(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    base_dir: Option<PathBuf>,
) -> PyResult<Scene> {
    let text = source
        .downcast::<PyString>()
        .ok()
        .map(|s| s.to_str().map(str::to_string))
        .transpose()?
        .filter(|s| s.contains('\n'));
    match text {
        Some(text) => {
            let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
            let inner =
                SparScene::parse(&text, "<string>", &base).map_err(|e| errors::scene(py, &e))?;
            Ok(Scene {
                inner,
                label: "<string>".into(),
            })
        }
        None => {
            if base_dir.is_some() {
                return Err(errors::input(
                    "base_dir is for TOML text; a scene file's paths are relative to its own \
                     directory",
                ));
            }
            let path: PathBuf = source.extract().map_err(|_| {
                errors::input(
                    "load_scene: expected a path (str or os.PathLike) or the TOML text of a scene",
                )
            })?;
            let inner = SparScene::load(Path::new(&path)).map_err(|e| errors::scene(py, &e))?;
            Ok(Scene {
                inner,
                label: path.display().to_string(),
            })
        }
    }
}

/// The embedded default scene (`spar render` without a scene file).
#[pyfunction]
pub fn default_scene() -> PyResult<Scene> {
    let inner = spar::cli::common::load_scene(None).map_err(errors::cli)?;
    Ok(Scene {
        inner,
        label: "(default scene)".into(),
    })
}

impl Scene {
    fn get(&self, py: Python<'_>, name: &str) -> PyResult<PyObject> {
        let d = settings::as_dict(py, &self.inner)?;
        Ok(d.get_item(name)?
            .expect("every setting is in the dict")
            .unbind())
    }

    fn set_one(&mut self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let d = PyDict::new(value.py());
        d.set_item(name, value)?;
        self.set(Some(&d))
    }
}

#[pymethods]
impl Scene {
    /// Changes several settings at once (samples, resolution, wavelengths,
    /// max_depth, prune, seed, quality, branching, polarization,
    /// coherence, spectral, dispersion, bundle, roulette, adaptive,
    /// min_samples, edges, max_samples),
    /// checked together as the command line checks its flags: `quality` is a preset the others override.
    /// On an error nothing changes.
    #[pyo3(signature = (**settings))]
    fn set(&mut self, settings: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        if let Some(d) = settings {
            for name in settings::RENDER_ONLY {
                if d.contains(name)? {
                    return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                        "{name} applies to one render: pass it to render(), which leaves the \
                         scene as it is"
                    )));
                }
            }
        }
        let o = settings::overrides(settings)?;
        settings::apply(&mut self.inner, &o)
    }

    /// A copy whose settings can change without changing this scene.
    fn copy(&self) -> Scene {
        self.clone()
    }

    /// Every setting, as plain values.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        settings::as_dict(py, &self.inner)
    }

    /// The scene as messages and render metadata name it.
    #[getter]
    fn label(&self) -> &str {
        &self.label
    }

    /// Samples per pixel.
    #[getter]
    fn samples(&self) -> u32 {
        self.inner.samples
    }
    #[setter]
    fn set_samples(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("samples", value)
    }

    /// Image size, (width, height) in pixels.
    #[getter]
    fn resolution(&self) -> (u32, u32) {
        (self.inner.camera.width, self.inner.camera.height)
    }
    #[setter]
    fn set_resolution(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("resolution", value)
    }

    /// The colour modes' wavelengths, nm. Set a count (over 380–780 nm),
    /// a sequence in nm, or the flag's text ("580nm", "450,550,650").
    #[getter]
    fn wavelengths(&self) -> Vec<f64> {
        self.inner.settings.wavelengths.lambdas().to_vec()
    }
    #[setter]
    fn set_wavelengths(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("wavelengths", value)
    }

    /// The most surface interactions along a path.
    #[getter]
    fn max_depth(&self) -> u32 {
        self.inner.settings.max_depth
    }
    #[setter]
    fn set_max_depth(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("max_depth", value)
    }

    /// Pruning threshold, a fraction of the brightest emitter (0: none).
    #[getter]
    fn prune(&self) -> f64 {
        self.inner.settings.prune
    }
    #[setter]
    fn set_prune(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("prune", value)
    }

    /// The random seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.settings.seed
    }
    #[setter]
    fn set_seed(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("seed", value)
    }

    /// Branch strategy: "full", "stochastic" or "hybrid:K".
    #[getter]
    fn branching(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.get(py, "branching")
    }
    #[setter]
    fn set_branching(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("branching", value)
    }

    /// Polarization model: "full" or "scalar".
    #[getter]
    fn polarization(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.get(py, "polarization")
    }
    #[setter]
    fn set_polarization(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("polarization", value)
    }

    /// How paths combine: "physical" or "incoherent".
    #[getter]
    fn coherence(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.get(py, "coherence")
    }
    #[setter]
    fn set_coherence(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("coherence", value)
    }

    /// Spectral sampling: "all" or "hero:K".
    #[getter]
    fn spectral(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.get(py, "spectral")
    }
    #[setter]
    fn set_spectral(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("spectral", value)
    }

    /// Dispersion: "on", "off" or "bands:K".
    #[getter]
    fn dispersion(&self, py: Python<'_>) -> PyResult<PyObject> {
        self.get(py, "dispersion")
    }
    #[setter]
    fn set_dispersion(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("dispersion", value)
    }

    /// o/e bundle tolerance in pixel footprints (0: every eigenwave its
    /// own ray); needs coherence "incoherent".
    #[getter]
    fn bundle(&self) -> f64 {
        self.inner.settings.approx.strategy.bundle
    }
    #[setter]
    fn set_bundle(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("bundle", value)
    }

    /// Russian roulette threshold, a fraction of the brightest light (0:
    /// off, the exact tree).
    #[getter]
    fn roulette(&self) -> f64 {
        self.inner.settings.approx.strategy.roulette
    }
    #[setter]
    fn set_roulette(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("roulette", value)
    }

    /// Adaptive sampling: a pixel stops taking samples once the standard
    /// error of its mean is at most this, in display units (0: off;
    /// `samples` is then the most a pixel takes).
    #[getter]
    fn adaptive(&self) -> f64 {
        self.inner.settings.adaptive.noise
    }
    #[setter]
    fn set_adaptive(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("adaptive", value)
    }

    /// Samples every pixel takes before adaptive sampling's first check.
    #[getter]
    fn min_samples(&self) -> u32 {
        self.inner.settings.adaptive.min_samples
    }
    #[setter]
    fn set_min_samples(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("min_samples", value)
    }

    /// Edge-adaptive sampling: a pixel takes every sample only if its first
    /// `min_samples` differ from a neighbour's by more than this, in
    /// display units (0: off).
    #[getter]
    fn edges(&self) -> f64 {
        self.inner.settings.adaptive.edges
    }
    #[setter]
    fn set_edges(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("edges", value)
    }

    /// Edge refinement (with `edges`): a pixel at an edge that has taken
    /// all its samples goes on, four times as many at a time up to this,
    /// while what it shows still moves by more than `edges` (from its
    /// first samples to all, then from one step to the next; 0: off).
    #[getter]
    fn max_samples(&self) -> u32 {
        self.inner.settings.adaptive.max_samples
    }
    #[setter]
    fn set_max_samples(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("max_samples", value)
    }

    /// Applies a quality preset (draft, fast, default, reference): depth,
    /// pruning and approximations.
    #[setter]
    fn set_quality(&mut self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set_one("quality", value)
    }

    /// Renders the scene; see the module's stub for the arguments. The
    /// settings given here apply to this render only, on a copy of the
    /// scene.
    #[pyo3(signature = (mode=None, *, wavelength=None, accel=None, threads=None, progress=false, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn render(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        mode: Option<&Bound<'_, PyAny>>,
        wavelength: Option<f64>,
        accel: Option<String>,
        threads: Option<usize>,
        progress: bool,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<render::Render> {
        // A copy, borrowed only for this line: while it renders, other
        // threads may change (or render) this scene.
        let (mut scene, label) = {
            let this = slf.borrow();
            (this.inner.clone(), this.label.clone())
        };
        settings::apply(&mut scene, &settings::overrides(settings)?)?;
        let modes: Vec<String> = match mode.map(|m| (m, m.downcast::<PyString>())) {
            None => vec!["stokes".into()],
            Some((_, Ok(s))) => s
                .to_str()?
                .split(',')
                .map(|m| m.trim().to_string())
                .collect(),
            Some((mode, Err(_))) => mode.extract().map_err(|_| {
                errors::input(
                    "mode: expected a mode name, a comma-separated list or a sequence of names",
                )
            })?,
        };
        let request = Request {
            modes,
            wavelength,
            accel,
            threads,
            progress,
        };
        render::render(py, &scene, &label, &request)
    }

    fn __repr__(&self) -> String {
        let s = &self.inner;
        format!(
            "<spar.Scene {} {}x{} px, {} samples, {} wavelengths, {} object(s)>",
            self.label,
            s.camera.width,
            s.camera.height,
            s.samples,
            s.settings.wavelengths.len(),
            s.objects.len()
        )
    }
}
