//! The checked-in controller session `tests/data/primitives_session.trace.jsonl`:
//! it is regenerated from the puppet script below with
//! `SHAPEWRIGHT_WRITE_TRACES=1 cargo test -p shapewright --lib interact::trace_fixture`,
//! and every run checks the file still matches the script, then replays it.

use crate::doc::{parse_script, run_script, ObjectId, Op, OpLog, ScriptCommand};
use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};
use crate::mesh;

use crate::interact::testkit::{Button, Puppet};
use crate::interact::{replay, Hand, ModelPlacement, Pose, Trace};

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::new(DVec3::new(x, y, z), DQuat::IDENTITY)
}

fn path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/primitives_session.trace.jsonl")
}

/// Places a box and a sphere, moves the box, scales the sphere with both
/// hands, places a cylinder and undoes it, places a cone, copies it and
/// moves the copy. The model sits on a desk (model +Z up): model point
/// (x, y, z) is stage point (x, 0.8 + z, -0.5 - y).
pub(crate) fn primitives_session() -> Trace {
    let up = |p: &mut Puppet| {
        let pos = DVec3::new(0.0, 1.0, -0.1);
        p.aim(R, pos, pos + DVec3::Y, 0.2).click(R, Button::Select);
    };
    let mut p = Puppet::new(90.0);
    p.controller(R, at(0.1, 1.0, -0.4))
        .controller(L, at(-0.3, 1.0, -0.1))
        .wait(0.3)
        // Box, then sphere.
        .click(R, Button::Primary)
        .click(R, Button::Menu)
        .move_to(R, at(0.35, 1.0, -0.4), 0.4)
        .click(R, Button::Primary)
        // Move the box up 15 cm.
        .move_to(R, at(0.1, 1.0, -0.2), 0.4)
        .set(R, Button::Grab, true)
        .move_to(R, at(0.1, 1.15, -0.2), 0.6)
        .set(R, Button::Grab, false)
        .wait(0.2)
        // Scale the sphere 2x with both hands (bar 0.2 m -> 0.4 m).
        .move_to(R, at(0.35, 1.0, -0.2), 0.4)
        .move_to(L, at(0.15, 1.0, -0.2), 0.4)
        .set(R, Button::Grab, true)
        .wait(0.1)
        .set(L, Button::Grab, true)
        .wait(0.1);
    for k in 1..=45 {
        let a = k as f64 / 45.0;
        p.move_to(R, at(0.35 + 0.1 * a, 1.0, -0.2), 0.0).move_to(
            L,
            at(0.15 - 0.1 * a, 1.0, -0.2),
            0.0,
        );
    }
    p.set(R, Button::Grab, false)
        .wait(0.2)
        .set(L, Button::Grab, false)
        .move_to(L, at(-0.3, 1.0, -0.1), 0.3);
    up(&mut p);
    // A cylinder, undone; a cone instead.
    p.click(R, Button::Menu)
        .move_to(R, at(-0.2, 1.0, -0.4), 0.4)
        .click(R, Button::Primary)
        .wait(0.3)
        .flick(R, -1.0)
        .click(R, Button::Menu)
        .click(R, Button::Primary)
        // Copy the cone and move the copy 25 cm left.
        .move_to(R, at(-0.2, 1.0, -0.2), 0.4)
        .click(R, Button::Select)
        .click(R, Button::Primary)
        .set(R, Button::Grab, true)
        .move_to(R, at(-0.45, 1.0, -0.2), 0.6)
        .set(R, Button::Grab, false)
        .wait(0.2);
    up(&mut p);
    p.wait(0.3);
    p.trace(
        ModelPlacement::desk(),
        "controller session: place box and sphere, move box, two-hand scale sphere 2x, \
         place cylinder + undo, place cone, copy it and move the copy",
    )
}

