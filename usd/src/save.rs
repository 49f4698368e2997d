//! Writing a document and its log as one usda layer.

use openusd::sdf::Value;
use openusd::usda::TextWriter;
use shapewright::doc::{ObjectId, OpLog, OP_FORMAT_VERSION};

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

/// One object (or part of one) that a save could not write.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unwritten {
    /// The object.
    pub id: ObjectId,
    /// What of it was left out and why (`part 2: ...`, `patch 4 boundary: ...`).
    pub what: String,
}

impl std::fmt::Display for Unwritten {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "object {}: {}", self.id, self.what)
    }
}

/// The usda text of a save and what it could not write.
#[derive(Clone, Debug, PartialEq)]
pub struct Authored {
    /// The layer as usda.
    pub text: String,
    /// Parametric parts left out (their objects' meshes, every other
    /// object, the log and the snapshot are in `text`).
    pub unwritten: Vec<Unwritten>,
}

/// The usda text of `log` (its ops, cursor and document at the cursor).
/// Parts that cannot be written are left out silently; use [`author`] to
/// learn which.
pub fn save_to_string(log: &OpLog, options: &SaveOptions) -> Result<String, SaveError> {
    author(log, options).map(|a| a.text)
}

/// The usda text of `log`, and what it could not write.
///
/// A save never fails because of one object: every object's mesh is
/// written, and a parametric part that cannot be made (see
/// [`crate::parametric::parts`]) is left out, named in
/// [`Authored::unwritten`] and in the object's `shapewright:unwritten`
/// attribute. The log and the snapshot, which reopening needs, are always
/// written: an op or snapshot whose JSON contains a backslash (which usda
/// readers disagree on) is stored hex-encoded ([`encode_json`]).
pub fn author(log: &OpLog, options: &SaveOptions) -> Result<Authored, SaveError> {
    if !(options.meters_per_unit.is_finite() && options.meters_per_unit > 0.0) {
        return Err(SaveError::Author(format!(
            "metersPerUnit must be a positive number, got {}",
            options.meters_per_unit
        )));
    }
    let doc = log.document();
    let mut world = PrimOut::new(WORLD_PRIM, "Xform");
    let mut unwritten = Vec::new();
    for (id, obj) in doc.objects() {
        let (prim, problems) = object_prim(id, obj);
        world.children.push(prim);
        unwritten.extend(problems.into_iter().map(|what| Unwritten { id, what }));
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
    let text =
        TextWriter::write_to_string(&data).map_err(|e| SaveError::Author(format!("{e:#}")))?;
    Ok(Authored { text, unwritten })
}

/// Prefix of a hex-encoded JSON value in the log prim.
pub const HEX_PREFIX: &str = "hex:";

/// JSON text as stored in a usda string: as is, or, when it contains a
/// backslash (a JSON escape, which Pixar's usda reader would unescape and
/// openusd's would not), as `hex:` and the hex digits of its UTF-8 bytes.
/// JSON text never starts with `h`, so the two cannot be confused.
pub fn encode_json(text: String) -> String {
    if !text.contains('\\') {
        return text;
    }
    let mut out = String::with_capacity(HEX_PREFIX.len() + 2 * text.len());
    out.push_str(HEX_PREFIX);
    for b in text.bytes() {
        out.push_str(&format!("{b:02x}"));
    }
    out
}

/// The JSON text of a stored value (see [`encode_json`]); `None` when a
/// `hex:` value has an odd length, a non-hex digit, or is not UTF-8.
pub fn decode_json(stored: &str) -> Option<std::borrow::Cow<'_, str>> {
    let Some(hex) = stored.strip_prefix(HEX_PREFIX) else {
        return Some(std::borrow::Cow::Borrowed(stored));
    };
    if hex.len() % 2 != 0 {
        return None;
    }
    let bytes = hex
        .as_bytes()
        .chunks(2)
        .map(|pair| {
            let digit = |c: u8| (c as char).to_digit(16);
            match pair {
                [hi, lo] => Some((digit(*hi)? * 16 + digit(*lo)?) as u8),
                _ => None,
            }
        })
        .collect::<Option<Vec<u8>>>()?;
    String::from_utf8(bytes).ok().map(std::borrow::Cow::Owned)
}

fn to_json<T: serde::Serialize>(v: &T) -> Result<String, SaveError> {
    let text = serde_json::to_string(v).map_err(|e| SaveError::Author(format!("{e}")))?;
    Ok(encode_json(text))
}

fn log_prim(log: &OpLog) -> Result<PrimOut, SaveError> {
    let mut ops = Vec::with_capacity(log.len());
    let mut types = Vec::with_capacity(log.len());
    for op in log.ops() {
        ops.push(to_json(op)?);
        types.push(op.name().into());
    }
    let snapshot = to_json(log.document())?;
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
