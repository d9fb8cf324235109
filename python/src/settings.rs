//! Settings from Python: keyword arguments (`samples=8`,
//! `max_depth=20`, `quality="draft"` …) become the command line's
//! [`SceneOverrides`], resolved onto the scene by spar's one validator
//! (`render::settings`, through `SceneOverrides::apply_from`). A bad
//! value is refused with the command line's message, the setting named as
//! Python names it: `max_depth must be at most 1000`.

use crate::errors;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use spar::cli::args::{SamplesArg, SceneOverrides};
use spar::render::approx::{
    BranchingArg, CoherenceModel, DispersionMode, PolarizationArg, Spectral,
};
use spar::render::quality::Quality;
use spar::render::rig::LightRig;
use spar::render::settings::Origin;
use spar::scene::Scene;
use std::str::FromStr;

/// The settings a scene takes from Python, in the order the docs list
/// them.
pub const NAMES: [&str; 18] = [
    "samples",
    "resolution",
    "wavelengths",
    "max_depth",
    "prune",
    "seed",
    "quality",
    "branching",
    "polarization",
    "coherence",
    "spectral",
    "dispersion",
    "bundle",
    "roulette",
    "adaptive",
    "min_samples",
    "edges",
    "max_samples",
];

/// What a render takes besides the settings: the lights and the stone's
/// pose for that render only (`spar render --light-rig`, `--tilt`). They
/// change the scene's lights and objects, not its settings, so
/// `Scene.set` refuses them (a tilt set twice would add up).
pub const RENDER_ONLY: [&str; 2] = ["light_rig", "tilt"];

/// The Python name of a command-line flag: `--max-depth` → `max_depth`.
fn python_name(flag: &str) -> String {
    flag.trim_start_matches('-').replace('-', "_")
}

/// A whole number for `name` that fits `T`, or an `InputError` naming it.
fn whole<T: TryFrom<i128>>(name: &str, value: &Bound<'_, PyAny>) -> PyResult<T> {
    let n: i128 = value.extract().map_err(|_| {
        errors::input(format!(
            "{name}: expected a whole number, got {}",
            describe(value)
        ))
    })?;
    T::try_from(n).map_err(|_| errors::input(format!("{name}: {n} is out of range")))
}

fn real(name: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    value.extract().map_err(|_| {
        errors::input(format!(
            "{name}: expected a number, got {}",
            describe(value)
        ))
    })
}

fn text(name: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    value.extract().map_err(|_| {
        errors::input(format!(
            "{name}: expected a string, got {}",
            describe(value)
        ))
    })
}

/// A value as a message shows it: its repr and type.
fn describe(value: &Bound<'_, PyAny>) -> String {
    let repr = value
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into());
    let ty = value
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    format!("{repr} ({ty})")
}

/// A string setting parsed as its flag parses it.
fn parsed<T: FromStr<Err = String>>(name: &str, value: &Bound<'_, PyAny>) -> PyResult<T> {
    let s = text(name, value)?;
    T::from_str(&s).map_err(|e| errors::input(format!("{name}: {e}")))
}

/// `resolution`: `(width, height)` or the flag's `"WIDTHxHEIGHT"`.
fn resolution(value: &Bound<'_, PyAny>) -> PyResult<(u32, u32)> {
    if let Ok(s) = value.downcast::<PyString>() {
        let s = s.to_str()?;
        let bad = || {
            errors::input(format!(
                "resolution `{s}`: expected WIDTHxHEIGHT or (width, height)"
            ))
        };
        let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
        let side = |v: &str| v.trim().parse::<u32>().map_err(|_| bad());
        return Ok((side(w)?, side(h)?));
    }
    let pair: Vec<Bound<'_, PyAny>> = value.extract().map_err(|_| {
        errors::input(format!(
            "resolution: expected (width, height), got {}",
            describe(value)
        ))
    })?;
    if pair.len() != 2 {
        return Err(errors::input(format!(
            "resolution: expected (width, height), got {} values",
            pair.len()
        )));
    }
    Ok((
        whole("resolution width", &pair[0])?,
        whole("resolution height", &pair[1])?,
    ))
}

/// `wavelengths`: a count over 380–780 nm, a sequence in nm, or the
/// flag's text (`"21"`, `"580nm"`, `"450,550,650"`), as the flag's text
/// (numbers written so they read back exactly).
fn wavelengths(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(s) = value.downcast::<PyString>() {
        return Ok(s.to_str()?.to_string());
    }
    if let Ok(n) = whole::<u64>("wavelengths", value) {
        return Ok(n.to_string());
    }
    let list: Vec<f64> = value.extract().map_err(|_| {
        errors::input(format!(
            "wavelengths: expected a count, a sequence of nm or a string, got {}",
            describe(value)
        ))
    })?;
    if list.is_empty() {
        return Err(errors::input("wavelengths: the sequence is empty"));
    }
    Ok(list
        .iter()
        .map(|l| l.to_string())
        .collect::<Vec<_>>()
        .join(","))
}

