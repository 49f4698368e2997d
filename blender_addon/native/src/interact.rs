//! Input feeding for `core::interact`: an `InputSession` wraps the core
//! per-frame driver (sanitizer, gesture classifiers, active tool) and
//! applies the command it produces to a document `Session`'s log, exactly
//! as `core::interact::replay` does. Controller bindings come from the
//! core's data (`ActionMap::default_map`), never from a copy in Python.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::ScriptCommand;
use shapewright::interact::{
    apply_command, tool_named, ActionMap, Hand, InputFrame, ModelPlacement, PaletteAction, Preview,
    Session as Driver, TRACE_FORMAT, TRACE_VERSION,
};

use crate::doc::Session;
use crate::error::{log_err, ParseError};

/// The per-frame input driver of one tool.
#[pyclass(module = "shapewright._native", unsendable)]
#[repr(transparent)]
pub struct InputSession(Driver);

fn parse_err(what: &str, e: impl std::fmt::Display) -> PyErr {
    ParseError::new_err(format!("{what}: {e}"))
}

/// The model placement a host passes as JSON
/// (`{"translate":[..],"rotate":[x,y,z,w],"scale":s}`).
fn model_of(placement_json: &str) -> PyResult<shapewright::interact::Similarity> {
    let placement: ModelPlacement =
        serde_json::from_str(placement_json).map_err(|e| parse_err("placement", e))?;
    placement
        .similarity()
        .ok_or_else(|| ParseError::new_err("placement must be finite with a positive scale"))
}

#[pymethods]
impl InputSession {
    /// A driver running the tool named `tool` (see `core::interact::tool_named`),
    /// with the model placed in stage space by `placement_json`
    /// (`{"translate":[..],"rotate":[x,y,z,w],"scale":s}`).
    #[new]
    fn new(tool: &str, placement_json: &str) -> PyResult<Self> {
        let model = model_of(placement_json)?;
        let tool = tool_named(tool).map_err(|e| parse_err("tool", e))?;
        Ok(Self(Driver::new(tool, model)))
    }

    /// Feeds one raw frame (a trace line: `InputFrame` as JSON). When the
    /// tool completes a gesture, its command is applied to `doc`; returns
    /// `(command_json, error)`: the command as a script line and, if the
    /// log refused it (nothing changed then), why. `None` when no command
    /// was produced (most frames).
    /// The tool is not `Send`, so the GIL stays held; a frame costs
    /// microseconds unless it completes a gesture.
    fn step(
        &mut self,
        doc: &mut Session,
        frame_json: &str,
    ) -> PyResult<Option<(String, Option<String>)>> {
        let frame: InputFrame =
            serde_json::from_str(frame_json).map_err(|e| parse_err("input frame", e))?;
        let log = doc.log_mut();
        let Some(cmd) = self.0.step(&frame, log.document()) else {
            return Ok(None);
        };
        let refused = apply_command(log, &cmd).err();
        let line = match &cmd {
            ScriptCommand::Op(op) => serde_json::to_string(op).map_err(|e| parse_err("op", e))?,
            ScriptCommand::Undo => "{\"op\":\"undo\"}".to_string(),
            ScriptCommand::Redo => "{\"op\":\"redo\"}".to_string(),
        };
        Ok(Some((line, refused.map(|e| log_err(e).to_string()))))
    }

    /// A modeler driver: every tool, `start` active, the palette on the
    /// left hand (the headset host's session; see `core::interact::palette`).
    #[staticmethod]
    fn modeler(start: &str, placement_json: &str) -> PyResult<Self> {
        let model = model_of(placement_json)?;
        Driver::modeler(start, Hand::Right, model)
            .map(Self)
            .map_err(|e| parse_err("tool", e))
    }

    /// Makes the tool named `tool` active (a modeler driver keeps every
    /// tool's choices; a one-tool driver gets a fresh tool), cancelling
    /// any gesture in progress.
    fn set_tool(&mut self, tool: &str) -> PyResult<()> {
        self.0.select_tool(tool).map_err(|e| parse_err("tool", e))
    }

    /// The active tool's name.
    fn tool(&self) -> &'static str {
        self.0.tool().name()
    }

    /// The palette to draw, when open: `pose` (stage `{"p","q"}`: centre,
    /// +X right, +Y up, +Z toward the head), `size` `[w, h]` (metres),
    /// `items` (`(label, [x0, y0, x1, y1], active, pickable)` in the plane),
    /// `hovered` (item index or None), `pointer` (stage point or None).
    fn palette<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(v) = self.0.palette() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        let pose = serde_json::to_string(&v.pose).map_err(|e| parse_err("pose", e))?;
        d.set_item("pose", pose)?; // JSON text: {"p": [x, y, z], "q": [x, y, z, w]}
        d.set_item("size", v.size)?;
        let items: Vec<(String, [f64; 4], bool, bool)> = v
            .items
            .iter()
            .map(|i| {
                (
                    i.label.clone(),
                    i.rect,
                    i.active,
                    i.action != PaletteAction::None,
                )
            })
            .collect();
        d.set_item("items", items)?;
        d.set_item("hovered", v.hovered)?;
        d.set_item("pointer", v.pointer.map(|p| p.to_array()))?;
        Ok(Some(d))
    }

    /// Saves asked for through the palette since the last call.
    fn take_save_requests(&mut self) -> u32 {
        self.0.take_save_requests()
    }

    /// What to draw now: `rays` (per hand `None` or `(origin, dir, length,
    /// hit)`), `sketch` (model-space points), `highlighted`, `selected`,
    /// `moving` (`(id, motion 4x4 row-major)`).
    fn preview<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        preview_dict(py, self.0.preview())
    }
}

/// A preview ray as Python sees it: origin, direction, length, hit.
type RayTuple = ([f64; 3], [f64; 3], f64, bool);

fn preview_dict<'py>(py: Python<'py>, p: &Preview) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rays: Vec<Option<RayTuple>> = p
        .rays
        .iter()
        .map(|r| r.map(|r| (r.origin.to_array(), r.dir.to_array(), r.length, r.hit)))
        .collect();
    d.set_item("rays", rays)?;
    d.set_item(
        "sketch",
        p.sketch.iter().map(|v| v.to_array()).collect::<Vec<_>>(),
    )?;
    d.set_item("highlighted", p.highlighted.map(|i| i.0))?;
    d.set_item("selected", p.selected.map(|i| i.0))?;
    let moving = p.moving.as_ref().map(|m| {
        let a = m.motion.to_affine();
        let c = shapewright::math::DMat4::from(a)
            .transpose()
            .to_cols_array();
        (m.id.0, c)
    });
    d.set_item("moving", moving)?;
    Ok(d)
}

/// Shapewright's controller bindings (every profile) as JSON, from the
/// core's data.
#[pyfunction]
pub(crate) fn action_map_json() -> String {
    ActionMap::default_map().to_json()
}

/// The names of the core's tools (what `InputSession` takes).
#[pyfunction]
pub(crate) fn tool_names() -> Vec<&'static str> {
    shapewright::interact::TOOL_NAMES.to_vec()
}

/// The trace format name and version this build reads.
#[pyfunction]
pub(crate) fn trace_format() -> (&'static str, u32) {
    (TRACE_FORMAT, TRACE_VERSION)
}
