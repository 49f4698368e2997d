//! The checked-in controller traces of the CSG and sculpt tools:
//! `tests/data/csg_cup.trace.jsonl` (paper 2's cup) and
//! `tests/data/bust.trace.jsonl` (paper 4's bust from a sphere). They are
//! regenerated from the puppet scripts below with
//! `SHAPEWRIGHT_WRITE_TRACES=1 cargo test -p shapewright --lib interact::ctl_traces`;
//! every run checks the files still match the scripts, replays them twice
//! and checks the op sequence, the printable model and bit-identity.

use crate::doc::{Op, ScriptCommand};
use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};
use crate::mesh::{self, TriMesh};
use crate::sdf::{CsgOp, ScaleAxis};

use super::{Button, Puppet};
use crate::interact::gesture::bimanual::ModelFrame;
use crate::interact::{replay, Hand, ModelPlacement, Pose, Replay, Trace};

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

fn data(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(name)
}

/// The desk placement as a model frame.
pub(crate) fn desk() -> ModelFrame {
    let d = ModelPlacement::desk();
    ModelFrame {
        pose: Pose::new(DVec3::from_array(d.translate), DQuat::from_array(d.rotate)),
        scale: d.scale,
    }
}

/// A level controller at the stage point of model point `p`.
pub(crate) fn at_model(view: &ModelFrame, p: [f64; 3]) -> Pose {
    Pose::new(view.to_world(DVec3::from_array(p)), DQuat::IDENTITY)
}

/// Two-hand gesture: both hands at `a0`/`b0` (model points), grab
/// (`first` then the other), move to `a1`/`b1`, release. `axis_flick`
/// pushes the right stick during the gesture (the scale axis quadrant).
pub(crate) fn two_hand(
    p: &mut Puppet,
    v: &ModelFrame,
    first: Hand,
    right: ([f64; 3], [f64; 3]),
    left: ([f64; 3], [f64; 3]),
    axis_flick: Option<f64>,
) {
    p.move_to(R, at_model(v, right.0), 0.3)
        .move_to(L, at_model(v, left.0), 0.3)
        .set(first, Button::Grab, true)
        .wait(0.1)
        .set(first.other(), Button::Grab, true)
        .wait(0.1);
    if let Some(x) = axis_flick {
        p.flick(R, x);
    }
    let n = 30;
    for k in 1..=n {
        let a = k as f64 / n as f64;
        let lerp = |u: [f64; 3], w: [f64; 3]| [0, 1, 2].map(|i| u[i] + (w[i] - u[i]) * a);
        p.move_to(R, at_model(v, lerp(right.0, right.1)), 0.0)
            .move_to(L, at_model(v, lerp(left.0, left.1)), 0.0);
    }
    p.set(R, Button::Grab, false)
        .wait(0.1)
        .set(L, Button::Grab, false)
        .wait(0.1);
}

