//! Reading a document and its log back from a Shapewright USD layer.
//!
//! Reopening restores the ops, the cursor and the document at the cursor
//! from the snapshot, without replaying the history (see
//! [`shapewright::doc::OpLog::from_snapshot`]); undo and redo then work as
//! in the session that saved it. Every load compares the stored meshes with
//! the evaluated ones ([`crate::check`]); [`LoadOptions::verify_history`]
//! also replays the whole history and compares it with the snapshot.
// Reads outside data: no indexing that can panic (issue 22).
#![deny(clippy::indexing_slicing)]

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use openusd::sdf::{self, AbstractData, Value};
use shapewright::doc::{Document, ObjectId, Op, OpLog, OP_FORMAT_VERSION};

use crate::check::{compare, ConsistencyReport, Mismatch, StoredMesh};
use crate::limits;
use crate::save::decode_json;
use crate::{LoadError, FORMAT_VERSION, OLDEST_FORMAT_VERSION};

/// How to load.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Replay the whole history and compare it with the snapshot (costs
    /// what the history costs; `info` does it, opening a file does not).
    pub verify_history: bool,
    /// Fail with [`LoadError::Inconsistent`] instead of returning a report
    /// with mismatches.
    pub strict: bool,
}

/// A loaded document with its history and what the load found.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The history, with its cursor and document restored.
    pub log: OpLog,
    /// Whether the stored geometry agrees with the log.
    pub report: ConsistencyReport,
    /// The file format version found.
    pub format_version: i64,
    /// `metersPerUnit` of the stage (1 when not authored).
    pub meters_per_unit: f64,
    /// True when the document was rebuilt by replaying the history (the
    /// file had no snapshot, or its snapshot was not trusted: see
    /// [`Loaded::snapshot`]).
    pub replayed: bool,
    /// What became of the file's snapshot.
    pub snapshot: SnapshotUse,
}

/// What a load did with the file's snapshot of the document.
///
/// The log is the truth: a snapshot that does not parse, or that gives a
/// different document than replaying the log, is never used; the document
/// is then the replayed log's, and this says why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SnapshotUse {
    /// The snapshot was used (and, when checked, agreed with the log).
    Used,
    /// The file has no snapshot; the log was replayed.
    Absent,
    /// The snapshot does not parse or does not fit the log; the log was
    /// replayed instead.
    Rejected {
        /// Why.
        reason: String,
    },
    /// The snapshot parses but replaying the log gives another document;
    /// the log's document is used.
    DisagreesWithLog,
}

impl SnapshotUse {
    /// A sentence for a warning, or `None` when the snapshot was used or
    /// simply absent.
    pub fn warning(&self) -> Option<String> {
        match self {
            Self::Used | Self::Absent => None,
            Self::Rejected { reason } => Some(format!(
                "the file's snapshot of the document is unusable ({reason}); the document was rebuilt by replaying its op log"
            )),
            Self::DisagreesWithLog => Some(
                "the file's snapshot of the document disagrees with its op log; the document was rebuilt by replaying the log (the log wins)"
                    .to_owned(),
            ),
        }
    }
}

/// Parses usda text and loads it.
pub fn load_from_str(text: &str, options: LoadOptions) -> Result<Loaded, LoadError> {
    limits::with_parser_stack(|| {
        limits::check_usda_nesting(text)?;
        let data = openusd::usda::parse(text).map_err(|e| LoadError::Parse(format!("{e:#}")))?;
        load_from_data(&data, options)
    })
}

/// Reads a usda, usdc or usdz file (by content, not by extension) and loads it.
pub fn load_file(path: &Path, options: LoadOptions) -> Result<Loaded, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.display().to_string(),
        source,
    })?;
    load_from_bytes(&bytes, options)
}

/// Loads a usda, usdc or usdz layer from its bytes.
pub fn load_from_bytes(bytes: &[u8], options: LoadOptions) -> Result<Loaded, LoadError> {
    limits::with_parser_stack(|| {
        let data = read_layer(bytes)?;
        load_from_data(data.as_ref(), options)
    })
}

