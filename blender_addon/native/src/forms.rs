//! The core's op forms (`shapewright::interact::forms`): every form with
//! its fields and defaults, and a form's values built into ops, so the
//! add-on holds no op wire shapes or tool defaults (issue 36). The built
//! ops stay in Rust ([`Built`]) until `Session.apply` takes them: an op
//! crosses the border once, as the form's values.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;
use shapewright::doc::Op;
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

/// The ops a form built, applied as one step by `Session.apply` (or, with
/// others, `Session.apply_all`); Python reads them only through
/// [`Built::dicts`].
#[pyclass(frozen, module = "shapewright._native")]
pub(crate) struct Built {
    pub(crate) ops: Vec<Op>,
}

#[pymethods]
impl Built {
    /// How many ops (most forms build one).
    fn __len__(&self) -> usize {
        self.ops.len()
    }

    fn __repr__(&self) -> String {
        let names: Vec<&str> = self.ops.iter().map(Op::name).collect();
        format!("Built([{}])", names.join(", "))
    }

    /// The ops as dicts, as a script line has them.
    fn dicts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for o in &self.ops {
            out.append(into_py(py, o)?)?;
        }
        Ok(out)
    }
}

/// The ops form `op` makes of `values` (field name -> value: metres,
/// quaternions, sketches as point lists), applied as one step. `doc` is
/// needed for a sketch on an existing object.
#[pyfunction]
#[pyo3(signature = (op, values, doc=None))]
pub(crate) fn build_form<'py>(
    py: Python<'py>,
    op: &str,
    values: &Bound<'py, PyDict>,
    doc: Option<PyRef<'py, Session>>,
) -> PyResult<Built> {
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
    Ok(Built { ops })
}
