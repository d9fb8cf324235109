//! spar's errors as Python exceptions. Every message is spar's own,
//! unchanged (a scene's `FILE:LINE: field: why`, a setting's
//! `max_depth must be at most 1000`); the class says whose fault it is:
//!
//! - `SparError(Exception)`: anything spar reports;
//! - `InputError(SparError, ValueError)`: bad input (the command line's
//!   exit status 2), a `ValueError` so that Python code catching bad
//!   values catches it;
//! - `SceneError(InputError)`: a scene that cannot be read, with `file`,
//!   `line`, `field` and `reason` as attributes.

use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;
use pyo3::types::{PyDict, PyTuple, PyType};
use spar::cli::error::{CliError, ErrorKind};
use spar::scene::SceneError as SparSceneError;

static SPAR_ERROR: GILOnceCell<Py<PyType>> = GILOnceCell::new();
static INPUT_ERROR: GILOnceCell<Py<PyType>> = GILOnceCell::new();
static SCENE_ERROR: GILOnceCell<Py<PyType>> = GILOnceCell::new();

/// A new exception class `spar.NAME` with `bases` and `doc`, made as
/// Python's `class` statement makes one (several bases are allowed).
fn class<'py>(
    py: Python<'py>,
    name: &str,
    bases: &[Bound<'py, PyType>],
    doc: &str,
) -> PyResult<Bound<'py, PyType>> {
    let namespace = PyDict::new(py);
    namespace.set_item("__module__", "spar")?;
    namespace.set_item("__doc__", doc)?;
    let bases = PyTuple::new(py, bases)?;
    let ty = py
        .import("builtins")?
        .getattr("type")?
        .call1((name, bases, namespace))?;
    Ok(ty.downcast_into::<PyType>()?)
}

/// Makes the three classes and adds them to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let spar_error = class(
        py,
        "SparError",
        &[py.get_type::<PyException>()],
        "Any error spar reports; the message is the one the command line prints.",
    )?;
    let input_error = class(
        py,
        "InputError",
        &[spar_error.clone(), py.get_type::<PyValueError>()],
        "Bad input: a setting, a mode, a medium, a cut parameter (the command line's exit \
         status 2). Also a ValueError.",
    )?;
    let scene_error = class(
        py,
        "SceneError",
        std::slice::from_ref(&input_error),
        "A scene that cannot be read. `file`, `line` (None where the file has no place for the \
         value), `field` (empty when the whole file is at fault) and `reason` say where and why; \
         str(error) is spar's `FILE:LINE: field: reason`.",
    )?;
    m.add("SparError", &spar_error)?;
    m.add("InputError", &input_error)?;
    m.add("SceneError", &scene_error)?;
    let _ = SPAR_ERROR.set(py, spar_error.unbind());
    let _ = INPUT_ERROR.set(py, input_error.unbind());
    let _ = SCENE_ERROR.set(py, scene_error.unbind());
    Ok(())
}

/// An exception of the class in `cell` (registered at import) saying
/// `message`.
fn raise(cell: &GILOnceCell<Py<PyType>>, message: String) -> PyErr {
    Python::with_gil(|py| match cell.get(py) {
        Some(ty) => PyErr::from_type(ty.bind(py).clone(), message),
        None => PyException::new_err(message),
    })
}

/// A command-line error as the exception of its kind.
pub fn cli(e: CliError) -> PyErr {
    match e.kind() {
        ErrorKind::Input => raise(&INPUT_ERROR, e.to_string()),
        ErrorKind::Output | ErrorKind::Internal => raise(&SPAR_ERROR, e.to_string()),
    }
}

/// Bad input, said in spar's words.
pub fn input(message: impl Into<String>) -> PyErr {
    raise(&INPUT_ERROR, message.into())
}

/// A failure that is not the caller's.
pub fn internal(message: impl Into<String>) -> PyErr {
    raise(&SPAR_ERROR, message.into())
}

/// A scene error as `SceneError`, its place as attributes.
pub fn scene(py: Python<'_>, e: &SparSceneError) -> PyErr {
    let err = raise(&SCENE_ERROR, e.to_string());
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("file", &e.file)?;
        value.setattr("line", e.line)?;
        value.setattr("field", &e.field)?;
        value.setattr("reason", &e.message)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}
