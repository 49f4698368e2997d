//! The document and its history: `Session` wraps the core `OpLog`.

use std::sync::Mutex;
use std::time::Duration;

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use shapewright::doc::shared::{Presence, PRESENCE_STALE_SECS};
use shapewright::doc::{parse_script, run_script, ObjectId, Op, OpLog, ScriptCommand, OP_NAMES};
use shapewright::mesh::validate;
use shapewright_net::{Link, LinkOptions, SessionUrl};

use crate::error::{log_err, op_err, script_err, ParseError, SessionError};
use crate::mesh::{buffers, report_dict};

/// A document with its undoable op log, and, in a shared session, its
/// connection (`join`).
#[pyclass(module = "shapewright._native")]
pub struct Session(OpLog, Option<Mutex<Link>>);

impl Session {
    /// A session over an existing log.
    pub(crate) fn from_log(log: OpLog) -> Self {
        Self(log, None)
    }

    /// The log.
    pub(crate) fn log(&self) -> &OpLog {
        &self.0
    }

    /// The log, mutably (input feeding applies commands to it).
    pub(crate) fn log_mut(&mut self) -> &mut OpLog {
        &mut self.0
    }
}

#[pymethods]
impl Session {
    /// An empty document.
    #[new]
    fn new() -> Self {
        Self(OpLog::new(), None)
    }

    /// Rebuilds a session from recorded ops (JSON lines) and a cursor.
    #[staticmethod]
    fn from_ops(py: Python<'_>, ops_jsonl: &str, cursor: usize) -> PyResult<Self> {
        let ops = parse_ops(ops_jsonl)?;
        py.detach(|| OpLog::replay(ops, cursor))
            .map(Self::from_log)
            .map_err(log_err)
    }

    /// Applies one op given as JSON; returns the id it created, if any.
    fn apply(&mut self, py: Python<'_>, op_json: &str) -> PyResult<Option<u32>> {
        let op: Op = serde_json::from_str(op_json)
            .map_err(|e| ParseError::new_err(format!("op {op_json}: {e}")))?;
        let out = py.detach(|| self.0.apply(op)).map_err(log_err)?;
        Ok(out.created.map(|id| id.0))
    }

    /// Applies one script line: an op, or `{"op":"undo"}` / `{"op":"redo"}`
    /// as in `.jsonl` files (the core's script grammar, so errors name the
    /// field and the reason). Returns the id an op created, if any.
    fn apply_line(&mut self, py: Python<'_>, line: &str) -> PyResult<Option<u32>> {
        let command = parse_line(line)?;
        let log = &mut self.0;
        py.detach(|| match &command {
            ScriptCommand::Op(op) => log.apply(op.clone()).map(|o| o.created.map(|id| id.0)),
            ScriptCommand::Undo => log.undo().map(|()| None),
            ScriptCommand::Redo => log.redo().map(|()| None),
        })
        .map_err(log_err)
    }

    /// A copy of the session sharing its meshes (cheap): background jobs
    /// work on it while the session keeps changing. (A copy of a shared
    /// session is not connected.)
    fn snapshot(&self) -> Self {
        Self(self.0.clone(), None)
    }

    /// Joins the shared session at `url` (`nats://[USER:PASS@]HOST:PORT/DOC`)
    /// as `name` (participant id `me`, by default made from the name),
    /// catching up from the latest snapshot; `opened` (a session holding a
    /// file's history) starts an empty session from it. Returns the
    /// session and messages for the person. Each person undoes their own
    /// edits; call `pump` often (the add-on's timer does).
    #[staticmethod]
    #[pyo3(signature = (url, name, me=None, replicas=1, opened=None))]
    fn join(
        py: Python<'_>,
        url: &str,
        name: &str,
        me: Option<String>,
        replicas: usize,
        opened: Option<PyRef<'_, Session>>,
    ) -> PyResult<(Self, Vec<String>)> {
        let url = SessionUrl::parse(url).map_err(|e| SessionError::new_err(e.to_string()))?;
        let me = me.unwrap_or_else(|| shapewright_net::join::participant_id(name));
        let opened = opened.map_or_else(OpLog::new, |s| s.0.clone());
        let options = LinkOptions {
            replicas: replicas.max(1),
            ..Default::default()
        };
        let (log, link, messages) = py
            .detach(|| shapewright_net::join::join(&url, name, &me, options, &opened))
            .map_err(|e| SessionError::new_err(e.to_string()))?;
        Ok((Self(log, Some(Mutex::new(link))), messages))
    }

