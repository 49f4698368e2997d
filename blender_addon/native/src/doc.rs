//! The document and its history: `Session` wraps the core `OpLog`.
//!
//! Ops cross as Python dicts (depythonized in Rust, numbers checked:
//! `convert.rs`), never as JSON text. The log's ops are serialized once
//! each as they are appended (`lines.rs`), so a host keeps only a count
//! and a hash of its history and recording an op costs the same however
//! long the history is. What a host asks of every object on every sync
//! is cached per version of the object (`objects.rs`). Blender's own
//! edits (moves, renames, duplicates, deletes) become ops through
//! `adopt.rs`; shared sessions are in `shared.rs`.

use std::sync::Mutex;

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use shapewright::doc::{parse_script, run_script, ObjectId, Op, OpLog, ScriptCommand, OP_NAMES};
use shapewright::interact::forms::current;
use shapewright::mesh::validate;
use shapewright_net::Link;

use crate::convert::{into_py, to_value};
use crate::error::{log_err, op_err, script_err, ParseError};
use crate::forms::Built;
use crate::lines::Lines;
use crate::mesh::{buffers, report_dict};
use crate::objects::Objects;
use crate::placement::Placement;
use crate::shared::Presence;

/// A document with its undoable op log, and, in a shared session, its
/// connection (`join`).
#[pyclass(module = "shapewright._native")]
pub struct Session {
    pub(crate) log: OpLog,
    pub(crate) link: Option<Mutex<Link>>,
    pub(crate) lines: Lines,
    pub(crate) objects: Objects,
}

impl Session {
    /// A session over an existing log.
    pub(crate) fn from_log(log: OpLog) -> Self {
        let lines = Lines::of(log.ops());
        Self {
            log,
            link: None,
            lines,
            objects: Objects::default(),
        }
    }

    /// The log.
    pub(crate) fn log(&self) -> &OpLog {
        &self.log
    }

    /// The log changed; its ops before `from` did not.
    pub(crate) fn changed(&mut self, from: usize) {
        let from = if self.log.shared().is_some() { 0 } else { from };
        self.lines.sync_from(self.log.ops(), from);
    }

    /// Applies one op at the cursor (the redo tail from the cursor goes).
    pub(crate) fn apply_op(&mut self, py: Python<'_>, op: Op) -> PyResult<Option<u32>> {
        let at = self.log.cursor();
        let log = &mut self.log;
        let out = py.detach(|| log.apply(op)).map_err(log_err)?;
        self.changed(at);
        Ok(out.created.map(|id| id.0))
    }

    /// The next op a redo would apply.
    pub(crate) fn next(&self) -> Option<&Op> {
        if self.log.can_redo() && self.log.shared().is_none() {
            self.log.ops().get(self.log.cursor())
        } else {
            None
        }
    }

    fn redo_now(&mut self, py: Python<'_>) -> PyResult<()> {
        let log = &mut self.log;
        py.detach(|| log.redo()).map_err(log_err)
    }

    /// Runs `cmds` all or none (tried on a copy of the log first when
    /// there is more than one); the id the last creating op created.
    fn apply_commands(
        &mut self,
        py: Python<'_>,
        cmds: Vec<ScriptCommand>,
    ) -> PyResult<Option<u32>> {
        if cmds.len() > 1 {
            let mut trial = self.log.clone();
            py.detach(|| {
                cmds.iter().try_for_each(|c| match c {
                    ScriptCommand::Op(op) => trial.apply(op.clone()).map(|_| ()),
                    ScriptCommand::Undo => trial.undo(),
                    ScriptCommand::Redo => trial.redo(),
                })
            })
            .map_err(log_err)?;
        }
        let mut created = None;
        for c in cmds {
            created = run_command(self, py, c)?.or(created);
        }
        Ok(created)
    }
}

/// A Python op dict as a command: an op, or `{"op": "undo"}` /
/// `{"op": "redo"}` as in `.jsonl` scripts.
pub(crate) fn command_of(op: &Bound<'_, PyAny>) -> PyResult<ScriptCommand> {
    let value = to_value(op)?;
    match value.get("op").and_then(|v| v.as_str()) {
        Some("undo") => return Ok(ScriptCommand::Undo),
        Some("redo") => return Ok(ScriptCommand::Redo),
        None => {
            return Err(ParseError::new_err(
                "an op is a dict with an \"op\" key naming it, e.g. {\"op\": \"add_solid\", ...}",
            ))
        }
        Some(_) => {}
    }
    if let Ok(op) = serde_json::from_value::<Op>(value.clone()) {
        return Ok(ScriptCommand::Op(op));
    }
    // The core's script grammar gives the clearer message (unknown op
    // names, missing and unknown fields, versions).
    let lines = parse_script(&value.to_string()).map_err(script_err)?;
    match lines.as_slice() {
        [one] => Ok(one.command.clone()),
        _ => Err(ParseError::new_err("expected one op")),
    }
}

