//! A form's values as its op (or the ops applied as one step): section
//! templates as profiles, placements as transforms, sketches through the
//! sketch pipeline the headset's GC tool runs. The values are checked only
//! as far as building needs (a number where a number goes); the op's own
//! checks, when it is applied, refuse bad sizes and ranges by field name.

use serde_json::{json, Map, Value};

use super::table::{form_named, Build, FieldKind};
use crate::doc::{Document, ObjectId, ObjectKind, Op};
use crate::gc::{GcAssembly, Profile, Resolution};
use crate::interact::tools::gc_tool::GcToolSettings;
use crate::math::DVec3;
use crate::sketch::{
    child_from_stroke, match_section_stroke, profile_radius, replace_spine_from_stroke,
    sketch_spine, ChildSettings, EndChoice, SectionSettings, SketchError, SketchPlane,
};
use crate::solid::SolidShape;

/// Why a form's values make no op.
#[derive(Debug, thiserror::Error)]
pub enum FormError {
    /// No form has this name.
    #[error("no form for op `{0}`")]
    Unknown(String),
    /// A field is missing.
    #[error("give {field}")]
    Missing {
        /// The form.
        op: &'static str,
        /// The field.
        field: &'static str,
    },
    /// A field's value is of the wrong kind.
    #[error("{field} must be {want}")]
    Bad {
        /// The form.
        op: &'static str,
        /// The field.
        field: String,
        /// What it must be.
        want: &'static str,
    },
    /// The sketch makes no such part.
    #[error("{source}")]
    Sketch {
        /// The form.
        op: &'static str,
        /// Why.
        source: SketchError,
    },
    /// The sizes make no section or solid, or the target is not there.
    #[error("{why}")]
    Refused {
        /// The form.
        op: &'static str,
        /// Why.
        why: String,
    },
    /// The values built something that is not an op (a wrong type in a
    /// nested value).
    #[error("{why}")]
    NotAnOp {
        /// The form.
        op: &'static str,
        /// serde's message.
        why: String,
    },
}

/// The tolerance of a part's attachment to its parent (metres).
const ATTACH_TOLERANCE: f64 = 1e-4;
/// How far a straight stub starts inside its parent (metres).
const STUB_SINK: f64 = 0.004;

/// Reads one form's values.
struct Values<'a> {
    op: &'static str,
    map: &'a Map<String, Value>,
}

