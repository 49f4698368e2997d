//! The core's op forms (`shapewright::interact::forms`): every form with
//! its fields and defaults, and a form's values built into ops, so the
//! add-on holds no op wire shapes or tool defaults (issue 36).

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;
use shapewright::interact::forms::{build, forms, FormError};

use crate::convert::{into_py, to_value};
use crate::doc::Session;
use crate::error::{OpRejected, ParseError};

/// Every form, in menu order: `[{"op", "fields": [{"name", "kind",
/// "default", "items", "label", "doc", "like", "unit", "none_at",
/// "units"}], "build", "sketch", "target_kind", "needs_points"}]`.
#[pyfunction]
pub(crate) fn op_forms(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    into_py(py, &forms())
}

/// The ops form `op` makes of `values` (field name -> value: metres,
/// quaternions, sketches as point lists), as op dicts applied as one
/// step. `doc` is needed for a sketch on an existing object.
#[pyfunction]
#[pyo3(signature = (op, values, doc=None))]
pub(crate) fn build_form<'py>(
    py: Python<'py>,
    op: &str,
    values: &Bound<'py, PyDict>,
    doc: Option<PyRef<'py, Session>>,
) -> PyResult<Bound<'py, PyList>> {
    let Value::Object(map) = to_value(values.as_any())? else {
        return Err(ParseError::new_err("a form's values are a dict"));
    };
    let document = doc.as_ref().map(|s| s.log().document());
    let ops = py
        .detach(|| build(op, &map, document))
        .map_err(|e| match e {
            FormError::Sketch { .. } | FormError::Refused { .. } => {
                OpRejected::new_err(e.to_string())
            }
            _ => ParseError::new_err(e.to_string()),
        })?;
    let out = PyList::empty(py);
    for o in &ops {
        out.append(into_py(py, o)?)?;
    }
    Ok(out)
}