/// What `op` asks for: the ops a form built ([`Built`]), or one op dict
/// (or undo/redo line).
fn commands_of(op: &Bound<'_, PyAny>) -> PyResult<Vec<ScriptCommand>> {
    match op.cast::<Built>() {
        Ok(built) => Ok(built
            .get()
            .ops
            .iter()
            .cloned()
            .map(ScriptCommand::Op)
            .collect()),
        Err(_) => Ok(vec![command_of(op)?]),
    }
}

fn run_command(s: &mut Session, py: Python<'_>, cmd: ScriptCommand) -> PyResult<Option<u32>> {
    match cmd {
        ScriptCommand::Op(op) => s.apply_op(py, op),
        ScriptCommand::Undo => {
            let log = &mut s.log;
            py.detach(|| log.undo()).map_err(log_err)?;
            s.changed(usize::MAX);
            Ok(None)
        }
        ScriptCommand::Redo => {
            s.redo_now(py)?;
            s.changed(usize::MAX);
            Ok(None)
        }
    }
}

#[pymethods]
impl Session {
    /// An empty document.
    #[new]
    fn new() -> Self {
        Self::from_log(OpLog::new())
    }

    /// Rebuilds a session from its ops as saved (JSON lines, what
    /// `ops_jsonl` wrote into a file) and a cursor.
    #[staticmethod]
    fn from_ops(py: Python<'_>, ops_jsonl: &str, cursor: usize) -> PyResult<Self> {
        let ops = parse_ops(ops_jsonl)?;
        py.detach(|| OpLog::replay(ops, cursor))
            .map(Self::from_log)
            .map_err(log_err)
    }

    /// Applies one op given as a dict (or `{"op": "undo"}` / `{"op":
    /// "redo"}`), or the ops a form built (`Built`, all or none); returns
    /// the id it created, if any. Refused ops (typed errors naming the
    /// field) change nothing.
    fn apply(&mut self, py: Python<'_>, op: &Bound<'_, PyAny>) -> PyResult<Option<u32>> {
        self.apply_commands(py, commands_of(op)?)
    }

    /// Applies a list of op dicts (or forms' built ops), all or none: if
    /// one is refused, none is applied. Returns the id the last creating
    /// op created, if any.
    fn apply_all(&mut self, py: Python<'_>, ops: Vec<Bound<'_, PyAny>>) -> PyResult<Option<u32>> {
        let mut cmds = Vec::new();
        for op in &ops {
            cmds.extend(commands_of(op)?);
        }
        self.apply_commands(py, cmds)
    }

    /// Runs a script (JSON lines, with undo/redo lines), all or none.
    fn run_script(&mut self, py: Python<'_>, text: &str) -> PyResult<()> {
        let lines = parse_script(text).map_err(script_err)?;
        let mut trial = self.log.clone();
        py.detach(|| run_script(&mut trial, &lines))
            .map_err(script_err)?;
        self.log = trial;
        self.changed(0);
        Ok(())
    }

    /// Steps back one op.
    fn undo(&mut self, py: Python<'_>) -> PyResult<()> {
        let log = &mut self.log;
        py.detach(|| log.undo()).map_err(log_err)?;
        self.changed(usize::MAX);
        Ok(())
    }

    /// Re-applies the next op.
    fn redo(&mut self, py: Python<'_>) -> PyResult<()> {
        self.redo_now(py)?;
        self.changed(usize::MAX);
        Ok(())
    }

    /// Moves the cursor to `cursor` (0..=len).
    fn seek(&mut self, py: Python<'_>, cursor: usize) -> PyResult<()> {
        let log = &mut self.log;
        py.detach(|| log.seek(cursor)).map_err(log_err)
    }

    /// How many ops are applied.
    #[getter]
    fn cursor(&self) -> usize {
        self.log.cursor()
    }

    /// Number of recorded ops (including the redo tail).
    fn __len__(&self) -> usize {
        self.lines.len()
    }

    /// True when there is an op to undo.
    #[getter]
    fn can_undo(&self) -> bool {
        self.log.can_undo()
    }

    /// True when there is an op to redo.
    #[getter]
    fn can_redo(&self) -> bool {
        self.log.can_redo()
    }

    /// A hash of the first `count` ops (hex), or None past the end: a host
    /// that stored `(count, prefix_hash(count))` knows whether this
    /// session still holds that history.
    fn prefix_hash(&self, count: usize) -> Option<String> {
        self.lines.prefix_hash(count)
    }

    /// Every recorded op as JSON lines: what a file stores.
    fn ops_jsonl(&self) -> String {
        self.lines.joined()
    }