#[test]
fn checked_in_trace_matches_the_puppet_and_replays() {
    let made = primitives_session();
    if std::env::var_os("SHAPEWRIGHT_WRITE_TRACES").is_some() {
        std::fs::write(path(), made.to_jsonl()).unwrap();
    }
    let text = std::fs::read_to_string(path()).unwrap();
    let trace = Trace::from_jsonl(&text).unwrap();
    assert_eq!(trace, Trace::from_jsonl(&made.to_jsonl()).unwrap());
    println!(
        "primitives_session.trace.jsonl: {} frames, {} bytes ({:.0} bytes/frame)",
        trace.frames.len(),
        text.len(),
        text.len() as f64 / trace.frames.len() as f64
    );

    let r = replay(&trace).unwrap();
    assert!(r.rejected.is_empty(), "{:?}", r.rejected);
    let names: Vec<String> = r
        .commands
        .iter()
        .map(|c| match c {
            ScriptCommand::Op(op) => match op {
                Op::SetTransform(s) => format!("set_transform {}", s.id),
                Op::Duplicate(d) => format!("duplicate {}", d.id),
                Op::AddSolid(a) => format!("add_solid {}", a.shape.name()),
                other => other.name().to_string(),
            },
            ScriptCommand::Undo => "undo".into(),
            ScriptCommand::Redo => "redo".into(),
        })
        .collect();
    assert_eq!(
        names,
        [
            "add_solid box",
            "add_solid sphere",
            "set_transform #1",
            "set_transform #2",
            "add_solid cylinder",
            "undo",
            "add_solid cone",
            "duplicate #3",
            "set_transform #4",
        ]
    );
    let close =
        |a: [f64; 3], b: [f64; 3]| (DVec3::from_array(a) - DVec3::from_array(b)).length() < 1e-9;
    let tf = |i: usize| match &r.commands[i] {
        ScriptCommand::Op(Op::SetTransform(s)) => s.transform,
        _ => unreachable!(),
    };
    assert!(close(tf(2).translate, [0.1, -0.1, 0.35]), "{:?}", tf(2));
    assert!(close(tf(3).translate, [0.45, 0.1, 0.2]), "{:?}", tf(3));
    assert!(close(tf(3).scale, [2.0; 3]), "{:?}", tf(3));
    assert!(close(tf(8).translate, [-0.45, -0.1, 0.2]), "{:?}", tf(8));

    // The model: four closed solids, the printable union of disjoint parts.
    let doc = r.log.document();
    let ids: Vec<ObjectId> = doc.objects().map(|(id, _)| id).collect();
    assert_eq!(ids, [ObjectId(1), ObjectId(2), ObjectId(3), ObjectId(4)]);
    let mut m = doc.combined_mesh();
    m.compute_normals();
    let report = mesh::validate(&m, &Default::default());
    assert!(report.is_closed_manifold(), "{}", report.problems());
    assert_eq!(report.components, 4);
    let sphere = doc.get(ObjectId(2)).unwrap().mesh.signed_volume();
    let want = 4.0 / 3.0 * std::f64::consts::PI * 0.14f64.fpowi(3);
    assert!((sphere - want).abs() / want < 0.02, "{sphere} vs {want}");

    // The commands as an op script replay to the same document, bit for bit.
    let script: String = r
        .commands
        .iter()
        .map(|c| match c {
            ScriptCommand::Op(op) => serde_json::to_string(op).unwrap(),
            ScriptCommand::Undo => "{\"op\":\"undo\"}".into(),
            ScriptCommand::Redo => "{\"op\":\"redo\"}".into(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(&script).unwrap()).unwrap();
    assert_eq!(log.document().content_hash(), doc.content_hash());
    let again = replay(&trace).unwrap();
    assert_eq!(again.log.document().content_hash(), doc.content_hash());
}

#[test]
fn bad_traces_are_refused_with_reasons() {
    use crate::interact::TraceError;
    assert_eq!(Trace::from_jsonl(""), Err(TraceError::Empty));
    let mut t = primitives_session();
    t.frames.truncate(2);
    let text = t.to_jsonl();
    assert!(matches!(
        Trace::from_jsonl(&text.replace("\"version\":1", "\"version\":9")),
        Err(TraceError::Version(9))
    ));
    assert!(matches!(
        Trace::from_jsonl(&text.replace("shapewright-trace", "other")),
        Err(TraceError::Format(_))
    ));
    let broken = format!("{text}{{\"time\":\"soon\"}}\n");
    assert!(matches!(
        Trace::from_jsonl(&broken),
        Err(TraceError::Frame { line: 4, .. })
    ));
    t.header.model.scale = 0.0;
    assert!(matches!(replay(&t), Err(TraceError::Model)));
}