impl<'a> Values<'a> {
    fn get(&self, field: &'static str) -> Result<&'a Value, FormError> {
        self.map
            .get(field)
            .ok_or(FormError::Missing { op: self.op, field })
    }
    fn bad(&self, field: &str, want: &'static str) -> FormError {
        FormError::Bad {
            op: self.op,
            field: field.to_string(),
            want,
        }
    }
    fn num(&self, field: &'static str) -> Result<f64, FormError> {
        self.get(field)?
            .as_f64()
            .ok_or_else(|| self.bad(field, "a number"))
    }
    fn text(&self, field: &'static str) -> Result<&'a str, FormError> {
        self.get(field)?
            .as_str()
            .ok_or_else(|| self.bad(field, "text"))
    }
    fn vec3(&self, field: &'static str) -> Result<DVec3, FormError> {
        let a = self.get(field)?.as_array().filter(|a| a.len() == 3);
        let xs: Option<Vec<f64>> = a.and_then(|a| a.iter().map(Value::as_f64).collect());
        match xs {
            Some(x) => Ok(DVec3::new(x[0], x[1], x[2])),
            None => Err(self.bad(field, "three numbers")),
        }
    }
    /// A sketch: points `[[x, y, z], ...]` (empty text or list: none).
    fn points(&self) -> Result<Vec<DVec3>, FormError> {
        let v = self.get("points")?;
        if v.as_str() == Some("") || v.is_null() {
            return Ok(Vec::new());
        }
        let bad = || self.bad("points", "a list of points [x, y, z]");
        let a = v.as_array().ok_or_else(bad)?;
        a.iter()
            .map(|p| {
                let p = p.as_array().filter(|p| p.len() == 3).ok_or_else(bad)?;
                let x: Option<Vec<f64>> = p.iter().map(Value::as_f64).collect();
                let x = x.ok_or_else(bad)?;
                Ok(DVec3::new(x[0], x[1], x[2]))
            })
            .collect()
    }
    fn raw(&self, field: &'static str) -> Result<Value, FormError> {
        self.get(field).cloned()
    }
    fn sketch(&self, e: SketchError) -> FormError {
        FormError::Sketch {
            op: self.op,
            source: e,
        }
    }
    fn refused(&self, why: impl ToString) -> FormError {
        FormError::Refused {
            op: self.op,
            why: why.to_string(),
        }
    }
}

fn arr(p: DVec3) -> Value {
    json!([p.x, p.y, p.z])
}

/// A GC section profile from the template fields.
fn profile(v: &Values) -> Result<Value, FormError> {
    let (a, b) = (v.num("size_a")?, v.num("size_b")?);
    Ok(match v.text("template")? {
        "circle" => json!({"template": "circle", "radius": a}),
        "ellipse" => json!({"template": "ellipse", "rx": a, "ry": b}),
        "polygon" => json!({"template": "polygon", "sides": v.raw("sides")?, "radius": a}),
        "rectangle" => json!({"template": "rectangle", "width": a, "height": b}),
        _ => return Err(v.bad("template", "circle, ellipse, polygon or rectangle")),
    })
}

fn shape_type(v: &Values) -> Result<Value, FormError> {
    Ok(match v.text("shape_type")? {
        "solid" => json!({"type": "solid"}),
        "shell" => json!({"type": "shell", "thickness": v.raw("thickness")?}),
        "container" => json!({
            "type": "container",
            "thickness": v.raw("thickness")?,
            "closed_end": v.raw("closed_end")?,
        }),
        _ => return Err(v.bad("shape_type", "solid, shell or container")),
    })
}

/// Location (or `at`), rotation and scale as a transform (identity where
/// the form has no such field).
fn transform_at(v: &Values, at: &'static str) -> Result<Value, FormError> {
    let or = |k: &'static str, d: Value| v.map.get(k).cloned().unwrap_or(d);
    Ok(json!({
        "translate": v.raw(at)?,
        "rotate": or("rotation", json!([0.0, 0.0, 0.0, 1.0])),
        "scale": or("scale", json!([1.0, 1.0, 1.0])),
    }))
}

fn transform(v: &Values) -> Result<Value, FormError> {
    transform_at(v, "location")
}

fn sections_at(p: &Value, params: &[f64]) -> Value {
    params
        .iter()
        .map(|t| json!({"profile": p, "v": t, "scale": 1.0, "twist": 0.0}))
        .collect()
}

/// Any direction not parallel to `normal` (a sketch plane's x axis).
fn x_hint(n: DVec3) -> DVec3 {
    let len = n.length();
    if n.x.abs() < 0.9 * if len > 0.0 { len } else { 1.0 } {
        DVec3::X
    } else {
        DVec3::Y
    }
}

/// The radius a profile reaches, for fitting a spine to it.
fn reach(v: &Values, p: &Value) -> Result<f64, FormError> {
    let prof: Profile = serde_json::from_value(p.clone()).map_err(|e| v.refused(e))?;
    prof.curve().map_err(|e| v.refused(e))?;
    Ok(profile_radius(&prof))
}

fn plane(v: &Values, origin: DVec3, normal: DVec3) -> Result<SketchPlane, FormError> {
    SketchPlane::new(origin, normal, x_hint(normal)).map_err(|e| v.sketch(e))
}

fn assembly<'d>(v: &Values, doc: Option<&'d Document>) -> Result<&'d GcAssembly, FormError> {
    let doc = doc.ok_or_else(|| v.refused("a sketch on a part needs the document"))?;
    let id = v
        .get("id")?
        .as_u64()
        .ok_or_else(|| v.bad("id", "an object id"))?;
    let id = u32::try_from(id).map_err(|_| v.bad("id", "an object id"))?;
    let obj = doc.get(ObjectId(id)).map_err(|e| v.refused(e))?;
    match &obj.kind {
        ObjectKind::GcAssembly(a) => Ok(a),
        other => Err(v.refused(format!(
            "object {id} is a {}, not a generalized-cylinder assembly",
            other.name()
        ))),
    }
}

fn gc_create(v: &Values) -> Result<Value, FormError> {
    let p = profile(v)?;
    let stroke = v.points()?;
    let (spine, normal, params) = if let Some(first) = stroke.first() {
        let pl = plane(v, *first, v.vec3("plane_normal")?)?;
        let sk = sketch_spine(&stroke, &pl, reach(v, &p)?, &SectionSettings::default())
            .map_err(|e| v.sketch(e))?;
        let spine: Vec<Value> = sk.points.iter().map(|q| arr(*q)).collect();
        (json!(spine), arr(sk.plane_normal), sk.plan.params)
    } else {
        let at = v.vec3("location")?;
        let end = at + DVec3::Z * v.num("length")?;
        (
            json!([arr(at), arr(end)]),
            v.raw("plane_normal")?,
            vec![0.0, 1.0],
        )
    };
    Ok(json!({
        "op": "gc_create",
        "spine": spine,
        "plane_normal": normal,
        "sections": sections_at(&p, &params),
        "shape": shape_type(v)?,
        "resolution": {"u": v.raw("res_u")?, "v": v.raw("res_v")?},
    }))
}

