//! Forms against the op vocabulary: every form's defaults, and each of its
//! choices, build ops the core takes; sketches build what the sketch
//! pipeline says and apply; bad values are refused by field name.

use serde_json::{json, Map, Value};

use super::{build, forms, Build, FieldKind, FormError};
use crate::doc::schema::op_schema;
use crate::doc::{ObjectId, ObjectKind, Op, OpLog, OP_NAMES};
use crate::math::fm::DetMath as _;
use crate::math::DVec3;

/// A form's default values, as a host sends them: targets resolved to
/// `target`, no sketch, a one-triangle-fan tetrahedron for a mesh field.
fn defaults(form: &super::Form, target: u32) -> Map<String, Value> {
    form.fields
        .iter()
        .map(|f| {
            let v = match f.kind {
                FieldKind::Target => json!(target),
                FieldKind::Points => json!([]),
                FieldKind::Mesh => json!({
                    "name": "tet",
                    "positions": [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]],
                    "triangles": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                }),
                _ => f.default.clone(),
            };
            (f.name.to_string(), v)
        })
        .collect()
}

/// The schema field a form field stands for exists: the op's own field,
/// or the `like` path into an op or a type of the schema's `defs`.
fn schema_has(schema: &Value, op: &str, name: &str, like: &[&str]) -> bool {
    let ops = schema["ops"].as_array().unwrap();
    let op_field = |o: &str, f: &str| {
        ops.iter()
            .find(|x| x["name"] == o)
            .and_then(|x| x["fields"].as_array())
            .is_some_and(|fs| fs.iter().any(|x| x["name"] == f))
    };
    match like {
        [] => op_field(op, name),
        [ty, member] if ty.starts_with('@') => {
            let text = schema["defs"][&ty[1..]].to_string();
            text.contains(&format!("\"{member}\""))
        }
        [o, f, ..] => op_field(o, f),
        _ => false,
    }
}

#[test]
fn every_form_builds_ops_the_core_takes_from_its_defaults_and_each_choice() {
    let schema = op_schema();
    let (mut built, mut refused) = (0, 0);
    for form in forms() {
        assert!(OP_NAMES.contains(&form.op), "{}: not an op", form.op);
        for f in &form.fields {
            let host_only = matches!(
                f.kind,
                FieldKind::Target | FieldKind::Points | FieldKind::Mesh | FieldKind::Pieces
            ) || !f.doc.is_empty();
            assert!(
                host_only || schema_has(&schema, form.op, f.name, &f.like),
                "{}.{}: stands for no schema field ({:?})",
                form.op,
                f.name,
                f.like
            );
            if f.kind == FieldKind::Enum {
                assert!(
                    f.items.contains(&f.default.as_str().unwrap()),
                    "{}.{}",
                    form.op,
                    f.name
                );
            }
        }
        if form.needs_points && form.build == Build::Sketch {
            continue; // built from a stroke on a part: below
        }
        let base = defaults(&form, 0);
        let mut variants = vec![("", base.clone())];
        for f in form.fields.iter().filter(|f| f.kind == FieldKind::Enum) {
            for item in &f.items {
                let mut v = base.clone();
                v.insert(f.name.into(), json!(item));
                variants.push((f.name, v));
            }
        }
        for (changed, values) in variants {
            match build(form.op, &values, None) {
                Ok(ops) => {
                    assert_eq!(ops.len(), 1, "{}", form.op);
                    assert_eq!(ops[0].name(), form.op);
                    built += 1;
                }
                // A 10 cm cube's sizes make no torus (its tube would fill
                // the hole): refused, saying which size to change.
                Err(FormError::Refused { why, .. })
                    if changed == "shape" && why.contains("torus") =>
                {
                    refused += 1;
                }
                Err(e) => panic!("{}: {e} from {values:?}", form.op),
            }
        }
    }
    assert_eq!(
        refused, 2,
        "add_solid and edit_solid refuse the default torus"
    );
    assert!(built > 60, "{built} variants built");
}