    /// Takes in others' edits and sends ours (never blocks). Returns
    /// `{"changed", "messages", "errors", "online", "view_only"}`;
    /// `changed` is False and the rest empty outside a shared session.
    fn pump<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = match &self.1 {
            Some(link) => {
                // On the caller's thread (Blender's timer): applying a
                // big edit of someone else's takes what applying it takes.
                let mut link = link.lock().unwrap_or_else(|e| e.into_inner());
                link.pump_log(&mut self.0).unwrap_or_default()
            }
            None => Default::default(),
        };
        let d = PyDict::new(py);
        d.set_item("changed", report.changed())?;
        d.set_item("messages", report.notices)?;
        d.set_item("errors", report.errors)?;
        d.set_item("online", report.online || self.1.is_none())?;
        d.set_item("view_only", report.view_only)?;
        Ok(d)
    }

    /// The shared session's address (`None` outside one).
    #[getter]
    fn shared_url(&self) -> Option<String> {
        let link = self.1.as_ref()?.lock().unwrap_or_else(|e| e.into_inner());
        Some(link.url().to_string())
    }

    /// The shared session's participants: `(id, name, (r, g, b))`.
    fn participants(&self) -> Vec<(String, String, (f32, f32, f32))> {
        self.0.shared().map_or_else(Vec::new, |s| {
            s.confirmed()
                .participants()
                .iter()
                .map(|p| (p.id.clone(), p.name.clone(), p.colour.into()))
                .collect()
        })
    }

    /// Sends this person's presence (a JSON presence message: `head`,
    /// `hands`, `selected` in model space); ignored outside a shared
    /// session. Refuses a message others could not draw.
    fn send_presence(&self, presence_json: &str) -> PyResult<()> {
        let p = Presence::decode(presence_json.as_bytes())
            .map_err(|e| ParseError::new_err(e.to_string()))?;
        if let Some(link) = &self.1 {
            let link = link.lock().unwrap_or_else(|e| e.into_inner());
            link.presence().send(&p);
        }
        Ok(())
    }

    /// The others heard from in the last two seconds: `(id, presence
    /// JSON)`.
    fn others(&self) -> Vec<(String, String)> {
        let Some(link) = &self.1 else {
            return Vec::new();
        };
        let link = link.lock().unwrap_or_else(|e| e.into_inner());
        link.presence()
            .others(Duration::from_secs_f64(PRESENCE_STALE_SECS))
            .into_iter()
            .map(|(who, p)| (who, String::from_utf8_lossy(&p.to_bytes()).into_owned()))
            .collect()
    }

    /// An object's kind: `solid`, `gc_assembly`, `sdf_volume`,
    /// `curve_network` or `sculpt_mesh`.
    fn object_kind(&self, id: u32) -> PyResult<&'static str> {
        Ok(self
            .0
            .document()
            .get(ObjectId(id))
            .map_err(op_err)?
            .kind
            .name())
    }

    /// Runs a script (JSON lines, with undo/redo lines) on the session.
    fn run_script(&mut self, py: Python<'_>, text: &str) -> PyResult<()> {
        let lines = parse_script(text).map_err(script_err)?;
        py.detach(|| run_script(&mut self.0, &lines))
            .map_err(script_err)
    }

    /// Steps back one op.
    fn undo(&mut self, py: Python<'_>) -> PyResult<()> {
        py.detach(|| self.0.undo()).map_err(log_err)
    }

    /// Re-applies the next op.
    fn redo(&mut self, py: Python<'_>) -> PyResult<()> {
        py.detach(|| self.0.redo()).map_err(log_err)
    }

    /// Moves the cursor to `cursor` (0..=len).
    fn seek(&mut self, py: Python<'_>, cursor: usize) -> PyResult<()> {
        py.detach(|| self.0.seek(cursor)).map_err(log_err)
    }

    /// How many ops are applied.
    #[getter]
    fn cursor(&self) -> usize {
        self.0.cursor()
    }

    /// Number of recorded ops (including the redo tail).
    fn __len__(&self) -> usize {
        self.0.len()
    }

    /// True when there is an op to undo.
    #[getter]
    fn can_undo(&self) -> bool {
        self.0.can_undo()
    }

    /// True when there is an op to redo.
    #[getter]
    fn can_redo(&self) -> bool {
        self.0.can_redo()
    }

    /// Every recorded op as JSON lines (all parameters explicit).
    fn ops_jsonl(&self) -> PyResult<String> {
        let mut out = String::new();
        for op in self.0.ops() {
            out += &serde_json::to_string(op).map_err(|e| ParseError::new_err(e.to_string()))?;
            out.push('\n');
        }
        Ok(out)
    }

    /// Ids of the document's objects, in order.
    fn object_ids(&self) -> Vec<u32> {
        self.0.document().objects().map(|(id, _)| id.0).collect()
    }

    /// An object's kind and parameters as JSON.
    fn object_json(&self, id: u32) -> PyResult<String> {
        let obj = self.0.document().get(ObjectId(id)).map_err(op_err)?;
        serde_json::to_string(&obj.kind).map_err(|e| ParseError::new_err(e.to_string()))
    }

    /// An object's user name (`rename_object`; `""`: unnamed).
    fn object_name(&self, id: u32) -> PyResult<String> {
        let obj = self.0.document().get(ObjectId(id)).map_err(op_err)?;
        Ok(obj.name.clone())
    }

    /// A hash of one object's parameters and mesh bits: changes exactly
    /// when the object does (hosts re-sync only what changed).
    fn object_hash(&self, id: u32) -> PyResult<u64> {
        self.0.document().object_hash(ObjectId(id)).map_err(op_err)
    }

    /// An object's mesh (or, with `id=None`, all objects appended) as
    /// `(positions, triangles, sources)` little-endian byte buffers.
    #[pyo3(signature = (id=None))]
    fn mesh_buffers<'py>(
        &self,
        py: Python<'py>,
        id: Option<u32>,
    ) -> PyResult<(
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
    )> {
        match id {
            Some(id) => {
                let obj = self.0.document().get(ObjectId(id)).map_err(op_err)?;
                Ok(buffers(py, &obj.mesh))
            }
            None => {
                let doc = self.0.document();
                let mesh = py.detach(|| doc.combined_mesh());
                Ok(buffers(py, &mesh))
            }
        }
    }

    /// The validation report of an object's mesh (or of all objects).
    #[pyo3(signature = (id=None))]
    fn validate<'py>(&self, py: Python<'py>, id: Option<u32>) -> PyResult<Bound<'py, PyDict>> {
        let report = match id {
            Some(id) => {
                let obj = self.0.document().get(ObjectId(id)).map_err(op_err)?;
                py.detach(|| validate(&obj.mesh, &Default::default()))
            }
            None => {
                let doc = self.0.document();
                py.detach(|| validate(&doc.combined_mesh(), &Default::default()))
            }
        };
        report_dict(py, &report)
    }

    /// Writes the printable union of all objects to `path` (.stl or .3mf
    /// in millimetres, .obj or .ply in metres); refuses (writing nothing)
    /// an empty result or one that is not a closed 2-manifold at the
    /// file's precision. Returns `{"path", "triangles", "volume", "size_mm",
    /// "volume_cm3", "fits", "fit", "over_mm"}`. For long exports use
    /// `ExportJob`.
    fn export_mesh<'py>(
        &self,
        py: Python<'py>,
        path: std::path::PathBuf,
    ) -> PyResult<Bound<'py, PyDict>> {
        crate::jobs::export_now(py, self.0.document(), &path)
    }

    /// The print line for the History panel (issue 31): the objects' size
    /// in mm against the document's printer, or None for an empty
    /// document. See `jobs::print_status_dict`.
    fn print_status<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        crate::jobs::print_status_dict(py, self.0.document())
    }

    /// A hash of the document's content (ids, parameters, mesh bits).
    fn content_hash(&self) -> u64 {
        self.0.document().content_hash()
    }
}

