//! Input feeding for `core::interact`: an `InputSession` wraps the core
//! per-frame driver (sanitizer, gesture classifiers, active tool) and
//! applies the command it produces to a document `Session`'s log, exactly
//! as `core::interact::replay` does. Controller bindings come from the
//! core's data (`ActionMap::default_map`), never from a copy in Python.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::ScriptCommand;
use shapewright::interact::{
    tool_named, ActionMap, Hand, PaletteAction, PaletteDraw as CoreDraw, PaletteLabel as CoreLabel,
    PaletteView as CorePalette, Preview, Session as Driver, Similarity, TRACE_FORMAT,
    TRACE_VERSION,
};
use shapewright::math::DQuat;

use crate::convert::into_py;
use crate::doc::Session;
use crate::error::{log_err, ParseError};
use crate::input::InputFrame;
use crate::placement::{Placement, Pose};
use crate::shared::Presence;

/// The per-frame input driver of one tool.
#[pyclass(module = "shapewright._native", unsendable)]
#[repr(transparent)]
pub struct InputSession(Driver);

fn parse_err(what: &str, e: impl std::fmt::Display) -> PyErr {
    ParseError::new_err(format!("{what}: {e}"))
}

/// The model's placement in stage space: a similarity (one scale for
/// every axis, positive).
fn model_of(p: &Placement) -> PyResult<Similarity> {
    let t = p.0;
    let s = t.scale[0];
    if !(s > 0.0 && t.scale.iter().all(|x| *x == s)) {
        return Err(ParseError::new_err(format!(
            "the model's placement must scale every axis alike and positively, got {:?}",
            t.scale
        )));
    }
    Ok(Similarity {
        translate: t.translate.into(),
        rotate: DQuat::from_array(t.rotate).normalize(),
        scale: s,
    })
}

#[pymethods]
impl InputSession {
    /// A driver running the tool named `tool` (see `core::interact::tool_named`),
    /// with the model placed in stage space by `placement` (uniform scale).
    #[new]
    fn new(tool: &str, placement: &Placement) -> PyResult<Self> {
        let model = model_of(placement)?;
        let tool = tool_named(tool).map_err(|e| parse_err("tool", e))?;
        Ok(Self(Driver::new(tool, model)))
    }

