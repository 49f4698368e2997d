//! The op schema: a machine-readable description of every op (its fields,
//! their types, units, ranges, defaults and docs), generated from the op
//! declarations themselves (`schemars` reads the same types, serde
//! attributes and doc comments that define the wire format), so it cannot
//! drift from what the core accepts.
//!
//! - [`op_schema`]: the description the hosts build their UI from (Blender
//!   operators and tooltips, the headset palette), also printed by
//!   `shapewright-xr ops --json`.
//! - [`check_op`]: the door check every op passes before it applies: every
//!   number finite, lengths (`x-unit: m`) within [`MAX_LENGTH`] of the
//!   origin, everything within [`MAX_MAGNITUDE`], refused with the field's
//!   path. The declared ranges are enforced by the geometry code, with its
//!   own typed errors (a test checks every declared bound is refused).
//!
//! Schema extensions used by the declarations: `x-unit` (`m`, `rad`),
//! `x-ref` (what an integer names: `object`, `part`, `section`, `curve`,
//! `patch`, `operand`).

use std::sync::OnceLock;

use serde_json::{json, Map, Value};

use super::ops::{Op, OP_KINDS};
use super::OpError;

/// The largest magnitude a length (a field with `x-unit: m`) may have, in
/// metres: 10 km. Anything larger is a unit mistake or lost tracking, and
/// would overflow the grids and meshes built from it.
pub const MAX_LENGTH: f64 = 1e4;

/// The largest magnitude of any other number: beyond it, products of two
/// such numbers overflow `f64`.
pub const MAX_MAGNITUDE: f64 = 1e15;

/// The JSON Schema of [`Op`] (draft 2020-12, as `schemars` writes it).
pub fn op_json_schema() -> &'static Value {
    static SCHEMA: OnceLock<Value> = OnceLock::new();
    SCHEMA.get_or_init(|| {
        serde_json::to_value(schemars::schema_for!(Op)).unwrap_or_else(|_| json!({}))
    })
}

fn defs() -> &'static Map<String, Value> {
    static EMPTY: OnceLock<Map<String, Value>> = OnceLock::new();
    op_json_schema()
        .get("$defs")
        .and_then(Value::as_object)
        .unwrap_or_else(|| EMPTY.get_or_init(Map::new))
}

/// `schema` with a top-level `$ref` replaced by its definition (and the
/// siblings of the `$ref` kept).
fn resolve(schema: &Value) -> &Value {
    let mut s = schema;
    for _ in 0..16 {
        match s.get("$ref").and_then(Value::as_str) {
            Some(r) => match r.strip_prefix("#/$defs/").and_then(|n| defs().get(n)) {
                Some(d) => s = d,
                None => return s,
            },
            None => return s,
        }
    }
    s
}

/// The object schema of one op's payload (its `"op"` tag included), with
/// `allOf` parts and references merged into one `properties` map.
fn op_object_schema(name: &str) -> Option<Map<String, Value>> {
    static BY_NAME: OnceLock<Vec<(String, Map<String, Value>)>> = OnceLock::new();
    let all = BY_NAME.get_or_init(|| {
        let mut out = Vec::new();
        for branch in op_json_schema()
            .get("oneOf")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            let merged = merge_object(branch);
            let tag = merged
                .get("properties")
                .and_then(|p| p.get("op"))
                .and_then(|t| t.get("const"))
                .and_then(Value::as_str)
                .map(str::to_owned);
            if let Some(tag) = tag {
                out.push((tag, merged));
            }
        }
        out
    });
    all.iter().find(|(n, _)| n == name).map(|(_, s)| s.clone())
}

