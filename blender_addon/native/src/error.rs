//! Core errors as Python exceptions. Every exception is a
//! `ShapewrightError` (a `ValueError`), with subclasses by source.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    shapewright,
    ShapewrightError,
    PyValueError,
    "An operation was refused; the document is unchanged."
);
create_exception!(
    shapewright,
    OpRejected,
    ShapewrightError,
    "An op's parameters or target were invalid."
);
create_exception!(
    shapewright,
    HistoryError,
    ShapewrightError,
    "Undo, redo or seek could not be done."
);
create_exception!(
    shapewright,
    ParseError,
    ShapewrightError,
    "A JSON op or script could not be parsed."
);

create_exception!(
    shapewright,
    SessionError,
    ShapewrightError,
    "A shared session could not be joined (unreachable, not allowed, ...)."
);

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ShapewrightError", py.get_type::<ShapewrightError>())?;
    m.add("OpRejected", py.get_type::<OpRejected>())?;
    m.add("HistoryError", py.get_type::<HistoryError>())?;
    m.add("ParseError", py.get_type::<ParseError>())?;
    m.add("SessionError", py.get_type::<SessionError>())?;
    Ok(())
}

/// Converts a log error.
pub(crate) fn log_err(e: shapewright::doc::LogError) -> PyErr {
    use shapewright::doc::LogError;
    match e {
        LogError::Op(op) => OpRejected::new_err(op.to_string()),
        other => HistoryError::new_err(other.to_string()),
    }
}

/// Converts a script error.
pub(crate) fn script_err(e: shapewright::doc::ScriptError) -> PyErr {
    use shapewright::doc::ScriptErrorKind;
    match &e.kind {
        ScriptErrorKind::Log(_) => OpRejected::new_err(e.to_string()),
        _ => ParseError::new_err(e.to_string()),
    }
}

/// Converts an op error.
pub(crate) fn op_err(e: shapewright::doc::OpError) -> PyErr {
    OpRejected::new_err(e.to_string())
}