/// Parses the bytes of a usda, usdc or usdz layer (usdz: its first layer).
///
/// Parsers recurse on nesting: call this on a thread with a large stack
/// ([`limits::with_parser_stack`], as [`load_file`] does); usda text
/// nested deeper than [`limits::MAX_NESTING`] is refused before parsing.
pub fn read_layer(bytes: &[u8]) -> Result<Box<dyn AbstractData>, LoadError> {
    let parse = |e: anyhow::Error| LoadError::Parse(format!("{e:#}"));
    if bytes.starts_with(b"PXR-USDC") {
        let data =
            openusd::usdc::CrateData::open(Cursor::new(bytes.to_vec()), true).map_err(parse)?;
        Ok(Box::new(data))
    } else if bytes.starts_with(b"PK\x03\x04") {
        let mut archive =
            openusd::usdz::Archive::from_reader(Cursor::new(bytes.to_vec())).map_err(parse)?;
        archive.read_first_layer().map_err(parse)
    } else {
        let text = std::str::from_utf8(bytes)
            .map_err(|e| LoadError::Parse(format!("usda text is not UTF-8: {e}")))?;
        limits::check_usda_nesting(text)?;
        Ok(Box::new(openusd::usda::parse(text).map_err(parse)?))
    }
}

pub(crate) fn field<'a>(
    data: &'a dyn AbstractData,
    path: &sdf::Path,
    name: &str,
) -> Option<Cow<'a, Value>> {
    data.try_field(path, name).ok().flatten()
}

pub(crate) fn attr_value<'a>(
    data: &'a dyn AbstractData,
    prim: &sdf::Path,
    name: &str,
) -> Option<Cow<'a, Value>> {
    let p = prim.append_property(name).ok()?;
    field(data, &p, "default")
}

pub(crate) fn as_int(v: &Value) -> Option<i64> {
    match v {
        Value::Int(i) => Some(i64::from(*i)),
        Value::Int64(i) => Some(*i),
        Value::Uint(i) => Some(i64::from(*i)),
        Value::Uint64(i) => i64::try_from(*i).ok(),
        Value::Uchar(i) => Some(i64::from(*i)),
        _ => None,
    }
}

fn log_int(data: &dyn AbstractData, log: &sdf::Path, name: &'static str) -> Result<i64, LoadError> {
    let v = attr_value(data, log, name).ok_or(LoadError::BadAttribute {
        name,
        problem: "missing".to_owned(),
    })?;
    as_int(&v).ok_or_else(|| LoadError::BadAttribute {
        name,
        problem: format!("not an integer ({})", type_of(&v)),
    })
}

fn type_of(v: &Value) -> String {
    let s = format!("{v:?}");
    s.split(['(', ' ', '{']).next().unwrap_or("?").to_owned()
}

fn strings(v: &Value) -> Option<Vec<String>> {
    match v {
        Value::StringVec(s) => Some(s.clone()),
        Value::TokenVec(s) => Some(s.iter().map(|t| t.as_str().to_owned()).collect()),
        _ => None,
    }
}

fn string(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Token(t) => Some(t.as_str().to_owned()),
        _ => None,
    }
}

fn check_version(
    what: &'static str,
    found: i64,
    oldest: i64,
    newest: i64,
) -> Result<(), LoadError> {
    if found < oldest || found > newest {
        return Err(LoadError::UnsupportedVersion {
            what,
            found,
            oldest,
            newest,
        });
    }
    Ok(())
}

