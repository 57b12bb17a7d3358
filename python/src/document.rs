//! Model documents between Python and TOML: a dict of the model file's tables (as
//! `tomllib.loads` gives it) → TOML text for `linkdyn.from_dict`, and a model's TOML text →
//! such a dict for `Model.to_dict`.
//!
//! The conversion is exact both ways: a Python float is an f64 and TOML's text of an f64 is its
//! shortest round-trip form, so a value read back is the value given, bit for bit.

use pyo3::exceptions::{PyOverflowError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};
use toml::{Table, Value};

/// Most levels of nesting accepted (a model file's deepest value is about five levels down):
/// a self-referencing list would otherwise recurse until the stack overflows.
const MAX_DEPTH: usize = 32;

/// The model document `obj` (a mapping from table names to tables and arrays of tables) as
/// TOML text. Keys whose value is `None` are left out, as an optional field that is not
/// written. Raises `TypeError` naming the dotted path of a value TOML cannot hold.
pub fn toml_text(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    let table = match value(obj, "", 0)? {
        Some(Value::Table(t)) => t,
        _ => {
            return Err(PyTypeError::new_err(format!(
                "from_dict: expected a dict of the model file's tables (\"model\", \"bodies\", …), got {}",
                type_name(obj)
            )));
        }
    };
    linkdyn::model::document_text(&table)
        .map_err(|e| PyTypeError::new_err(format!("from_dict: {e}")))
}

/// The TOML value of `obj` at `path`; `None` for Python's `None` (the key is left out).
fn value(obj: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<Option<Value>> {
    let at = if path.is_empty() {
        "the document"
    } else {
        path
    };
    if depth > MAX_DEPTH {
        return Err(PyTypeError::new_err(format!(
            "{at}: nested more than {MAX_DEPTH} levels deep; expected a model file's tables"
        )));
    }
    if obj.is_none() {
        return Ok(None);
    }
    // bool before int: Python's bool is an int.
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Some(Value::Boolean(b.is_true())));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj.extract().map_err(|_| {
            PyOverflowError::new_err(format!(
                "{at}: the integer {obj} does not fit TOML's 64-bit integers"
            ))
        })?;
        return Ok(Some(Value::Integer(i)));
    }
    if let Ok(f) = obj.cast::<PyFloat>() {
        return Ok(Some(Value::Float(f.value())));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Some(Value::String(s.extract::<String>()?)));
    }
    if let Ok(m) = obj.cast::<PyMapping>() {
        let mut table = Table::new();
        for item in m.items()?.iter() {
            let (k, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
            let Ok(key) = k.extract::<String>() else {
                return Err(PyTypeError::new_err(format!(
                    "{at}: the key {k} is a {}; expected a string (a field or table name)",
                    type_name(&k)
                )));
            };
            let inner = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            if let Some(v) = value(&v, &inner, depth + 1)? {
                table.insert(key, v);
            }
        }
        return Ok(Some(Value::Table(table)));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut array = Vec::new();
        for (k, item) in obj.try_iter()?.enumerate() {
            let item = item?;
            match value(&item, &format!("{path}[{k}]"), depth + 1)? {
                Some(v) => array.push(v),
                None => {
                    return Err(PyTypeError::new_err(format!(
                        "{path}[{k}]: None in a list; TOML arrays hold values only"
                    )));
                }
            }
        }
        return Ok(Some(Value::Array(array)));
    }
    // NumPy scalars and arrays: their Python value (`item`) or list (`tolist`).
    for method in ["tolist", "item"] {
        if obj.hasattr(method)? {
            return value(&obj.call_method0(method)?, path, depth + 1);
        }
    }
    Err(PyTypeError::new_err(format!(
        "{at}: cannot write a {} as a model value (expected a number, bool, string, list or dict)",
        type_name(obj)
    )))
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "value".into())
}

/// A TOML table as a Python dict (tables → dict, arrays → list, dates → their TOML text).
pub fn to_py<'py>(py: Python<'py>, table: &Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in table {
        d.set_item(k, value_to_py(py, v)?)?;
    }
    Ok(d)
}

fn value_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(f) => f.into_pyobject(py)?.into_any(),
        Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for item in a {
                list.append(value_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Table(t) => to_py(py, t)?.into_any(),
    })
}