/// One script line as a command. The core's script grammar reads a `"v"`
/// key as the op format version, which collides with the ops whose own
/// field is `v` (`gc_insert_section`, `gc_shift`): the line is first read
/// as an op with all its fields, and only when that fails by the grammar
/// (which also gives the clearer messages: unknown op names, versions).
fn parse_line(line: &str) -> PyResult<ScriptCommand> {
    if let Ok(op) = serde_json::from_str::<Op>(line) {
        return Ok(ScriptCommand::Op(op));
    }
    let lines = parse_script(line).map_err(script_err)?;
    match lines.as_slice() {
        [one] => Ok(one.command.clone()),
        other => Err(ParseError::new_err(format!(
            "expected one op line, got {} commands",
            other.len()
        ))),
    }
}

fn parse_ops(text: &str) -> PyResult<Vec<Op>> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l)
                .map_err(|e| ParseError::new_err(format!("op line {}: {e}", i + 1)))
        })
        .collect()
}

/// The names of every op kind.
#[pyfunction]
pub(crate) fn op_names() -> Vec<&'static str> {
    OP_NAMES.to_vec()
}

/// The op schema as JSON: every op's fields with types, units, ranges,
/// defaults and docs (`shapewright::doc::schema::op_schema`). The add-on
/// builds its operators and tooltips from it.
#[pyfunction]
pub(crate) fn op_schema_json() -> String {
    shapewright::doc::schema::op_schema().to_string()
}