    /// Op `index` (0-based) as a dict.
    fn op<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyAny>> {
        let op = self.log.ops().get(index).ok_or_else(|| {
            ParseError::new_err(format!("no op {index}: the log has {}", self.lines.len()))
        })?;
        into_py(py, op)
    }

    /// The op a redo would apply, as a dict (None at the end).
    fn next_op<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.next().map(|op| into_py(py, op)).transpose()
    }

    /// A copy of the session sharing its meshes (cheap): background jobs
    /// work on it while the session keeps changing. (A copy of a shared
    /// session is not connected.)
    fn snapshot(&self) -> Self {
        Self::from_log(self.log.clone())
    }

    /// Ids of the document's objects, in order.
    fn object_ids(&self) -> Vec<u32> {
        self.log.document().objects().map(|(id, _)| id.0).collect()
    }

    /// An object's kind: `solid`, `gc_assembly`, `sdf_volume`,
    /// `curve_network` or `sculpt_mesh`.
    fn object_kind(&self, id: u32) -> PyResult<&'static str> {
        let obj = self.log.document().get(ObjectId(id)).map_err(op_err)?;
        Ok(obj.kind.name())
    }

    /// An object's user name (`rename_object`; `""`: unnamed).
    fn object_name(&self, id: u32) -> PyResult<String> {
        let obj = self.log.document().get(ObjectId(id)).map_err(op_err)?;
        Ok(obj.name.clone())
    }

    /// An object's parameters as a dict (`{"kind": ..., ...}`): what an
    /// edit's form starts from.
    fn object_params<'py>(&self, py: Python<'py>, id: u32) -> PyResult<Bound<'py, PyAny>> {
        let obj = self.log.document().get(ObjectId(id)).map_err(op_err)?;
        into_py(py, &obj.kind)
    }

    /// The values op `op`'s form starts from on object `id` (part `part`
    /// of an assembly): the object's current ones (see
    /// `shapewright::interact::forms::current`); empty when it has none.
    #[pyo3(signature = (op, id, part=0))]
    fn form_current<'py>(
        &self,
        py: Python<'py>,
        op: &str,
        id: u32,
        part: i64,
    ) -> PyResult<Bound<'py, PyAny>> {
        // A negative part is no part (a form's own range check refuses it).
        let values = usize::try_from(part)
            .map(|k| current(op, self.log.document(), ObjectId(id), k))
            .unwrap_or_default();
        crate::convert::to_py(py, &serde_json::Value::Object(values))
    }

    /// Where an object is: the transform its placement ops change (a
    /// solid's or sculpt's own, else the object's placement).
    fn object_transform(&self, id: u32) -> PyResult<Placement> {
        let obj = self.log.document().get(ObjectId(id)).map_err(op_err)?;
        Ok(Placement(obj.transform()))
    }

    /// An object's origin (`shapewright::doc::Object::origin`): where a
    /// host shows it and what it turns and scales about.
    fn object_origin(&self, id: u32) -> PyResult<Placement> {
        Ok(Placement(self.objects.origin(self.log.document(), id)?))
    }

    /// The key of an object's mesh in its origin's frame: equal keys mean
    /// the same mesh (a host re-reads the mesh only when it changes).
    fn shape_key(&self, id: u32) -> PyResult<String> {
        self.objects.shape_key(self.log.document(), id)
    }

    /// A hash of one object's name, placement, parameters and mesh bits.
    fn object_hash(&self, id: u32) -> PyResult<u64> {
        self.objects.hash(self.log.document(), id)
    }

    /// An object's mesh (or, with `id=None`, all objects appended, in
    /// world space) as `(positions f64, triangles u32, sources u32)`
    /// little-endian byte buffers. `frame` is `world` or `origin` (the
    /// mesh the object's origin places); positions are multiplied by
    /// `units_per_metre` (a host scene's units).
    #[pyo3(signature = (id=None, frame="world", units_per_metre=1.0))]
    fn mesh_buffers<'py>(
        &self,
        py: Python<'py>,
        id: Option<u32>,
        frame: &str,
        units_per_metre: f64,
    ) -> PyResult<(
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
        Bound<'py, PyBytes>,
    )> {
        let doc = self.log.document();
        let mesh = match (id, frame) {
            (None, "world") => py.detach(|| doc.combined_mesh()),
            (Some(id), "world") => {
                let obj = doc.get(ObjectId(id)).map_err(op_err)?;
                return Ok(buffers(py, &obj.mesh, units_per_metre));
            }
            (Some(id), "origin") => {
                let obj = doc.get(ObjectId(id)).map_err(op_err)?;
                py.detach(|| obj.origin_mesh()).map_err(op_err)?
            }
            (_, other) => {
                return Err(ParseError::new_err(format!(
                    "frame must be \"world\" or \"origin\" (with an id), got {other:?}"
                )))
            }
        };
        Ok(buffers(py, &mesh, units_per_metre))
    }

    /// The validation report of an object's mesh (or of all objects).
    #[pyo3(signature = (id=None))]
    fn validate<'py>(&self, py: Python<'py>, id: Option<u32>) -> PyResult<Bound<'py, PyDict>> {
        let doc = self.log.document();
        let report = match id {
            Some(id) => {
                let obj = doc.get(ObjectId(id)).map_err(op_err)?;
                py.detach(|| validate(&obj.mesh, &Default::default()))
            }
            None => py.detach(|| validate(&doc.combined_mesh(), &Default::default())),
        };
        report_dict(py, &report)
    }

    /// Writes the printable union of all objects to `path` (by extension)
    /// (.stl or .3mf in millimetres, .obj or .ply in metres) on this
    /// thread (GIL released); refuses, writing nothing, what the print
    /// path refuses. Returns the export's summary with the printed size and
    /// bed fit (see `ExportJob`, also for `scale` and `fit`).
    #[pyo3(signature = (path, *, scale=1.0, fit=false))]
    fn export_mesh<'py>(
        &self,
        py: Python<'py>,
        path: std::path::PathBuf,
        scale: f64,
        fit: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let scale = crate::jobs::print_scale(scale, fit);
        crate::jobs::export_now(py, self.log.document(), &path, scale)
    }

    /// The print line for the History panel (issue 31): the objects' size
    /// in mm against the document's printer, or None for an empty
    /// document. See `jobs::print_status_dict`.
    fn print_status<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        crate::jobs::print_status_dict(py, self.log.document())
    }

    /// A hash of the document's content (ids, parameters, mesh bits).
    fn content_hash(&self) -> u64 {
        self.log.document().content_hash()
    }

    /// Blender's move of object `id`: its origin is now `origin`. Redoes
    /// the next op when it is that very change (an undo step that holds
    /// the move with the log before it), else records a `set_transform`.
    /// Returns `redone`, `applied` or `same` (nothing to do).
    fn adopt_placement(
        &mut self,
        py: Python<'_>,
        id: u32,
        origin: &Placement,
    ) -> PyResult<&'static str> {
        crate::adopt::placement(self, py, id, origin)
    }

    /// Blender's rename of object `id` (redone or recorded as above).
    fn adopt_name(&mut self, py: Python<'_>, id: u32, name: &str) -> PyResult<&'static str> {
        crate::adopt::name(self, py, id, name)
    }

    /// Blender's duplicate of object `id` (Shift-D); returns how it was
    /// taken and the copy's id.
    fn adopt_duplicate(&mut self, py: Python<'_>, id: u32) -> PyResult<(&'static str, u32)> {
        crate::adopt::duplicate(self, py, id)
    }

    /// Blender's delete of object `id` (X).
    fn adopt_delete(&mut self, py: Python<'_>, id: u32) -> PyResult<&'static str> {
        crate::adopt::delete(self, py, id)
    }

    /// Joins the shared session at `url` (`nats://[USER:PASS@]HOST:PORT/DOC`)
    /// as `name` (participant id `me`, by default made from the name),
    /// catching up from the latest snapshot; `opened` (a session holding a
    /// file's history) starts an empty session from it. Returns the
    /// session and messages for the person. Blocks while it connects (the
    /// GIL released): a host calls it off its UI thread.
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
        let opened = opened.map_or_else(OpLog::new, |s| s.log.clone());
        crate::shared::join(py, url, name, me, replicas, opened)
    }

    /// Takes in others' edits and sends ours (never blocks). Returns
    /// `{"changed", "messages", "errors", "online", "view_only"}`;
    /// `changed` is False and the rest empty outside a shared session.
    fn pump<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::shared::pump(self, py)
    }

    /// The shared session's address (`None` outside one).
    #[getter]
    fn shared_url(&self) -> Option<String> {
        crate::shared::url(self)
    }

    /// The shared session's participants: `(id, name, (r, g, b))`.
    fn participants(&self) -> Vec<(String, String, (f32, f32, f32))> {
        crate::shared::participants(self)
    }

    /// Sends this person's presence; ignored outside a shared session.
    fn send_presence(&self, presence: &Presence) {
        crate::shared::send_presence(self, presence);
    }

    /// The others heard from in the last two seconds: `(id, presence)`.
    fn others(&self) -> Vec<(String, Presence)> {
        crate::shared::others(self)
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

/// The op schema (`shapewright::doc::schema::op_schema`) as Python
/// values: every op's fields with types, units, ranges, defaults and docs.
/// The add-on builds its operators and tooltips from it.
#[pyfunction]
pub(crate) fn op_schema(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    crate::convert::to_py(py, &shapewright::doc::schema::op_schema())
}