/// Merges `$ref` and `allOf` parts of an object schema (and the siblings
/// of a `$ref`) into one map with one `properties` and one `required`.
fn merge_object(schema: &Value) -> Map<String, Value> {
    fn collect(
        s: &Value,
        out: &mut Map<String, Value>,
        props: &mut Map<String, Value>,
        required: &mut Vec<Value>,
        depth: u32,
    ) {
        if depth > 16 {
            return;
        }
        if let Some(p) = s.get("properties").and_then(Value::as_object) {
            for (k, v) in p {
                props.entry(k.clone()).or_insert_with(|| v.clone());
            }
        }
        if let Some(r) = s.get("required").and_then(Value::as_array) {
            for x in r {
                if !required.contains(x) {
                    required.push(x.clone());
                }
            }
        }
        if let Some(o) = s.as_object() {
            for (k, v) in o {
                if !matches!(k.as_str(), "properties" | "required" | "allOf" | "$ref") {
                    out.entry(k.clone()).or_insert_with(|| v.clone());
                }
            }
        }
        if s.get("$ref").is_some() {
            let r = resolve(&json!({"$ref": s["$ref"]})).clone();
            collect(&r, out, props, required, depth + 1);
        }
        for part in s
            .get("allOf")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            collect(part, out, props, required, depth + 1);
        }
    }
    let mut out = Map::new();
    let mut props = Map::new();
    let mut required = Vec::new();
    collect(schema, &mut out, &mut props, &mut required, 0);
    out.insert("properties".into(), Value::Object(props));
    out.insert("required".into(), Value::Array(required));
    out
}

/// True when op `name` has a field called `field`.
pub fn op_has_field(name: &str, field: &str) -> bool {
    op_object_schema(name)
        .and_then(|s| s.get("properties").map(|p| p.get(field).is_some()))
        .unwrap_or(false)
}

/// The host-facing description of every op, in table order:
/// `{"format_version", "version_key", "max_length", "ops": [{"name", "kind",
/// "doc", "fields": [{"name", "doc", "required", "default", "unit",
/// "minimum", "maximum", "exclusiveMinimum", "ref", "schema"}]}], "defs"}`.
/// `schema` is the field's JSON Schema (references point into `defs`).
pub fn op_schema() -> Value {
    let ops: Vec<Value> = OP_KINDS
        .iter()
        .map(|&(name, kind)| {
            let s = op_object_schema(name).unwrap_or_default();
            let required: Vec<&str> = s
                .get("required")
                .and_then(Value::as_array)
                .map(|r| r.iter().filter_map(Value::as_str).collect())
                .unwrap_or_default();
            let fields: Vec<Value> = s
                .get("properties")
                .and_then(Value::as_object)
                .map(|p| {
                    p.iter()
                        .filter(|(k, _)| k.as_str() != "op")
                        .map(|(k, v)| field_entry(k, v, required.contains(&k.as_str())))
                        .collect()
                })
                .unwrap_or_default();
            json!({
                "name": name,
                "kind": kind,
                "doc": s.get("description").cloned().unwrap_or(Value::Null),
                "fields": fields,
            })
        })
        .collect();
    json!({
        "format_version": super::OP_FORMAT_VERSION,
        "version_key": super::script::VERSION_KEY,
        "max_length": MAX_LENGTH,
        "ops": ops,
        "defs": Value::Object(defs().clone()),
    })
}

fn field_entry(name: &str, schema: &Value, required: bool) -> Value {
    let r = resolve(schema);
    let pick = |k: &str| {
        schema
            .get(k)
            .or_else(|| r.get(k))
            .cloned()
            .unwrap_or(Value::Null)
    };
    json!({
        "name": name,
        "doc": pick("description"),
        "required": required,
        "default": pick("default"),
        "unit": pick("x-unit"),
        "minimum": pick("minimum"),
        "maximum": pick("maximum"),
        "exclusiveMinimum": pick("exclusiveMinimum"),
        "ref": pick("x-ref"),
        "schema": schema,
    })
}

/// Checks every number of `op` against its schema: finite (a NaN or an
/// infinity serializes as `null` where a number is declared), lengths
/// within [`MAX_LENGTH`], everything within [`MAX_MAGNITUDE`]. The error
/// names the op and the field's path.
pub fn check_op(op: &Op) -> Result<(), OpError> {
    let value = serde_json::to_value(op).map_err(|e| OpError::BadField {
        op: op.name(),
        field: String::new(),
        problem: format!("cannot be encoded: {e}"),
    })?;
    let Some(schema) = op_object_schema(op.name()) else {
        return Ok(());
    };
    let mut path = String::new();
    check_value(&value, &Value::Object(schema), &mut path, None).map_err(|problem| {
        OpError::BadField {
            op: op.name(),
            field: path.trim_start_matches('.').to_string(),
            problem,
        }
    })
}