/// Paper 2's cup with controllers (Table 1, Fig. 7c): a new volume; a
/// cylinder scaled 2.4× with both hands (r 0.12, h 0.24); a torus handle
/// placed at x = 0.17, turned 90° about X by a grab and scaled 1.5×; an
/// inner cylinder subtracted, scaled 2.1× uniformly and then 8/7× along Z
/// (r 0.105, h 0.24, from z = -0.09: a 3 cm floor, open top); a copy of
/// the handle deleted by double click, undone, redone; a sphere placed
/// with *intersect* and cancelled; then *update*. Genus 1.
pub(crate) fn csg_cup() -> Trace {
    let v = desk();
    let mut p = Puppet::new(72.0);
    p.controller(R, at_model(&v, [0.3, -0.3, 0.1]))
        .controller(L, at_model(&v, [-0.3, -0.3, 0.1]))
        .wait(0.2)
        // SceneOperate in an empty document: a new volume.
        .click(R, Button::Primary)
        // The body: a cylinder (the menu's first component), scaled 2.4×.
        .move_to(R, at_model(&v, [0.0, 0.0, 0.0]), 0.3)
        .click(R, Button::Primary);
    two_hand(
        &mut p,
        &v,
        R,
        ([0.03, 0.0, 0.0], [0.072, 0.0, 0.0]),
        ([-0.03, 0.0, 0.0], [-0.072, 0.0, 0.0]),
        None,
    );
    // The handle: next component (torus), placed, turned, scaled 1.5×.
    p.click(R, Button::Menu)
        .move_to(R, at_model(&v, [0.17, 0.0, 0.0]), 0.3)
        .click(R, Button::Primary)
        .set(R, Button::Grab, true)
        .wait(0.1);
    let turned = Pose::new(
        v.to_world(DVec3::new(0.17, 0.0, 0.0)),
        DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
    );
    p.move_to(R, turned, 0.3)
        .lose_tracking(R, 0.1)
        .move_to(R, turned, 0.2)
        .set(R, Button::Grab, false)
        .wait(0.1)
        .move_to(R, at_model(&v, [0.19, 0.0, 0.0]), 0.2);
    two_hand(
        &mut p,
        &v,
        R,
        ([0.19, 0.0, 0.0], [0.2, 0.0, 0.0]),
        ([0.15, 0.0, 0.0], [0.14, 0.0, 0.0]),
        None,
    );
    // The hollow: previous component (cylinder), SceneOperate down twice
    // (union -> intersect -> subtract), placed, scaled.
    p.click(L, Button::Menu);
    p.flick_y(R, -1.0).flick_y(R, -1.0);
    p.move_to(R, at_model(&v, [0.0, 0.0, 0.03]), 0.3)
        .click(R, Button::Primary);
    two_hand(
        &mut p,
        &v,
        R,
        ([0.03, 0.0, 0.03], [0.063, 0.0, 0.03]),
        ([-0.03, 0.0, 0.03], [-0.063, 0.0, 0.03]),
        None,
    );
    // ... and 8/7 along Z (right stick left: the Z quadrant).
    two_hand(
        &mut p,
        &v,
        R,
        ([0.03, 0.0, 0.03], [0.04, 0.0, 0.03]),
        ([-0.04, 0.0, 0.03], [-0.04, 0.0, 0.03]),
        Some(-1.0),
    );
    // Copy the handle (select it, update button), delete the copy by
    // double click, undo, redo.
    p.move_to(R, at_model(&v, [0.17, 0.0, 0.0]), 0.3)
        .click(R, Button::Select)
        .click(R, Button::Secondary)
        .move_to(R, at_model(&v, [0.32, 0.0, 0.0]), 0.3)
        .click(R, Button::Select)
        .click(R, Button::Select)
        .wait(0.3)
        .flick(R, -1.0)
        .flick(R, 1.0);
    // A sphere with intersect (SceneOperate up once), then cancelled.
    p.click(R, Button::Menu)
        .click(R, Button::Menu)
        .flick_y(R, 1.0)
        .move_to(R, at_model(&v, [0.0, -0.4, 0.0]), 0.3)
        .click(R, Button::Primary)
        .flick_y(R, -1.0)
        .flick_y(R, -1.0)
        .click(R, Button::Select)
        .click(R, Button::Primary)
        // Update: fuse and extract.
        .move_to(R, at_model(&v, [0.3, -0.3, 0.1]), 0.3)
        .click(R, Button::Secondary)
        .wait(0.2);
    let mut t = p.trace(
        ModelPlacement::desk(),
        "paper 2's cup by controllers: cylinder, torus handle, subtracted hollow, update",
    );
    t.header.tool = "csg".into();
    t
}

/// Op names of commands, with undo/redo.
pub(crate) fn names(commands: &[ScriptCommand]) -> Vec<String> {
    commands.iter().map(|c| c.name().to_string()).collect()
}

