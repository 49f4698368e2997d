//! Writing a document and its log as one usda layer.

use openusd::sdf::Value;
use openusd::usda::TextWriter;
use shapewright::doc::{OpLog, OP_FORMAT_VERSION};

use crate::kinds::object_prim;
use crate::prims::{build_layer, AttrOut, PrimOut, StageMeta};
use crate::{SaveError, FORMAT_VERSION, LOG_PRIM, WORLD_PRIM};

/// Options of a save.
#[derive(Clone, Debug, PartialEq)]
pub struct SaveOptions {
    /// `metersPerUnit` of the stage: the length of one model unit in
    /// meters. Shapewright models in meters, so 1.
    pub meters_per_unit: f64,
}

impl Default for SaveOptions {
    fn default() -> Self {
        Self {
            meters_per_unit: 1.0,
        }
    }
}

/// The usda text of `log` (its ops, cursor and document at the cursor).
pub fn save_to_string(log: &OpLog, options: &SaveOptions) -> Result<String, SaveError> {
    if !(options.meters_per_unit.is_finite() && options.meters_per_unit > 0.0) {
        return Err(SaveError::Author(format!(
            "metersPerUnit must be a positive number, got {}",
            options.meters_per_unit
        )));
    }
    let doc = log.document();
    let mut world = PrimOut::new(WORLD_PRIM, "Xform");
    for (id, obj) in doc.objects() {
        world.children.push(object_prim(id, obj)?);
    }
    let roots = [world, log_prim(log)?];
    let meta = StageMeta {
        default_prim: WORLD_PRIM.to_owned(),
        up_axis: "Z",
        meters_per_unit: options.meters_per_unit,
        doc: format!(
            "Shapewright document with its op history (shapewright-usd {}, format {FORMAT_VERSION})",
            env!("CARGO_PKG_VERSION")
        ),
    };
    let data = build_layer(&meta, &roots)?;
    TextWriter::write_to_string(&data).map_err(|e| SaveError::Author(format!("{e:#}")))
}

fn no_backslash(text: String, what: impl FnOnce() -> String) -> Result<String, SaveError> {
    if text.contains('\\') {
        Err(SaveError::Unencodable { what: what() })
    } else {
        Ok(text)
    }
}

fn to_json<T: serde::Serialize>(v: &T, what: impl FnOnce() -> String) -> Result<String, SaveError> {
    let text = serde_json::to_string(v).map_err(|e| SaveError::Author(format!("{e}")))?;
    no_backslash(text, what)
}

fn log_prim(log: &OpLog) -> Result<PrimOut, SaveError> {
    let mut ops = Vec::with_capacity(log.len());
    let mut types = Vec::with_capacity(log.len());
    for (i, op) in log.ops().iter().enumerate() {
        ops.push(to_json(op, || format!("op {i}"))?);
        types.push(op.name().into());
    }
    let snapshot = to_json(log.document(), || "the snapshot".to_owned())?;
    let count = |n: usize, what: &str| {
        i32::try_from(n).map_err(|_| SaveError::Author(format!("{what} {n} exceeds int")))
    };
    let mut p = PrimOut::new(LOG_PRIM, "Scope");
    p.attrs = vec![
        AttrOut::custom(
            "shapewright:formatVersion",
            "int",
            Value::Int(FORMAT_VERSION as i32),
        ),
        AttrOut::custom(
            "shapewright:opFormatVersion",
            "int",
            Value::Int(OP_FORMAT_VERSION as i32),
        ),
        AttrOut::custom(
            "shapewright:cursor",
            "int",
            Value::Int(count(log.cursor(), "cursor")?),
        ),
        AttrOut::custom(
            "shapewright:opCount",
            "int",
            Value::Int(count(log.len(), "op count")?),
        ),
        AttrOut::custom("shapewright:opTypes", "token[]", Value::TokenVec(types)),
        AttrOut::custom("shapewright:ops", "string[]", Value::StringVec(ops)),
        AttrOut::custom("shapewright:snapshot", "string", Value::String(snapshot)),
    ];
    Ok(p)
}
