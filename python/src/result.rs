//! `linkdyn.Result`: a finished run as read-only NumPy arrays, its events and its summary.

use crate::errors;
use linkdyn::formulation::Crossing;
use linkdyn::output::{
    CsvSink, ResultPair, check_mat, check_npz_size, impacts_csv, impacts_path, write_mat, write_npz,
};
use linkdyn::simulation::{Columns, RunSummary, Sample, SampleSink, Trajectory};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyImportError, PyKeyError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A finished run: sample times `t`, one float64 array per output column, the located
/// events and the run summary (what `linkdyn run` writes as CSV and JSON).
#[pyclass(name = "Result", module = "linkdyn", frozen)]
pub struct PyResult_ {
    names: Vec<String>,
    t: Py<PyArray1<f64>>,
    columns: Vec<Py<PyArray1<f64>>>,
    constraint_violation: Py<PyArray1<f64>>,
    events: Vec<(f64, usize, Option<String>, &'static str, bool)>,
    summary: RunSummary,
    samples: usize,
}

/// A read-only NumPy array that owns `v` (no copy: NumPy points at the Rust allocation).
fn frozen_array(py: Python<'_>, v: Vec<f64>) -> PyResult<Py<PyArray1<f64>>> {
    let a = PyArray1::from_vec(py, v);
    // Read-only: every access returns the same array, so no caller may change another's data.
    a.getattr("flags")?.setattr("writeable", false)?;
    Ok(a.unbind())
}

impl PyResult_ {
    /// Takes the trajectory's vectors over as NumPy arrays; `clearance` names the clearance
    /// joints in model order (event k belongs to joint k).
    pub fn new(py: Python<'_>, run: Trajectory, clearance: Vec<String>) -> PyResult<Self> {
        // The contact events only: event k < n_c is clearance joint k's δ; the others (the
        // friction kinks, the generalised formulation's repartition) are where the method ended
        // its steps, not impacts or separations.
        let events = run
            .events
            .iter()
            .filter(|e| e.index < clearance.len())
            .map(|e| {
                let kind = match e.crossing {
                    Crossing::Rising => "impact",
                    Crossing::Falling => "separation",
                };
                (
                    e.t,
                    e.index,
                    clearance.get(e.index).cloned(),
                    kind,
                    e.restarted,
                )
            })
            .collect();
        let columns = run
            .columns
            .into_iter()
            .map(|c| frozen_array(py, c))
            .collect::<PyResult<_>>()?;
        Ok(PyResult_ {
            samples: run.t.len(),
            names: run.names,
            t: frozen_array(py, run.t)?,
            columns,
            constraint_violation: frozen_array(py, run.constraint_violation)?,
            events,
            summary: run.summary,
        })
    }

    fn lookup(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        if name == "t" {
            return Ok(self.t.clone_ref(py));
        }
        match self.names.iter().position(|n| n == name) {
            Some(k) => self
                .columns
                .get(k)
                .map(|c| c.clone_ref(py))
                .ok_or_else(|| PyKeyError::new_err(name.to_string())),
            None => {
                let close: Vec<&str> = self
                    .names
                    .iter()
                    .filter(|n| {
                        let stem = name.split('.').next().unwrap_or(name);
                        n.starts_with(stem) || n.ends_with(name.rsplit('.').next().unwrap_or(name))
                    })
                    .map(String::as_str)
                    .take(8)
                    .collect();
                let hint = if close.is_empty() {
                    format!("{} columns, see Result.names", self.names.len() + 1)
                } else {
                    format!("similar: {}", close.join(", "))
                };
                Err(PyKeyError::new_err(format!(
                    "no column \"{name}\" ({hint})"
                )))
            }
        }
    }
}

#[pymethods]
impl PyResult_ {
    /// Sample times (s), float64, read-only.
    #[getter]
    fn t(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.t.clone_ref(py)
    }

    /// Output column names in CSV order, without `t`.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.names.clone()
    }

    /// Constraint violation max |Φ| at each sample (m or rad; 0 for the reduced formulation).
    #[getter]
    fn constraint_violation(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.constraint_violation.clone_ref(py)
    }

    /// A column by name (`"t"` included), float64, read-only; `KeyError` if there is none.
    fn column(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        self.lookup(py, name)
    }

    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyArray1<f64>>> {
        self.lookup(py, name)
    }

    fn __contains__(&self, name: &str) -> bool {
        name == "t" || self.names.iter().any(|n| n == name)
    }

    /// Number of samples.
    fn __len__(&self) -> usize {
        self.samples
    }