/// Checks the file matches the script (rewriting it on request), replays
/// it twice, and returns the replay and the printable mesh.
fn check_fixture(name: &str, made: &Trace) -> (Replay, TriMesh) {
    let path = data(name);
    if std::env::var_os("SHAPEWRIGHT_WRITE_TRACES").is_some() {
        std::fs::write(&path, made.to_jsonl()).unwrap();
    }
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.len() < 3 << 20, "{name}: {} bytes", text.len());
    let trace = Trace::from_jsonl(&text).unwrap();
    assert_eq!(trace, Trace::from_jsonl(&made.to_jsonl()).unwrap());
    let r = replay(&trace).unwrap();
    assert!(r.rejected.is_empty(), "{:?}", r.rejected);
    let again = replay(&trace).unwrap();
    assert_eq!(again.commands, r.commands);
    assert_eq!(
        again.log.document().content_hash(),
        r.log.document().content_hash()
    );
    let printable = r.log.document().printable_mesh().unwrap();
    let again_mesh = again.log.document().printable_mesh().unwrap();
    assert_eq!(printable.positions, again_mesh.positions);
    assert_eq!(printable.triangles, again_mesh.triangles);
    println!(
        "{name}: {} frames, {} bytes, {} commands, {} triangles",
        trace.frames.len(),
        text.len(),
        r.commands.len(),
        printable.triangles.len()
    );
    if let Some(dir) = std::env::var_os("SHAPEWRIGHT_TRACE_STL") {
        let out = std::path::Path::new(&dir).join(name.replace(".trace.jsonl", ".stl"));
        let mut f = std::io::BufWriter::new(std::fs::File::create(out).unwrap());
        mesh::write_stl(&printable, &mut f).unwrap();
    }
    (r, printable)
}

#[test]
fn csg_cup_trace_replays_to_a_genus_one_cup() {
    let (r, m) = check_fixture("csg_cup.trace.jsonl", &csg_cup());
    assert_eq!(
        names(&r.commands),
        [
            "sdf_create",
            "sdf_add_operand",
            "sdf_scale_two_hand",
            "sdf_add_operand",
            "sdf_set_operand_transform",
            "sdf_scale_two_hand",
            "sdf_add_operand",
            "sdf_scale_two_hand",
            "sdf_scale_two_hand",
            "sdf_copy_operand",
            "sdf_cancel_operand",
            "undo",
            "redo",
            "sdf_add_operand",
            "sdf_cancel_operand",
            "sdf_update",
        ]
    );
    // The ops carry what the gestures meant.
    let ops: Vec<&Op> = r
        .commands
        .iter()
        .filter_map(|c| match c {
            ScriptCommand::Op(op) => Some(op),
            _ => None,
        })
        .collect();
    let Op::SdfAddOperand(hollow) = ops[6] else {
        panic!("{:?}", ops[6])
    };
    assert_eq!(hollow.csg, CsgOp::Subtract);
    let Op::SdfScaleTwoHand(z) = ops[8] else {
        panic!()
    };
    assert_eq!(z.axis, ScaleAxis::Z);
    let Op::SdfAddOperand(sphere) = ops[11] else {
        panic!()
    };
    assert_eq!(sphere.csg, CsgOp::Intersect);
    let v = match &r.log.document().objects().next().unwrap().1.kind {
        crate::doc::ObjectKind::SdfVolume(v) => v.clone(),
        other => panic!("{}", other.name()),
    };
    assert!(v.pending.is_empty());
    assert_eq!(v.fused.len(), 3);
    let [body, handle, hollow] = [0, 1, 2].map(|i| v.fused[i].transform);
    let near = |a: [f64; 3], b: [f64; 3], tol: f64| {
        (DVec3::from_array(a) - DVec3::from_array(b)).length() < tol
    };
    assert!(near(body.scale, [2.4; 3], 1e-3), "{:?}", body.scale);
    assert!(near(handle.scale, [1.5; 3], 1e-3), "{:?}", handle.scale);
    assert!(near(handle.translate, [0.17, 0.0, 0.0], 1e-3));
    let q = DQuat::from_array(handle.rotate);
    assert!(q.angle_between(DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)) < 1e-3);
    assert!(
        near(hollow.scale, [2.1, 2.1, 2.4], 2e-3),
        "{:?}",
        hollow.scale
    );
    // A closed printable cup with one handle hole.
    let report = mesh::validate(&m, &Default::default());
    assert!(report.is_closed_manifold(), "{}", report.problems());
    assert_eq!(report.genus, Some(1));
    // Volume: the body minus the hollow, plus the handle (sampled at 1 cm).
    let pi = std::f64::consts::PI;
    let expected = pi * 0.12f64.fpowi(2) * 0.24 - pi * 0.105f64.fpowi(2) * 0.21
        + 2.0 * pi * pi * 0.06 * 0.015f64.fpowi(2) * 0.6;
    let vol = report.signed_volume;
    assert!(
        (vol - expected).abs() / expected < 0.2,
        "{vol} vs {expected}"
    );
}