/// Walks `value` along `schema`. On error `path` holds the failing field.
fn check_value(
    value: &Value,
    schema: &Value,
    path: &mut String,
    unit: Option<&str>,
) -> Result<(), String> {
    let s = resolve(schema);
    let unit = s
        .get("x-unit")
        .or_else(|| schema.get("x-unit"))
        .and_then(Value::as_str)
        .or(unit);
    if let Some(all) = s.get("allOf").and_then(Value::as_array) {
        for part in all {
            check_value(value, part, path, unit)?;
        }
    }
    for key in ["oneOf", "anyOf"] {
        if let Some(branches) = s.get(key).and_then(Value::as_array) {
            if let Some(b) = pick_branch(value, branches) {
                check_value(value, b, path, unit)?;
            }
        }
    }
    let types = type_names(s);
    match value {
        Value::Null
            if types.iter().any(|t| *t == "number" || *t == "integer")
                && !types.contains(&"null") =>
        {
            return Err("is not a finite number (NaN or infinity: tracking lost?)".into());
        }
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            check_number(x, unit)?;
        }
        Value::Array(items) => {
            let prefix = s.get("prefixItems").and_then(Value::as_array);
            let rest = s.get("items");
            for (i, item) in items.iter().enumerate() {
                let sub = prefix.and_then(|p| p.get(i)).or(rest);
                if let Some(sub) = sub {
                    let len = path.len();
                    path.push_str(&format!("[{i}]"));
                    check_value(item, sub, path, unit)?;
                    path.truncate(len);
                }
            }
        }
        Value::Object(fields) => {
            if let Some(props) = s.get("properties").and_then(Value::as_object) {
                for (k, v) in fields {
                    if let Some(sub) = props.get(k) {
                        let len = path.len();
                        path.push('.');
                        path.push_str(k);
                        check_value(v, sub, path, None)?;
                        path.truncate(len);
                    }
                }
            }
        }
        _ => {}
    }
    Ok(())
}

fn type_names(s: &Value) -> Vec<&str> {
    match s.get("type") {
        Some(Value::String(t)) => vec![t.as_str()],
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    }
}

/// The branch of a tagged union that `value` is: the one whose `const`
/// properties all match. `None` when no single branch is certain (then
/// nothing below is checked: the check never refuses what serde accepts,
/// except numbers).
fn pick_branch<'a>(value: &Value, branches: &'a [Value]) -> Option<&'a Value> {
    let mut found = None;
    for b in branches {
        let rb = resolve(b);
        let Some(props) = rb.get("properties").and_then(Value::as_object) else {
            // A branch that is a bare number or array (e.g. `Option<T>`).
            if branches.len() == 2 && value.is_null() == (type_names(rb) == ["null"]) {
                return Some(b);
            }
            continue;
        };
        let consts: Vec<(&String, &Value)> = props
            .iter()
            .filter_map(|(k, v)| resolve(v).get("const").map(|c| (k, c)))
            .collect();
        if consts.is_empty() {
            continue;
        }
        if consts
            .iter()
            .all(|(k, c)| value.get(k.as_str()) == Some(*c))
        {
            if found.is_some() {
                return None;
            }
            found = Some(b);
        }
    }
    found
}

fn check_number(x: f64, unit: Option<&str>) -> Result<(), String> {
    if !x.is_finite() {
        return Err("is not a finite number".into());
    }
    if unit == Some("m") && x.abs() > MAX_LENGTH {
        return Err(format!(
            "is {x} m, farther than {MAX_LENGTH} m: a unit mistake or lost tracking?"
        ));
    }
    if x.abs() > MAX_MAGNITUDE {
        return Err(format!(
            "is {x}, beyond the largest magnitude {MAX_MAGNITUDE}"
        ));
    }
    Ok(())
}