    /// Feeds one frame. When the tool completes a gesture, its command is
    /// applied to `doc`; returns `(command, error)`: the command as a dict
    /// (an op, or `{"op": "undo"}` / `{"op": "redo"}`) and, if the log
    /// refused it (nothing changed then), why. `None` when no command was
    /// produced (most frames). The tool is not `Send`, so the GIL stays
    /// held; a frame costs microseconds unless it completes a gesture.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        doc: &mut Session,
        frame: &InputFrame,
    ) -> PyResult<Option<(Bound<'py, PyAny>, Option<String>)>> {
        let Some(cmd) = self.0.step(&frame.0, doc.log.document()) else {
            return Ok(None);
        };
        let at = doc.log.cursor();
        let refused = doc.log.apply_command(&cmd).err();
        doc.changed(at);
        let out = match &cmd {
            ScriptCommand::Op(op) => into_py(py, op)?,
            ScriptCommand::Undo => into_py(py, &serde_json::json!({"op": "undo"}))?,
            ScriptCommand::Redo => into_py(py, &serde_json::json!({"op": "redo"}))?,
        };
        Ok(Some((out, refused.map(|e| log_err(e).to_string()))))
    }

    /// This person's presence from the last frame fed (head and hands in
    /// model space, `shapewright::interact::Session::presence`), with
    /// `selected`; `None` before the first frame.
    #[pyo3(signature = (selected=None))]
    fn presence(&self, selected: Option<u32>) -> Option<Presence> {
        self.0.presence(selected).map(Presence)
    }

    /// A modeler driver: every tool, `start` active, the palette on the
    /// left hand (the headset host's session; see `core::interact::palette`).
    #[staticmethod]
    fn modeler(start: &str, placement: &Placement) -> PyResult<Self> {
        let model = model_of(placement)?;
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

    /// The palette to draw, when open.
    fn palette(&self) -> Option<PaletteView> {
        self.0.palette().cloned().map(PaletteView)
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

/// The open palette: a plane in stage space with its items.
#[pyclass(module = "shapewright._native", frozen)]
#[derive(Clone, Debug)]
#[repr(transparent)]
pub struct PaletteView(CorePalette);

#[pymethods]
impl PaletteView {
    /// The plane (stage space): centre, +X right, +Y up, +Z toward the head.
    #[getter]
    fn pose(&self) -> Pose {
        Pose(self.0.pose)
    }

    /// `(width, height)` of the panel (metres).
    #[getter]
    fn size(&self) -> [f64; 2] {
        self.0.size
    }

    /// The items: `(label, (x0, y0, x1, y1) in the plane, active, pickable)`.
    #[getter]
    fn items(&self) -> Vec<(String, [f64; 4], bool, bool)> {
        self.0
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
            .collect()
    }

    /// The item under the pointer, if any.
    #[getter]
    fn hovered(&self) -> Option<usize> {
        self.0.hovered
    }

    /// Where the pointer meets the plane (stage space), if it does.
    #[getter]
    fn pointer(&self) -> Option<[f64; 3]> {
        self.0.pointer.map(|p| p.to_array())
    }

    /// The stage-space point of plane point `(x, y)`.
    fn to_world(&self, x: f64, y: f64) -> [f64; 3] {
        self.0.to_world(x, y).to_array()
    }

    /// What to draw: the core's draw list (stage space) with its theme.
    fn draw_list(&self) -> PaletteDraw {
        PaletteDraw(self.0.draw_list())
    }
}

/// The open palette as the core lays it out for drawing (stage space).
#[pyclass(module = "shapewright._native", frozen)]
#[derive(Clone, Debug)]
pub struct PaletteDraw(CoreDraw);

/// A quad of the draw list: corners (lower left, lower right, upper right,
/// upper left), role, linear RGB.
type QuadTuple = ([[f64; 3]; 4], &'static str, [f32; 3]);

#[pymethods]
impl PaletteDraw {
    /// Back to front: `(corners, role, rgb)`.
    #[getter]
    fn quads(&self) -> Vec<QuadTuple> {
        self.0
            .quads
            .iter()
            .map(|q| {
                (
                    q.corners.map(|c| c.to_array()),
                    q.role.name(),
                    q.role.color(),
                )
            })
            .collect()
    }

    /// One per palette item, in order.
    #[getter]
    fn labels(&self) -> Vec<PaletteLabel> {
        self.0.labels.iter().cloned().map(PaletteLabel).collect()
    }
}

/// A label of the draw list and the room it has on its button.
#[pyclass(module = "shapewright._native", frozen)]
#[derive(Clone, Debug)]
pub struct PaletteLabel(CoreLabel);

#[pymethods]
impl PaletteLabel {
    #[getter]
    fn text(&self) -> &str {
        &self.0.text
    }

    /// `"label"` or `"header"`.
    #[getter]
    fn role(&self) -> &'static str {
        self.0.role.name()
    }

    /// Linear RGB of the text.
    #[getter]
    fn color(&self) -> [f32; 3] {
        self.0.role.color()
    }

    /// Unit vector along the text (stage space).
    #[getter]
    fn right(&self) -> [f64; 3] {
        self.0.right.to_array()
    }

    /// Unit vector up the letters (stage space).
    #[getter]
    fn up(&self) -> [f64; 3] {
        self.0.up.to_array()
    }

    /// `(origin, em)`: the baseline's start (stage space) and the em height
    /// (metres) for this text, given its width and its capitals' height at
    /// an em of 1 in the host's font.
    fn place(&self, advance: f64, cap: f64) -> ([f64; 3], f64) {
        let (origin, em) = self.0.place(advance, cap);
        (origin.to_array(), em)
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

/// Shapewright's controller bindings (every profile), from the core's
/// data, as Python values.
#[pyfunction]
pub(crate) fn action_map(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let v: serde_json::Value = serde_json::from_str(&ActionMap::default_map().to_json())
        .map_err(|e| parse_err("action map", e))?;
    crate::convert::to_py(py, &v)
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