/// The sculpt tool's stroke script: brush preset, start and end (model
/// units), brush rotation in the model, pressure.
struct BustStroke {
    preset: usize,
    from: [f64; 3],
    to: [f64; 3],
    rot: DQuat,
    pressure: f64,
}

fn bust_strokes() -> Vec<BustStroke> {
    let id = DQuat::IDENTITY;
    let s = |preset, from: [f64; 3], to: [f64; 3]| BustStroke {
        preset,
        from: from.map(|x| x * 0.1),
        to: to.map(|x| x * 0.1),
        rot: id,
        pressure: 1.0,
    };
    let mut v = vec![
        // Skull up and back, the neck down, the jaw.
        s(0, [0.0, 0.1, 0.6], [0.0, 0.25, 0.95]),
        s(1, [0.0, -0.35, -0.75], [0.0, -0.45, -1.05]),
        s(2, [0.0, 0.15, -0.85], [0.0, 0.2, -1.75]),
        // Shoulders.
        s(4, [-0.1, 0.2, -1.72], [-1.2, 0.2, -1.95]),
        s(4, [0.1, 0.2, -1.72], [1.2, 0.2, -1.95]),
        s(5, [0.0, 0.2, -2.0], [0.0, 0.2, -2.55]),
        // Chest and back.
        s(2, [0.0, 0.05, -1.75], [0.0, -0.25, -2.3]),
        s(2, [0.0, 0.35, -1.75], [0.0, 0.55, -2.3]),
        // Smooth the torso.
        s(3, [-0.8, 0.2, -1.9], [0.8, 0.2, -1.9]),
        s(3, [-0.8, 0.2, -2.15], [0.8, 0.2, -2.15]),
        s(3, [-0.8, 0.2, -2.4], [0.8, 0.2, -2.4]),
        // Face: eye sockets, brow, nose, mouth, ears (after the model is
        // turned and scaled up).
        s(6, [-0.33, -0.92, 0.2], [-0.33, -0.8, 0.2]),
        s(6, [0.33, -0.92, 0.2], [0.33, -0.8, 0.2]),
        BustStroke {
            rot: DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2),
            ..s(8, [0.0, -0.98, 0.38], [0.0, -1.05, 0.38])
        },
        s(6, [0.0, -0.97, 0.05], [0.0, -1.22, -0.05]),
        s(7, [0.0, -0.9, -0.35], [0.0, -0.96, -0.35]),
        s(9, [-0.97, 0.1, 0.1], [-1.12, 0.15, 0.1]),
        s(9, [0.97, 0.1, 0.1], [1.12, 0.15, 0.1]),
    ];
    v.push(BustStroke {
        pressure: 0.5,
        ..s(10, [0.0, -0.9, 0.0], [0.0, -0.9, 0.0])
    });
    v
}