fn gc_add_child(v: &Values, doc: Option<&Document>) -> Result<Value, FormError> {
    let p = profile(v)?;
    let res = Resolution::DEFAULT;
    let mut out = json!({
        "op": "gc_add_child",
        "id": v.raw("id")?,
        "tolerance": ATTACH_TOLERANCE,
        "shape": shape_type(v)?,
        "resolution": {"u": res.u, "v": res.v},
    });
    let stroke = v.points()?;
    let more = if stroke.is_empty() {
        let end = if v.text("end")? == "parent" {
            "parent"
        } else {
            "free"
        };
        json!({
            "parent": v.raw("parent")?,
            "at": v.raw("at")?,
            "spine": [[-STUB_SINK, 0.0], [v.num("length")?, 0.0]],
            "end": end,
            "end_tolerance": ATTACH_TOLERANCE,
            "sections": sections_at(&p, &[0.0, 1.0]),
        })
    } else {
        let end = match v.text("end")? {
            "auto" => EndChoice::Auto,
            "free" => EndChoice::Free,
            "parent" => EndChoice::Parent,
            _ => return Err(v.bad("end", "auto, free or parent")),
        };
        let asm = assembly(v, doc)?;
        let c = child_from_stroke(asm, &stroke, reach(v, &p)?, end, &ChildSettings::default())
            .map_err(|e| v.sketch(e))?;
        json!({
            "parent": c.parent,
            "at": arr(c.at),
            "spine": c.spine,
            "end": if c.lands { "parent" } else { "free" },
            "end_tolerance": c.end_tolerance,
            "sections": sections_at(&p, &c.plan.params),
        })
    };
    if let (Some(o), Value::Object(m)) = (out.as_object_mut(), more) {
        o.extend(m);
    }
    Ok(out)
}

/// Key sections first where the new spine needs them (they keep the
/// current shape), then the spine, moved to start where it started.
fn gc_replace_spine(v: &Values, doc: Option<&Document>) -> Result<Vec<Value>, FormError> {
    let asm = assembly(v, doc)?;
    let part = v
        .get("part")?
        .as_u64()
        .ok_or_else(|| v.bad("part", "a part index"))?;
    let r = replace_spine_from_stroke(
        asm,
        part as usize,
        &v.points()?,
        &SectionSettings::default(),
    )
    .map_err(|e| v.sketch(e))?;
    let (id, part) = (v.raw("id")?, v.raw("part")?);
    let mut ops: Vec<Value> = r
        .insert_at
        .iter()
        .map(|t| json!({"op": "gc_insert_section", "id": id, "part": part, "v": t}))
        .collect();
    let points: Vec<Value> = r.points.iter().map(|q| arr(*q)).collect();
    ops.push(json!({
        "op": "gc_replace_spine",
        "id": id,
        "part": part,
        "points": points,
        "plane_normal": arr(r.plane_normal),
    }));
    Ok(ops)
}

fn gc_replace_section(v: &Values) -> Result<Value, FormError> {
    let stroke = v.points()?;
    let profile = if let Some(first) = stroke.first() {
        let pl = plane(v, *first, v.vec3("plane_normal")?)?;
        let m = match_section_stroke(&stroke, &pl).map_err(|e| v.sketch(e))?;
        // The headset's rule: the template when it matches well, else the
        // loop as drawn.
        let drawn = m.drawn(GcToolSettings::default().min_template_score);
        serde_json::to_value(drawn.profile).map_err(|e| v.refused(e))?
    } else {
        profile(v)?
    };
    Ok(json!({
        "op": "gc_replace_section",
        "id": v.raw("id")?,
        "part": v.raw("part")?,
        "section": v.raw("section")?,
        "profile": profile,
    }))
}

fn part_move(v: &Values) -> Result<Value, FormError> {
    let mut out = json!({
        "op": v.op,
        "id": v.raw("id")?,
        "part": v.raw("part")?,
        "translate": v.raw("location")?,
        "rotate": v.raw("rotation")?,
        "tolerance": ATTACH_TOLERANCE,
    });
    if v.op == "gc_copy" {
        out["mirror"] = v.raw("mirror")?;
    }
    Ok(out)
}

