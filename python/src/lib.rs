//! `linkdyn._linkdyn`: the compiled core of the `linkdyn` Python package.
//!
//! Thin bindings over [`linkdyn::simulation`]: [`load`] reads a model (with `--set`-style
//! overrides) into a [`model::PyModel`], whose `run` integrates it with the GIL released and
//! returns a [`result::PyResult_`] of NumPy arrays; its analyses ([`analyses`], [`sweep`])
//! return the records of `linkdyn._analyses`. Errors become the exception classes of
//! `linkdyn._errors` with the command line's messages ([`errors`]). The Python-facing API,
//! its defaults and its documentation live in `linkdyn/__init__.py` and `linkdyn/_linkdyn.pyi`.

mod analyses;
mod document;
mod errors;
mod model;
mod orbit;
mod result;
mod settings;
mod sweep;
mod wear;

use pyo3::prelude::*;

/// Reads and validates a model file, applying `overrides` (`"KEY=VALUE"` strings, as the
/// command line's `--set`) in order.
#[pyfunction]
#[pyo3(signature = (path, overrides = Vec::new()))]
fn load(py: Python<'_>, path: String, overrides: Vec<String>) -> PyResult<model::PyModel> {
    let loaded = py.detach(|| linkdyn::model::load(path.as_ref(), &overrides));
    match loaded {
        Ok(m) => Ok(model::PyModel::new(m, path)),
        Err(e) => Err(errors::to_py(py, linkdyn::Error::from(e), None)),
    }
}

/// Reads and validates a model from TOML text, as `load` reads a file; `name` stands for the
/// file in messages and provenance.
#[pyfunction]
#[pyo3(signature = (text, overrides = Vec::new(), name = String::from("<string>")))]
fn loads(
    py: Python<'_>,
    text: String,
    overrides: Vec<String>,
    name: String,
) -> PyResult<model::PyModel> {
    let loaded = py.detach(|| linkdyn::model::load_str(&text, &name, &overrides));
    match loaded {
        Ok(m) => Ok(model::PyModel::from_text(m, name, text)),
        Err(e) => Err(errors::to_py(py, linkdyn::Error::from(e), None)),
    }
}

/// The model document `document` (a dict of the model file's tables) as TOML text; raises
/// `TypeError` naming a value TOML cannot hold.
#[pyfunction]
fn dict_to_toml(document: &Bound<'_, PyAny>) -> PyResult<String> {
    document::toml_text(document)
}

/// linkdyn version and git commit of the compiled core.
#[pyfunction]
fn version() -> String {
    linkdyn::version()
}

/// The extension module.
#[pymodule]
fn _linkdyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(loads, m)?)?;
    m.add_function(wrap_pyfunction!(dict_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<result::PyResult_>()?;
    Ok(())
}