/// A bust from a 10 cm sphere with the sculpt tool: shape strokes at desk
/// scale; then the left hand turns the model 90° about the vertical and
/// both hands scale it 1.95× (brush sized up by three 1.25× steps to
/// match) for the face and ears.
pub(crate) fn bust() -> Trace {
    let presets = crate::interact::BrushToolSettings::default().presets.len();
    let mut view = desk();
    let rest = Pose::new(DVec3::new(0.3, 1.0, -0.2), DQuat::IDENTITY);
    let hold = Pose::new(DVec3::new(-0.25, 0.8, -0.5), DQuat::IDENTITY);
    let mut p = Puppet::new(60.0);
    p.controller(R, rest)
        .controller(L, Pose::new(DVec3::new(-0.3, 1.0, -0.2), DQuat::IDENTITY))
        .wait(0.2)
        .click(R, Button::Primary);
    let mut current = 0;
    for (k, s) in bust_strokes().iter().enumerate() {
        if k == 11 {
            // Turn the model with the left hand, scale with both.
            let turned = Pose::new(
                hold.position,
                DQuat::from_rotation_y(0.5 * std::f64::consts::PI),
            );
            let (r0, r1) = (
                hold.position + DVec3::new(0.128, 0.0, 0.0),
                hold.position + DVec3::new(0.25, 0.0, 0.0),
            );
            let mut g = crate::interact::OrientGrab::new(hold, view);
            p.move_to(L, hold, 0.4)
                .set(L, Button::Grab, true)
                .move_to(L, turned, 0.5)
                .move_to(R, Pose::new(r0, DQuat::IDENTITY), 0.4)
                .set(R, Button::Grab, true)
                .move_to(R, Pose::new(r1, DQuat::IDENTITY), 0.5)
                .set(R, Button::Grab, false)
                .set(L, Button::Grab, false)
                .flick_y(R, 1.0)
                .flick_y(R, 1.0)
                .flick_y(R, 1.0);
            g.frame(&turned, None);
            g.frame(&turned, Some(r0));
            view = g.frame(&turned, Some(r1));
        }
        while current != s.preset {
            p.click(R, Button::Menu);
            current = (current + 1) % presets;
        }
        let q = view.pose.orientation * s.rot;
        let a = Pose::new(view.to_world(DVec3::from_array(s.from)), q);
        let b = Pose::new(view.to_world(DVec3::from_array(s.to)), q);
        p.move_to(R, a, 0.4)
            .trigger(R, s.pressure)
            .move_to(R, b, 0.5)
            .trigger(R, 0.0)
            .wait(0.05);
    }
    p.move_to(R, rest, 0.4).wait(0.1);
    let mut t = p.trace(
        ModelPlacement::desk(),
        "a bust from a sphere with the sculpt tool: strokes, the left hand turning and scaling the model",
    );
    t.header.tool = "sculpt".into();
    t
}

#[test]
fn bust_trace_replays_to_a_closed_bust() {
    let (r, m) = check_fixture("bust.trace.jsonl", &bust());
    let n = names(&r.commands);
    assert_eq!(n[0], "sculpt_create");
    assert_eq!(n.len(), 1 + bust_strokes().len());
    assert!(n[1..].iter().all(|s| s == "sculpt_stroke"), "{n:?}");
    // Pressure comes from the trigger: the last stroke was held at half.
    let Some(ScriptCommand::Op(Op::SculptStroke(last))) = r.commands.last() else {
        panic!()
    };
    assert!(last.samples.iter().all(|s| s.pressure == 0.5));
    assert_eq!(last.settings.warp, crate::sculpt::Warp::Whittle);
    let report = mesh::validate(&m, &Default::default());
    assert!(report.is_closed_manifold(), "{}", report.problems());
    assert_eq!(report.genus, Some(0));
    // Head on shoulders: pulled well below the sphere (neck and chest),
    // shoulders wider than the head, the nose out of the face.
    let [lo, hi] = report.bbox.unwrap();
    assert!(lo[2] < -0.2 && hi[2] > 0.1, "{lo:?} {hi:?}");
    assert!(hi[0] - lo[0] > 0.2, "{lo:?} {hi:?}");
    assert!(lo[1] < -0.11, "{lo:?}");
}
