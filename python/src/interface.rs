//! `spar.interface`: one interface solved by `spar interface`'s own code
//! (`cli::interface::run` with `--json`), its JSON read back by Python's
//! `json`, so the waves are the command's, key for key.

use crate::errors;
use pyo3::prelude::*;
use pyo3::types::PyString;
use spar::cli::interface::{run, InterfaceArgs};

/// A vector argument as the flag's `x,y,z` text (numbers written so they
/// read back exactly), or the text itself.
fn vector(name: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(s) = value.downcast::<PyString>() {
        return Ok(s.to_str()?.to_string());
    }
    let v: Vec<f64> = value.extract().map_err(|_| {
        errors::input(format!(
            "{name}: expected three numbers (x, y, z) or the text \"x,y,z\""
        ))
    })?;
    Ok(v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(","))
}

/// Solves one interface: the outgoing waves for one incident wave, as
/// `spar interface --json` prints them (a list of dicts with side, mode,
/// k, ray, evanescent, energy; reflected first, then transmitted).
#[pyfunction]
#[pyo3(signature = (from_, to, *, incident, mode, axis=None, axis_x=None, normal=None, wavelength=589.3))]
#[allow(clippy::too_many_arguments)]
pub fn interface<'py>(
    py: Python<'py>,
    from_: String,
    to: String,
    incident: &Bound<'py, PyAny>,
    mode: String,
    axis: Option<&Bound<'py, PyAny>>,
    axis_x: Option<&Bound<'py, PyAny>>,
    normal: Option<&Bound<'py, PyAny>>,
    wavelength: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let args = InterfaceArgs {
        from: Some(from_),
        to: Some(to),
        describe: None,
        axis: match axis {
            Some(a) => vector("axis", a)?,
            None => "0,0,1".into(),
        },
        // A biaxial side's crystal x (made normal to `axis`); None: the
        // command line's default (+x, or +y when `axis` is within 45° of ±x).
        axis_x: match axis_x {
            Some(a) => Some(vector("axis_x", a)?),
            None => None,
        },
        normal: match normal {
            Some(n) => vector("normal", n)?,
            None => "0,0,1".into(),
        },
        incident: Some(vector("incident", incident)?),
        mode: Some(mode),
        wavelength,
        json: true,
    };
    let mut out = Vec::new();
    run(&args, &mut out).map_err(errors::cli)?;
    let text = String::from_utf8(out).map_err(|e| errors::internal(e.to_string()))?;
    let doc = py.import("json")?.call_method1("loads", (text,))?;
    doc.get_item("waves")
}