/// The log's ops, checked against its `opTypes` and `opCount` when the
/// file has them (a truncated or hand-edited log is refused, named).
fn read_ops(data: &dyn AbstractData, log_path: &sdf::Path) -> Result<Vec<Op>, LoadError> {
    let ops_value =
        attr_value(data, log_path, "shapewright:ops").ok_or(LoadError::BadAttribute {
            name: "shapewright:ops",
            problem: "missing".to_owned(),
        })?;
    let texts = strings(&ops_value).ok_or_else(|| LoadError::BadAttribute {
        name: "shapewright:ops",
        problem: format!("not a string array ({})", type_of(&ops_value)),
    })?;
    let mut ops = Vec::with_capacity(texts.len());
    for (index, t) in texts.iter().enumerate() {
        let bad = |message: String| LoadError::BadOp { index, message };
        let json = decode_json(t).ok_or_else(|| bad("bad hex encoding".to_owned()))?;
        let op: Op = serde_json::from_str(&json).map_err(|e| bad(e.to_string()))?;
        ops.push(op);
    }
    if let Some(v) = attr_value(data, log_path, "shapewright:opTypes") {
        let types = strings(&v).ok_or_else(|| LoadError::BadAttribute {
            name: "shapewright:opTypes",
            problem: format!("not a token array ({})", type_of(&v)),
        })?;
        if types.len() != ops.len() {
            return Err(LoadError::BadAttribute {
                name: "shapewright:opTypes",
                problem: format!("{} entries for {} ops", types.len(), ops.len()),
            });
        }
        if let Some((i, (t, op))) = types
            .iter()
            .zip(&ops)
            .enumerate()
            .find(|(_, (t, op))| t.as_str() != op.name())
        {
            return Err(LoadError::BadAttribute {
                name: "shapewright:opTypes",
                problem: format!("entry {i} says `{t}` but op {i} is `{}`", op.name()),
            });
        }
    }
    if let Some(v) = attr_value(data, log_path, "shapewright:opCount") {
        if as_int(&v) != Some(ops.len() as i64) {
            return Err(LoadError::BadAttribute {
                name: "shapewright:opCount",
                problem: format!("{v:?} but the log holds {} ops (truncated?)", ops.len()),
            });
        }
    }
    Ok(ops)
}

/// Loads from a parsed layer.
pub fn load_from_data(data: &dyn AbstractData, options: LoadOptions) -> Result<Loaded, LoadError> {
    let log_path = crate::layout::find_log(data).ok_or(LoadError::NotShapewright)?;
    let format_version = log_int(data, &log_path, "shapewright:formatVersion")?;
    check_version(
        "file format",
        format_version,
        OLDEST_FORMAT_VERSION,
        FORMAT_VERSION,
    )?;
    let op_version = log_int(data, &log_path, "shapewright:opFormatVersion")?;
    check_version("op format", op_version, 1, i64::from(OP_FORMAT_VERSION))?;

    let ops = read_ops(data, &log_path)?;
    let cursor = log_int(data, &log_path, "shapewright:cursor")?;
    let cursor = usize::try_from(cursor).map_err(|_| LoadError::BadAttribute {
        name: "shapewright:cursor",
        problem: format!("negative ({cursor})"),
    })?;

    // The snapshot, if it parses and fits the log.
    let from_snapshot = match attr_value(data, &log_path, "shapewright:snapshot") {
        None => Err(SnapshotUse::Absent),
        Some(v) => {
            let rejected = |reason: String| SnapshotUse::Rejected { reason };
            string(&v)
                .ok_or_else(|| rejected(format!("not a string ({})", type_of(&v))))
                .and_then(|text| {
                    let json =
                        decode_json(&text).ok_or_else(|| rejected("bad hex encoding".into()))?;
                    serde_json::from_str::<Document>(&json).map_err(|e| rejected(e.to_string()))
                })
                .and_then(|doc| {
                    OpLog::from_snapshot(ops.clone(), cursor, doc)
                        .map_err(|e| rejected(e.to_string()))
                })
        }
    };
    // Object prims wherever the stage keeps them (ours, or under
    // Blender's root prim with Blender's names).
    let prims = crate::layout::object_prims(data);
    let stored = stored_meshes(data, &prims.objects, stage_meters_per_unit(data));
    let check = |doc: &Document| {
        let mut r = compare(doc, &stored, prims.extra.clone());
        r.mismatches
            .extend(crate::parametric::mismatches(data, doc, &prims.objects));
        r
    };
    let (log, snapshot) = match from_snapshot {
        Ok(log) => (log, SnapshotUse::Used),
        Err(why) => (OpLog::replay(ops.clone(), cursor)?, why),
    };
    let mut report = check(log.document());
    let (log, snapshot, report) = if snapshot == SnapshotUse::Used
        && (options.verify_history || !report.is_consistent())
    {
        // Something disagrees (or the caller asked): the log decides.
        match OpLog::replay(ops, cursor) {
            Ok(r) if r.document().content_hash() == log.document().content_hash() => {
                report.history_checked = true;
                (log, SnapshotUse::Used, report)
            }
            Ok(r) => {
                let mut report = check(r.document());
                report.history_checked = true;
                report.mismatches.push(Mismatch::History {
                    detail: format!(
                        "replaying the {cursor} applied ops gives a different document than the snapshot; the log's document is used"
                    ),
                });
                (r, SnapshotUse::DisagreesWithLog, report)
            }
            Err(e) if report.is_consistent() => {
                // Only the check asked for failed: the snapshot agrees
                // with the stored meshes; report the history.
                report.history_checked = true;
                report.mismatches.push(Mismatch::History {
                    detail: e.to_string(),
                });
                (log, SnapshotUse::Used, report)
            }
            Err(e) => {
                // Neither can be trusted: say which is which.
                return Err(LoadError::Untrusted {
                    mismatches: report.to_string(),
                    replay: e.to_string(),
                });
            }
        }
    } else {
        (log, snapshot, report)
    };
    let replayed = snapshot != SnapshotUse::Used;
    if options.strict && !report.is_consistent() {
        return Err(LoadError::Inconsistent(report));
    }
    let meters_per_unit = stage_meters_per_unit(data);
    Ok(Loaded {
        log,
        report,
        format_version,
        meters_per_unit,
        replayed,
        snapshot,
    })
}