/// `curve_fill_loop`'s pieces from "curve from to" triples separated by
/// commas (e.g. "0 0 1, 1 0 1, 2 0 1").
fn pieces(v: &Values) -> Result<Value, FormError> {
    let mut out = Vec::new();
    for chunk in v.text("pieces")?.split(',') {
        let chunk = chunk.trim();
        if chunk.is_empty() {
            continue;
        }
        // Digits only ("+1" is not a node number).
        let nums: Vec<u64> = chunk
            .split_whitespace()
            .map(|n| {
                if n.bytes().all(|b| b.is_ascii_digit()) {
                    n.parse::<u64>().ok()
                } else {
                    None
                }
            })
            .collect::<Option<_>>()
            .unwrap_or_default();
        if nums.len() != 3 || chunk.split_whitespace().count() != 3 {
            return Err(v.refused(format!(
                "pieces: each is three whole numbers 'curve from to', got '{chunk}'"
            )));
        }
        out.push(json!({"curve": nums[0], "from": nums[1], "to": nums[2]}));
    }
    Ok(json!({"op": "curve_fill_loop", "id": v.raw("id")?, "pieces": out}))
}

/// A parametric solid from its kind and bounding box (the core's one
/// mapping, `SolidShape::from_sizes`).
fn solid(v: &Values) -> Result<Value, FormError> {
    let d = v.vec3("dimensions")?;
    let shape = SolidShape::from_sizes(v.text("shape")?, d.to_array()).map_err(|e| v.refused(e))?;
    serde_json::to_value(shape).map_err(|e| v.refused(e))
}

fn add_solid(v: &Values) -> Result<Value, FormError> {
    let at = json!({
        "translate": v.raw("location")?,
        "rotate": v.raw("rotation")?,
        "scale": [1.0, 1.0, 1.0],
    });
    Ok(json!({
        "op": "add_solid",
        "shape": solid(v)?,
        "segments": v.raw("segments")?,
        "transform": at,
    }))
}

fn sdf_add(v: &Values) -> Result<Value, FormError> {
    let component = match v.text("component")? {
        "library" => json!({"kind": "library", "name": v.raw("library")?}),
        "solid" => json!({"kind": "solid", "shape": solid(v)?}),
        _ => return Err(v.bad("component", "library or solid")),
    };
    Ok(json!({
        "op": "sdf_add_operand",
        "volume": v.raw("volume")?,
        "component": component,
        "csg": v.raw("csg")?,
        "transform": transform(v)?,
    }))
}

fn operand_transform(v: &Values) -> Result<Value, FormError> {
    Ok(json!({
        "op": v.op,
        "volume": v.raw("volume")?,
        "operand": v.raw("operand")?,
        "transform": transform(v)?,
    }))
}

fn sdf_two_hand(v: &Values) -> Result<Value, FormError> {
    Ok(json!({
        "op": "sdf_scale_two_hand",
        "volume": v.raw("volume")?,
        "operand": v.raw("operand")?,
        "axis": v.raw("axis")?,
        "hands_start": [v.raw("left_start")?, v.raw("right_start")?],
        "hands_end": [v.raw("left_end")?, v.raw("right_end")?],
    }))
}

/// A component from the mesh the host read: `{"name", "positions",
/// "triangles"}`; the form's own name wins when given.
fn import_component(v: &Values) -> Result<Value, FormError> {
    let mesh = v.get("mesh")?;
    let part = |k: &'static str| {
        mesh.get(k)
            .cloned()
            .ok_or_else(|| v.bad("mesh", "{name, positions, triangles} read by the host"))
    };
    let name = match v.text("name")? {
        "" => part("name")?,
        given => json!(given),
    };
    Ok(json!({
        "op": "sdf_import_component",
        "volume": v.raw("volume")?,
        "name": name,
        "positions": part("positions")?,
        "triangles": part("triangles")?,
    }))
}

fn curve_draw(v: &Values) -> Result<Value, FormError> {
    let fit = match v.text("fit")? {
        "interpolate" => json!({"mode": "interpolate"}),
        "approximate" => json!({"mode": "approximate", "tol": v.raw("tol")?}),
        _ => return Err(v.bad("fit", "interpolate or approximate")),
    };
    let resample = v.num("resample")?;
    let samples: Vec<Value> = v.points()?.iter().map(|q| arr(*q)).collect();
    Ok(json!({
        "op": "curve_draw",
        "id": v.raw("id")?,
        "samples": samples,
        "fit": fit,
        "resample": if resample > 0.0 { json!(resample) } else { Value::Null },
        "snap_tol": v.raw("snap_tol")?,
    }))
}