/// A document with one GC: a 20 cm tube of radius 4 cm along +z at x 0.5.
fn gc_doc() -> OpLog {
    let mut log = OpLog::new();
    let sections: Vec<Value> = [0.0, 0.4, 0.6, 1.0]
        .iter()
        .map(|v| json!({"profile": {"template": "circle", "radius": 0.04}, "v": v}))
        .collect();
    let op: Op = serde_json::from_value(json!({
        "op": "gc_create",
        "spine": [[0.5, 0.0, 0.0], [0.5, 0.0, 0.2]],
        "plane_normal": [0.0, 1.0, 0.0],
        "sections": sections,
    }))
    .unwrap();
    log.apply(op).unwrap();
    log
}

fn pts(points: impl IntoIterator<Item = DVec3>) -> Value {
    points.into_iter().map(|p| json!([p.x, p.y, p.z])).collect()
}

#[test]
fn a_sketched_spout_and_a_new_spine_build_and_apply() {
    let mut log = gc_doc();
    let forms = forms();
    let form = |op: &str| forms.iter().find(|f| f.op == op).unwrap();
    // A spout: from the tube's side (x 0.54) outwards and up, ending free.
    let mut v = defaults(form("gc_add_child"), 1);
    let stroke = (0..=20).map(|i| {
        let t = f64::from(i) / 20.0;
        DVec3::new(0.539 + 0.08 * t, 0.0, 0.1 + 0.05 * t * t)
    });
    v.insert("points".into(), pts(stroke));
    let ops = build("gc_add_child", &v, Some(log.document())).unwrap();
    let Op::GcAddChild(child) = &ops[0] else {
        panic!("{ops:?}")
    };
    assert_eq!(
        serde_json::to_value(child).unwrap()["end"],
        json!("free"),
        "a stroke ending away from the part is a spout"
    );
    log.apply(ops[0].clone()).unwrap();
    let ObjectKind::GcAssembly(a) = &log.document().get(ObjectId(1)).unwrap().kind else {
        panic!()
    };
    assert_eq!(a.parts.len(), 2);

    // Without the document a sketch on a part is refused, typed.
    let e = build("gc_add_child", &v, None).unwrap_err();
    assert!(matches!(e, FormError::Refused { .. }), "{e}");

    // A new spine for the body: a bow in its spine plane (y normal).
    let mut v = defaults(form("gc_replace_spine"), 1);
    let bow = (0..=30).map(|i| {
        let t = f64::from(i) / 30.0;
        DVec3::new(0.5 + 0.06 * (std::f64::consts::PI * t).fsin(), 0.0, 0.3 * t)
    });
    v.insert("points".into(), pts(bow));
    let ops = build("gc_replace_spine", &v, Some(log.document())).unwrap();
    let names: Vec<&str> = ops.iter().map(Op::name).collect();
    assert_eq!(names.last(), Some(&"gc_replace_spine"), "{names:?}");
    assert!(names[..names.len() - 1]
        .iter()
        .all(|n| *n == "gc_insert_section"));
    for op in ops {
        log.apply(op).unwrap();
    }
}

#[test]
fn a_sketched_loop_becomes_the_matched_template_or_itself() {
    let forms = forms();
    let form = forms.iter().find(|f| f.op == "gc_replace_section").unwrap();
    let ring = |n: usize, r: f64| -> Value {
        pts((0..n).map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            DVec3::new(r * a.fcos(), r * a.fsin(), 0.1)
        }))
    };
    let mut v = defaults(form, 1);
    v.insert("points".into(), ring(64, 0.03));
    let op = build("gc_replace_section", &v, None).unwrap().remove(0);
    let profile = serde_json::to_value(&op).unwrap()["profile"].clone();
    assert_eq!(profile["template"], json!("circle"), "{profile}");
    // An L matches no template well: the loop as drawn.
    let corners = [
        (0.0, 0.0),
        (0.06, 0.0),
        (0.06, 0.012),
        (0.012, 0.012),
        (0.012, 0.06),
        (0.0, 0.06),
    ];
    let ell: Value = pts((0..corners.len() * 8).map(|k| {
        let (a, b) = (corners[k / 8], corners[(k / 8 + 1) % corners.len()]);
        let t = (k % 8) as f64 / 8.0;
        DVec3::new(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t, 0.1)
    }));
    v.insert("points".into(), ell);
    let op = build("gc_replace_section", &v, None).unwrap().remove(0);
    let profile = serde_json::to_value(&op).unwrap()["profile"].clone();
    assert_eq!(profile["template"], json!("points"), "{profile}");
}

