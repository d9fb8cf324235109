//! `spar.cut`: a standard cut or a GemCAD design's stone as arrays, built
//! by the code behind `spar cut` (`geometry::cuts`, `geometry::asc`) and
//! checked as it checks it (`geometry::validate`).

use crate::errors;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyList};
use spar::geometry::asc::load_asc;
use spar::geometry::cuts::{cut_from_spec, Cut, CUT_NAMES};
use spar::geometry::validate::validate;
use spar::geometry::Mesh;
use std::path::Path;

/// A keyword parameter as the TOML value a scene's `cut = { … }` takes.
fn toml_value(name: &str, value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyInt>() && !value.is_instance_of::<pyo3::types::PyBool>() {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    Err(errors::input(format!("{name}: expected a number")))
}

/// The stone of a cut by name with `params`, or of a GemCAD `.asc` file.
fn stone(cut: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<(Mesh, Vec<String>)> {
    if cut.to_ascii_lowercase().ends_with(".asc") {
        if let Some((k, _)) = params.and_then(|p| p.iter().next()) {
            return Err(errors::input(format!(
                "`{k}` does not apply to a GemCAD design: its facets are given"
            )));
        }
        let design = load_asc(Path::new(cut)).map_err(|e| errors::input(e.to_string()))?;
        let stone = design.stone().map_err(|e| errors::input(e.to_string()))?;
        return Ok((stone.mesh, stone.notes));
    }
    if Cut::by_name(cut).is_none() {
        return Err(errors::input(format!(
            "unknown cut `{cut}`: expected one of {} or a GemCAD .asc file",
            CUT_NAMES.join(", ")
        )));
    }
    let mut table = toml::Table::new();
    table.insert("name".into(), toml::Value::String(cut.into()));
    if let Some(p) = params {
        for (k, v) in p.iter() {
            let k: String = k.extract()?;
            let v = toml_value(&k, &v)?;
            table.insert(k, v);
        }
    }
    let c = cut_from_spec(&toml::Value::Table(table)).map_err(errors::input)?;
    let stone = c.stone().map_err(errors::input)?;
    Ok((stone.mesh, stone.notes))
}

/// A cut's stone as arrays. `cut` is round-brilliant, oval, princess,
/// emerald (parameters as keywords: table=0.56, crown_angle=33, …, the
/// names of a scene's `cut = { … }` table) or a GemCAD `.asc` file.
///
/// Returns a dict: `vertices` (N×3 float64), `faces` (the facets: a list
/// of int arrays of vertex indices, counter-clockwise seen from outside),
/// `facet_names` (each facet's name, None where it has none), `triangles` (M×3 uint32, the
/// renderer's), `triangle_facet` (M uint32: each triangle's facet),
/// `summary` (the validation summary `spar cut` prints) and `notes`
/// (its warnings).
#[pyfunction]
#[pyo3(signature = (cut, **params))]
pub fn cut<'py>(
    py: Python<'py>,
    cut: &str,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (mesh, mut notes) = stone(cut, params)?;
    let report = validate(&mesh);
    if let Some(t) = &report.topology {
        return Err(errors::internal(format!(
            "{cut}: the stone is not closed: {t}"
        )));
    }
    notes.extend(report.warnings());
    let out = PyDict::new(py);
    let vertices: Vec<f64> = mesh.positions.iter().flat_map(|p| p.to_array()).collect();
    out.set_item(
        "vertices",
        PyArray1::from_vec(py, vertices).reshape([mesh.positions.len(), 3])?,
    )?;
    let faces = PyList::empty(py);
    for f in &mesh.facets {
        faces.append(PyArray1::from_vec(py, f.vertices.clone()))?;
    }
    out.set_item("faces", faces)?;
    let names: Vec<Option<String>> = mesh.facets.iter().map(|f| f.name.clone()).collect();
    out.set_item("facet_names", names)?;
    let triangles: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    out.set_item(
        "triangles",
        PyArray1::from_vec(py, triangles).reshape([mesh.triangles.len(), 3])?,
    )?;
    out.set_item(
        "triangle_facet",
        PyArray1::from_vec(py, mesh.triangle_facet.clone()),
    )?;
    out.set_item("summary", report.summary())?;
    out.set_item("notes", notes)?;
    Ok(out)
}