fn sculpt_create(v: &Values) -> Result<Value, FormError> {
    let a = v.num("size_a")?;
    let edge = v.raw("edge_length")?;
    let base = match v.text("base")? {
        "sphere" => json!({"kind": "sphere", "radius": a, "edge_length": edge}),
        "box" => json!({"kind": "box", "size": [a * 2.0, a * 2.0, a * 2.0], "edge_length": edge}),
        _ => return Err(v.bad("base", "sphere or box")),
    };
    Ok(json!({"op": "sculpt_create", "base": base, "transform": transform(v)?}))
}

fn sculpt_stroke(v: &Values) -> Result<Value, FormError> {
    let samples: Vec<Value> = v
        .points()?
        .iter()
        .map(|q| json!({"position": arr(*q), "rotation": [0.0, 0.0, 0.0, 1.0], "pressure": 1.0}))
        .collect();
    Ok(json!({
        "op": "sculpt_stroke",
        "id": v.raw("id")?,
        "settings": v.raw("settings")?,
        "samples": samples,
    }))
}

/// A styling tool's op: its values, and the sketch as its `path`.
fn path_op(v: &Values, fields: &[&'static str]) -> Result<Value, FormError> {
    let others: Vec<&'static str> = fields.iter().copied().filter(|f| *f != "points").collect();
    let mut out = verbatim(v, &others)?;
    let path: Vec<Value> = v.points()?.iter().map(|q| arr(*q)).collect();
    out["path"] = json!(path);
    Ok(out)
}

/// The op's fields as they are.
fn verbatim(v: &Values, fields: &[&'static str]) -> Result<Value, FormError> {
    let mut out = Map::new();
    out.insert("op".into(), json!(v.op));
    for f in fields {
        out.insert((*f).into(), v.raw(f)?);
    }
    Ok(Value::Object(out))
}

/// The op (or the ops applied as one step) that form `op` makes of
/// `values` (field name -> value: metres, quaternions, points as lists).
/// `doc` is needed only for a sketch on an existing object (a child part,
/// a new spine).
pub fn build(
    op: &str,
    values: &Map<String, Value>,
    doc: Option<&Document>,
) -> Result<Vec<Op>, FormError> {
    let form = form_named(op).ok_or_else(|| FormError::Unknown(op.to_string()))?;
    let v = Values {
        op: form.op,
        map: values,
    };
    let names: Vec<&'static str> = form.fields.iter().map(|f| f.name).collect();
    let built: Vec<Value> = match (form.build, form.op) {
        (Build::Verbatim, _) => vec![verbatim(&v, &names)?],
        (_, "gc_create") => vec![gc_create(&v)?],
        (_, "gc_add_child") => vec![gc_add_child(&v, doc)?],
        (_, "gc_replace_spine") => gc_replace_spine(&v, doc)?,
        (_, "gc_replace_section") => vec![gc_replace_section(&v)?],
        (_, "gc_delete_section") => vec![verbatim(&v, &["id", "part", "section"])?],
        (_, "gc_set_shape") => {
            let mut o = verbatim(&v, &["id", "part"])?;
            o["shape"] = shape_type(&v)?;
            vec![o]
        }
        (_, "gc_copy" | "gc_transform_part") => vec![part_move(&v)?],
        (_, "sdf_add_operand") => vec![sdf_add(&v)?],
        (_, "sdf_set_operand_transform" | "sdf_copy_operand") => vec![operand_transform(&v)?],
        (_, "sdf_scale_two_hand") => vec![sdf_two_hand(&v)?],
        (_, "sdf_import_component") => vec![import_component(&v)?],
        (_, "curve_draw") => vec![curve_draw(&v)?],
        (_, "curve_fill_loop") => vec![pieces(&v)?],
        (_, "sculpt_create") => vec![sculpt_create(&v)?],
        (_, "sculpt_stroke") => vec![sculpt_stroke(&v)?],
        (_, "add_solid") => vec![add_solid(&v)?],
        (_, "edit_solid") => {
            let mut o = verbatim(&v, &["id", "segments"])?;
            o["shape"] = solid(&v)?;
            vec![o]
        }
        (_, "transform_by") => {
            let mut o = verbatim(&v, &["id"])?;
            o["transform"] = transform_at(&v, "offset")?;
            vec![o]
        }
        (_, _) if form.fields.iter().any(|f| f.kind == FieldKind::Points) => {
            vec![path_op(&v, &names)?]
        }
        (_, other) => return Err(FormError::Unknown(other.to_string())),
    };
    built
        .into_iter()
        .map(|o| {
            serde_json::from_value::<Op>(o).map_err(|e| FormError::NotAnOp {
                op: form.op,
                why: e.to_string(),
            })
        })
        .collect()
}