    /// The run summary as a dict (the JSON file of `linkdyn run`: provenance, solver options
    /// and statistics, constraint violation, per clearance joint impacts and maxima, energy
    /// balance). A new dict on every access.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.summary).map_err(|e| {
            pyo3::exceptions::PyRuntimeError::new_err(format!("cannot convert the summary: {e}"))
        })?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// The located contact events in time order: one dict each with `t` (s), `index`, `joint`
    /// (the clearance joint), `kind` (`"impact"`: δ rising through 0, `"separation"`) and
    /// `restarted`. Events where the method only ended its steps (the friction law's kinks,
    /// the generalised formulation's repartition) are not listed.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (t, index, joint, kind, restarted) in &self.events {
            let d = PyDict::new(py);
            d.set_item("t", t)?;
            d.set_item("index", index)?;
            d.set_item("joint", joint)?;
            d.set_item("kind", kind)?;
            d.set_item("restarted", restarted)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The columns (`t` first) as a `pandas.DataFrame`; `ImportError` without pandas.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|e| {
            PyImportError::new_err(format!(
                "Result.to_pandas() needs pandas, which cannot be imported ({e}); install it with `pip install pandas`, or use Result.t and Result[name] (NumPy arrays)"
            ))
        })?;
        let data = PyDict::new(py);
        data.set_item("t", self.t.bind(py).to_owned())?;
        for (n, c) in self.names.iter().zip(&self.columns) {
            data.set_item(n, c.bind(py).to_owned())?;
        }
        pandas.call_method1("DataFrame", (data,))
    }

    /// Writes the result files of `linkdyn run --out PATH --format FORMAT` (`"csv"`, `"npz"` or
    /// `"mat"`): the data file, the JSON summary beside it (`PATH` with the extension `.json`)
    /// and the impact log, all appearing whole or not at all, the earlier pair untouched on failure. The CSV is byte for byte the
    /// command line's for the same model and settings. Raises `OutputError`.
    #[pyo3(signature = (path, format = "csv"))]
    fn save(&self, py: Python<'_>, path: std::path::PathBuf, format: &str) -> PyResult<()> {
        let to_py = |e: linkdyn::output::OutputError| errors::to_py(py, e.into(), None);
        // The CSV is streamed row by row; the NPZ and the MAT-file take the columns whole.
        let format = match format {
            "csv" | "npz" | "mat" => format,
            other => {
                return Err(errors::to_py(
                    py,
                    linkdyn::Error::settings(
                        "format",
                        format!("expected \"csv\", \"npz\" or \"mat\", got \"{other}\""),
                    ),
                    None,
                ));
            }
        };
        // Copies of the columns (the arrays stay with Python); then no GIL while writing.
        let data = Columns {
            t: self.t.bind(py).to_vec().map_err(PyErr::from)?,
            columns: self
                .columns
                .iter()
                .map(|c| c.bind(py).to_vec())
                .collect::<Result<_, _>>()
                .map_err(PyErr::from)?,
            constraint_violation: self
                .constraint_violation
                .bind(py)
                .to_vec()
                .map_err(PyErr::from)?,
            events: Vec::new(),
        };
        let names = &self.names;
        let summary = &self.summary;
        py.detach(|| -> Result<(), linkdyn::Error> {
            let provenance = &summary.provenance;
            match format {
                "npz" => check_npz_size(&path, data.t.len(), names)?,
                "mat" => check_mat(&path, data.t.len(), names)?,
                _ => {}
            }
            // The model file itself is never a target (as on the command line).
            let model = std::path::Path::new(&provenance.model.path);
            // The same files as `linkdyn run`: data, summary and impact log, all or none.
            let mut pair = ResultPair::begin_with(&path, Some(model), &[impacts_path(&path)])?;
            if format == "npz" {
                write_npz(pair.csv().writer(), &path, provenance, names, &data)?;
            } else if format == "mat" {
                write_mat(pair.csv().writer(), &path, provenance, names, &data)?;
            } else {
                let label = path.display().to_string();
                let mut csv = CsvSink::new(pair.csv().writer(), label, provenance, names)?;
                let mut row = vec![0.0; names.len()];
                for (k, (&t, &cv)) in data.t.iter().zip(&data.constraint_violation).enumerate() {
                    for (r, c) in row.iter_mut().zip(&data.columns) {
                        *r = c.get(k).copied().unwrap_or(f64::NAN);
                    }
                    csv.sample(&Sample {
                        t,
                        state: &[],
                        outputs: &row,
                        constraint_violation: cv,
                    })?;
                }
            }
            pair.commit_with_files(summary, &[impacts_csv(provenance, summary)])?;
            Ok(())
        })
        .map_err(|e| match e {
            linkdyn::Error::Output(o) => to_py(o),
            other => errors::to_py(py, other, None),
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<linkdyn.Result: {} samples × {} columns, {} events>",
            self.samples,
            self.names.len() + 1,
            self.events.len()
        )
    }
}
