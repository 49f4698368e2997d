//! Python values to and from the core's serde values, by hand (no
//! `pythonize` release follows pyo3 0.30 yet): a dict, list or number from
//! Python becomes a `serde_json::Value` that serde turns into a typed core
//! value (an `Op`, an input frame, a presence message), and back. No JSON
//! text crosses the border.
//!
//! Numbers are checked on the way in, naming the field (`shape.radius`,
//! `samples[3].position[1]`): NaN and infinity are refused, and so is a
//! float32 overflow (Blender stores float properties as float32, and
//! `inf` typed into a field arrives as 3.4e38), so a host needs no
//! finiteness checks of its own. Sequences that are not lists (tuples,
//! Blender's vectors and property arrays, numpy arrays) read as lists.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};
use serde_json::{Map, Number, Value};

use crate::error::ParseError;

/// Anything this large is a float32 overflow of `inf`, not a size.
pub(crate) const FLOAT32_OVERFLOW: f64 = 3.0e38;

/// Nesting deeper than this is refused (a cycle or a hostile value).
const MAX_DEPTH: usize = 64;

fn name(path: &str) -> &str {
    if path.is_empty() {
        "value"
    } else {
        path
    }
}

fn number(x: f64, path: &str) -> PyResult<Value> {
    if x.is_nan() {
        return Err(ParseError::new_err(format!(
            "{}: NaN is not a number; give a finite value",
            name(path)
        )));
    }
    if !x.is_finite() || x.abs() >= FLOAT32_OVERFLOW {
        return Err(ParseError::new_err(format!(
            "{}: {x} is not finite; give a finite value",
            name(path)
        )));
    }
    Number::from_f64(x)
        .map(Value::Number)
        .ok_or_else(|| ParseError::new_err(format!("{}: {x} is not a number", name(path))))
}

/// Refuses a non-finite number (or a float32 overflow of `inf`) in a
/// host's typed argument, naming it (`dimensions[0]`).
pub(crate) fn check_finite(name_: &str, values: &[f64]) -> PyResult<()> {
    for (k, x) in values.iter().enumerate() {
        number(*x, &format!("{name_}[{k}]"))?;
    }
    Ok(())
}

/// A Python value as a serde value, numbers checked (see the module doc).
pub(crate) fn to_value(obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    walk(obj, &mut String::new(), 0, false)
}

/// Numbers as the trace format reads them: finite, or `"NaN"`, `"inf"`,
/// `"-inf"` (lost tracking is a fact a frame records, not an error).
fn lenient(x: f64) -> Value {
    if x.is_nan() {
        Value::from("NaN")
    } else if x.is_infinite() {
        Value::from(if x > 0.0 { "inf" } else { "-inf" })
    } else {
        Number::from_f64(x).map_or(Value::Null, Value::Number)
    }
}

fn walk(obj: &Bound<'_, PyAny>, path: &mut String, depth: usize, loose: bool) -> PyResult<Value> {
    if depth > MAX_DEPTH {
        return Err(ParseError::new_err(format!(
            "{}: nested more than {MAX_DEPTH} levels deep",
            name(path)
        )));
    }
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if let Ok(i) = obj.cast::<PyInt>() {
        if let Ok(v) = i.extract::<i64>() {
            return Ok(Value::from(v));
        }
        if let Ok(v) = i.extract::<u64>() {
            return Ok(Value::from(v));
        }
        return Err(ParseError::new_err(format!(
            "{}: the integer {i} is too large",
            name(path)
        )));
    }
    if let Ok(f) = obj.cast::<PyFloat>() {
        return if loose {
            Ok(lenient(f.value()))
        } else {
            number(f.value(), path)
        };
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                ParseError::new_err(format!("{}: keys must be strings, got {k}", name(path)))
            })?;
            let len = path.len();
            if !path.is_empty() {
                path.push('.');
            }
            path.push_str(&key);
            let value = walk(&v, path, depth + 1, loose)?;
            path.truncate(len);
            map.insert(key, value);
        }
        return Ok(Value::Object(map));
    }
    if obj.hasattr("__len__")? && obj.hasattr("__getitem__")? && !obj.hasattr("keys")? {
        let n = obj.len()?;
        let mut items = Vec::with_capacity(n);
        for (k, item) in obj.try_iter()?.enumerate() {
            let len = path.len();
            path.push_str(&format!("[{k}]"));
            items.push(walk(&item?, path, depth + 1, loose)?);
            path.truncate(len);
        }
        return Ok(Value::Array(items));
    }
    // numpy and other number types that are not Python floats.
    if let Ok(x) = obj.extract::<f64>() {
        return if loose {
            Ok(lenient(x))
        } else {
            number(x, path)
        };
    }
    Err(PyTypeError::new_err(format!(
        "{}: a {} is not a value an op holds (numbers, strings, lists, dicts)",
        name(path),
        obj.get_type().name()?
    )))
}

/// A Python value as a typed core value `T` (the serde error naming
/// what was wrong), non-finite numbers kept (see [`lenient`]).
pub(crate) fn from_py_lenient<T: serde::de::DeserializeOwned>(
    obj: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<T> {
    let value = walk(obj, &mut String::new(), 0, true)?;
    serde_json::from_value(value).map_err(|e| ParseError::new_err(format!("{what}: {e}")))
}

/// A serde value as a Python value (dicts keep their keys' order).
pub(crate) fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let d = PyDict::new(py);
            for (k, item) in map {
                d.set_item(k, to_py(py, item)?)?;
            }
            d.into_any()
        }
    })
}

/// A typed core value as a Python value.
pub(crate) fn into_py<'py, T: serde::Serialize>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let v = serde_json::to_value(value).map_err(|e| ParseError::new_err(e.to_string()))?;
    to_py(py, &v)
}