/// Puts the setting `name` = `value` into `o`; an unknown name is a
/// `TypeError`, as for any function's unknown keyword.
fn set(o: &mut SceneOverrides, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
    match name {
        "samples" => o.samples = Some(SamplesArg::Count(whole(name, value)?)),
        "resolution" => o.resolution = Some(resolution(value)?),
        "wavelengths" => o.wavelengths = Some(wavelengths(value)?),
        "max_depth" => o.max_depth = Some(whole(name, value)?),
        "prune" => o.prune = Some(real(name, value)?),
        "seed" => o.seed = Some(whole(name, value)?),
        "quality" => {
            let s = text(name, value)?;
            o.quality = Some(
                <Quality as clap::ValueEnum>::from_str(&s, false).map_err(|_| {
                    errors::input(format!(
                        "quality `{s}`: expected draft, fast, default or reference"
                    ))
                })?,
            );
        }
        "branching" => o.branching = Some(parsed::<BranchingArg>(name, value)?),
        "polarization" => o.polarization = Some(parsed::<PolarizationArg>(name, value)?),
        "coherence" => o.coherence = Some(parsed::<CoherenceModel>(name, value)?),
        "spectral" => o.spectral = Some(parsed::<Spectral>(name, value)?),
        "dispersion" => o.dispersion = Some(parsed::<DispersionMode>(name, value)?),
        "bundle" => o.bundle = Some(real(name, value)?),
        "roulette" => o.roulette = Some(real(name, value)?),
        "adaptive" => o.adaptive = Some(real(name, value)?),
        "min_samples" => o.min_samples = Some(whole(name, value)?),
        "edges" => o.edges = Some(real(name, value)?),
        "max_samples" => o.max_samples = Some(whole(name, value)?),
        "light_rig" => o.light_rig = Some(parsed::<LightRig>(name, value)?),
        "tilt" => o.tilt = Some(real(name, value)?),
        other => {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "unknown setting `{other}`; the settings are {} (and, for render, {})",
                NAMES.join(", "),
                RENDER_ONLY.join(", ")
            )))
        }
    }
    Ok(())
}

/// The overrides in `settings` (None values are left out).
pub fn overrides(settings: Option<&Bound<'_, PyDict>>) -> PyResult<SceneOverrides> {
    let mut o = SceneOverrides::default();
    if let Some(d) = settings {
        for (k, v) in d.iter() {
            if v.is_none() {
                continue;
            }
            let name: String = k.extract()?;
            set(&mut o, &name, &v)?;
        }
    }
    Ok(o)
}

/// Resolves `o` onto `scene`, checked by spar's validator; on an error the
/// scene is unchanged.
pub fn apply(scene: &mut Scene, o: &SceneOverrides) -> PyResult<()> {
    o.apply_from(scene, &|flag| Origin::Flag(python_name(flag)))
        .map(|_| ())
        .map_err(errors::cli)
}

/// The scene's settings as a dict of plain Python values (what the
/// getters of `Scene` return; `quality` is a preset, not a setting, and
/// is not in it).
pub fn as_dict<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let s = &scene.settings;
    d.set_item("samples", scene.samples)?;
    d.set_item("resolution", (scene.camera.width, scene.camera.height))?;
    d.set_item("wavelengths", s.wavelengths.lambdas().to_vec())?;
    d.set_item("max_depth", s.max_depth)?;
    d.set_item("prune", s.prune)?;
    d.set_item("seed", s.seed)?;
    d.set_item(
        "branching",
        BranchingArg(s.approx.strategy.branching).to_string(),
    )?;
    d.set_item(
        "polarization",
        PolarizationArg(s.approx.strategy.polarization).to_string(),
    )?;
    d.set_item("coherence", s.approx.strategy.coherence.to_string())?;
    d.set_item("spectral", s.approx.spectral.to_string())?;
    d.set_item("dispersion", s.approx.dispersion.to_string())?;
    d.set_item("bundle", s.approx.strategy.bundle)?;
    d.set_item("roulette", s.approx.strategy.roulette)?;
    d.set_item("adaptive", s.adaptive.noise)?;
    d.set_item("min_samples", s.adaptive.min_samples)?;
    d.set_item("edges", s.adaptive.edges)?;
    d.set_item("max_samples", s.adaptive.max_samples)?;
    Ok(d)
}