#[test]
fn bad_values_are_refused_by_field_not_panicked_on() {
    let forms = forms();
    let form = |op: &str| forms.iter().find(|f| f.op == op).unwrap();
    let mut v = defaults(form("gc_create"), 0);
    v.insert("size_a".into(), json!("wide"));
    let e = build("gc_create", &v, None).unwrap_err();
    assert!(e.to_string().contains("size_a"), "{e}");
    v.remove("size_a");
    let e = build("gc_create", &v, None).unwrap_err();
    assert!(
        matches!(
            e,
            FormError::Missing {
                field: "size_a",
                ..
            }
        ),
        "{e}"
    );

    let mut v = defaults(form("curve_fill_loop"), 1);
    for bad in ["0 0", "0 0 1, a b c", "0 -1 2", "0 +1 2", "1 2 3 4"] {
        v.insert("pieces".into(), json!(bad));
        let e = build("curve_fill_loop", &v, None).unwrap_err();
        assert!(e.to_string().contains("three whole numbers"), "{bad}: {e}");
    }
    v.insert("pieces".into(), json!("0 0 1, 1 0 1 , 2 0 1,"));
    let Op::CurveFillLoop(fill) = &build("curve_fill_loop", &v, None).unwrap()[0] else {
        panic!()
    };
    assert_eq!(
        serde_json::to_value(fill).unwrap()["pieces"]
            .as_array()
            .unwrap()
            .len(),
        3
    );

    let mut v = defaults(form("gc_create"), 0);
    v.insert("points".into(), json!([[0.0, 0.0, 0.0], [f64::MAX, 0.0]]));
    let e = build("gc_create", &v, None).unwrap_err();
    assert!(e.to_string().contains("points"), "{e}");
    assert!(matches!(
        build("no_such_op", &v, None),
        Err(FormError::Unknown(_))
    ));

    // A value of the wrong type for the op: refused, saying the value
    // (serde's message: an internally tagged op loses the field's path; a
    // host's form checks ranges by field name first, and names itself).
    let mut v = defaults(form("gc_bend"), 1);
    v.insert("section".into(), json!(-1));
    let e = build("gc_bend", &v, None).unwrap_err();
    assert!(matches!(e, FormError::NotAnOp { .. }), "{e}");
    let text = e.to_string();
    assert!(text.contains("-1") && !text.starts_with("gc_bend"), "{e}");
}

#[test]
fn an_edit_form_starts_from_the_object_and_changes_nothing_applied_as_is() {
    let mut log = gc_doc();
    let shell: Op = serde_json::from_value(json!({
        "op": "gc_set_shape", "id": 1, "part": 0,
        "shape": {"type": "container", "thickness": 0.003, "closed_end": "end"},
    }))
    .unwrap();
    log.apply(shell).unwrap();
    let doc = log.document();
    let now = super::current("gc_set_shape", doc, ObjectId(1), 0);
    assert_eq!(
        Value::Object(now.clone()),
        json!({"shape_type": "container", "thickness": 0.003, "closed_end": "end"})
    );
    // The form's values with the current ones build the op that changes
    // nothing: the same content hash after it.
    let forms = forms();
    let form = forms.iter().find(|f| f.op == "gc_set_shape").unwrap();
    let mut v = defaults(form, 1);
    v.extend(now);
    let before = log.document().content_hash();
    log.apply(build("gc_set_shape", &v, None).unwrap().remove(0))
        .unwrap();
    assert_eq!(log.document().content_hash(), before);

    let res = super::current("gc_set_resolution", log.document(), ObjectId(1), 0);
    assert_eq!(
        Value::Object(res),
        json!({"resolution": {"u": 96, "v": 64}})
    );
    let place = super::current("set_transform", log.document(), ObjectId(1), 0);
    assert_eq!(place["transform"]["rotate"], json!([0.0, 0.0, 0.0, 1.0]));
    // No such part, object or op: nothing, the form's defaults stand.
    assert!(super::current("gc_set_shape", log.document(), ObjectId(1), 7).is_empty());
    assert!(super::current("sdf_set_step", log.document(), ObjectId(1), 0).is_empty());
    assert!(super::current("gc_bend", log.document(), ObjectId(9), 0).is_empty());
}