/// The stage's `metersPerUnit` (1 when not set).
fn stage_meters_per_unit(data: &dyn AbstractData) -> f64 {
    field(data, &sdf::Path::abs_root(), "metersPerUnit")
        .and_then(|v| match v.as_ref() {
            Value::Double(d) => Some(*d),
            Value::Float(f) => Some(f64::from(*f)),
            other => as_int(other).map(|i| i as f64),
        })
        .filter(|m| m.is_finite() && *m > 0.0)
        .unwrap_or(1.0)
}

pub(crate) fn children(data: &dyn AbstractData, path: &sdf::Path) -> Vec<String> {
    field(data, path, "primChildren")
        .and_then(|v| strings(&v))
        .unwrap_or_default()
}

/// The transform placing `prim` in the stage (its stack times its
/// ancestors'), or None when one cannot be read (the points are then
/// compared as stored).
fn placement_of(data: &dyn AbstractData, prim: &sdf::Path) -> Option<shapewright::math::DMat4> {
    let layer = crate::xform::FlatLayer(data);
    let mut m = shapewright::math::DMat4::IDENTITY;
    let mut p = Some(prim.clone());
    while let Some(cur) = p {
        if cur.is_abs_root() {
            break;
        }
        let (local, reset) = crate::xform::local_transform(&layer, &cur).ok()?;
        m = local * m;
        if reset {
            break;
        }
        p = cur.parent();
    }
    Some(m)
}

/// The stored mesh of each object prim that has one.
fn stored_meshes(
    data: &dyn AbstractData,
    objects: &BTreeMap<ObjectId, sdf::Path>,
    meters_per_unit: f64,
) -> BTreeMap<ObjectId, StoredMesh> {
    let mut out = BTreeMap::new();
    for (id, obj) in objects {
        let Some(mesh) = crate::layout::mesh_of(data, obj) else {
            continue;
        };
        let ints = |name: &str| match attr_value(data, &mesh, name).as_deref() {
            Some(Value::IntVec(v)) => v.clone(),
            _ => Vec::new(),
        };
        let mut points = match attr_value(data, &mesh, "points").as_deref() {
            Some(Value::Vec3fVec(v)) => v.clone(),
            _ => Vec::new(),
        };
        // A host may write each object at its origin (Blender does): the
        // points are then placed by the prims' transforms and the stage's
        // metres per unit before they are compared with the document.
        let placed = placement_of(data, &mesh)
            .map(|m| {
                shapewright::math::DMat4::from_scale(shapewright::math::DVec3::splat(
                    meters_per_unit,
                )) * m
            })
            .filter(|m| *m != shapewright::math::DMat4::IDENTITY);
        if let Some(m) = placed {
            for p in &mut points {
                let q = m.transform_point3(shapewright::math::DVec3::new(
                    f64::from(p.x),
                    f64::from(p.y),
                    f64::from(p.z),
                ));
                *p = openusd::gf::vec3f(q.x as f32, q.y as f32, q.z as f32);
            }
        }
        out.insert(
            *id,
            StoredMesh {
                points,
                counts: ints("faceVertexCounts"),
                indices: ints("faceVertexIndices"),
                placed: placed.is_some(),
            },
        );
    }
    out
}
