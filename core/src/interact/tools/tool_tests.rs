//! The object tool end to end: puppet traces through a session onto a log.
//! One op per completed gesture; bad input leaves the document unchanged or
//! commits cleanly.

use crate::doc::{
    AddSolid, Delete, Duplicate, ObjectId, ObjectKind, Op, OpLog, ScriptCommand, SetTransform,
};
use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3, Transform};
use crate::solid::SolidShape;

use crate::interact::testkit::{Button, Puppet};
use crate::interact::{
    replay, GestureLabel, Hand, ModelPlacement, ObjectTool, Pose, Session, Similarity, Trace,
};

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::new(DVec3::new(x, y, z), DQuat::IDENTITY)
}

fn identity() -> ModelPlacement {
    ModelPlacement {
        translate: [0.0; 3],
        rotate: [0.0, 0.0, 0.0, 1.0],
        scale: 1.0,
    }
}

fn run(p: &Puppet) -> (Vec<ScriptCommand>, OpLog) {
    let r = replay(&p.trace(identity(), "test")).unwrap();
    assert!(r.rejected.is_empty(), "{:?}", r.rejected);
    (r.commands, r.log)
}

fn run_on(log: &mut OpLog, trace: &Trace) -> Vec<ScriptCommand> {
    let mut s = Session::new(Box::new(ObjectTool::default()), Similarity::IDENTITY);
    let mut out = Vec::new();
    for f in &trace.frames {
        if let Some(c) = s.step(f, log.document()) {
            log.apply_command(&c).unwrap();
            out.push(c);
        }
    }
    out
}

fn transform_of(log: &OpLog, id: u32) -> Transform {
    match &log.document().get(ObjectId(id)).unwrap().kind {
        ObjectKind::Solid(s) => s.transform,
        #[allow(unreachable_patterns)]
        _ => panic!("not a solid"),
    }
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (DVec3::from_array(a) - DVec3::from_array(b)).length() < 1e-9
}

/// A box placed at (0, 1, 0) by the right controller, which then backs off
/// to (0, 1, 0.3) aiming at it; the left controller idles at (-0.2, 1, 0.3).
fn with_box() -> Puppet {
    let mut p = Puppet::new(90.0);
    p.controller(R, at(0.0, 1.0, 0.0))
        .controller(L, at(-0.2, 1.0, 0.3))
        .wait(0.1)
        .click(R, Button::Primary)
        .move_to(R, at(0.0, 1.0, 0.3), 0.3);
    p
}

fn set_transform(c: &ScriptCommand) -> &SetTransform {
    match c {
        ScriptCommand::Op(Op::SetTransform(st)) => st,
        other => panic!("expected set_transform, got {other:?}"),
    }
}

#[test]
pub(crate) fn grab_move_rotate_emits_one_op_per_release() {
    let mut p = with_box();
    p.set(R, Button::Grab, true)
        .move_to(R, at(0.2, 1.1, 0.3), 0.5)
        .set(R, Button::Grab, false)
        .wait(0.1);
    // Rotate in place: the box, 0.3 m ahead, swings to the left.
    p.aim(R, DVec3::new(0.2, 1.1, 0.3), DVec3::new(0.2, 1.1, 0.0), 0.2)
        .set(R, Button::Grab, true)
        .move_to(
            R,
            Pose::new(
                DVec3::new(0.2, 1.1, 0.3),
                DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2),
            ),
            0.5,
        )
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, log) = run(&p);
    assert_eq!(cmds.len(), 3, "{cmds:?}");
    assert!(
        matches!(&cmds[0], ScriptCommand::Op(Op::AddSolid(AddSolid { shape: SolidShape::Box { .. }, transform, .. })) if close(transform.translate, [0.0, 1.0, 0.0]))
    );
    let st = set_transform(&cmds[1]);
    assert_eq!(st.id, ObjectId(1));
    assert!(close(st.transform.translate, [0.2, 1.1, 0.0]), "{st:?}");
    let st = set_transform(&cmds[2]);
    assert!(close(st.transform.translate, [-0.1, 1.1, 0.3]), "{st:?}");
    let q = DQuat::from_array(st.transform.rotate);
    assert!(q.angle_between(DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2)) < 1e-9);
    assert_eq!(transform_of(&log, 1), st.transform);
}

#[test]
fn two_hand_scale_is_one_op_with_the_handle_bar() {
    let mut p = with_box();
    p.set(R, Button::Grab, true)
        .wait(0.1)
        .set(L, Button::Grab, true)
        .wait(0.1);
    // Bar 0.2 m -> 0.6 m about its midpoint (-0.1, 1, 0.3): scale 3.
    // Both hands move together (interleaved one-frame steps).
    for k in 1..=30 {
        let a = k as f64 / 30.0;
        p.move_to(R, at(0.2 * a, 1.0, 0.3), 0.0)
            .move_to(L, at(-0.2 - 0.2 * a, 1.0, 0.3), 0.0);
    }
    p.set(R, Button::Grab, false)
        .wait(0.2)
        .set(L, Button::Grab, false)
        .wait(0.1);
    let (cmds, log) = run(&p);
    assert_eq!(cmds.len(), 2, "{cmds:?}");
    let st = set_transform(&cmds[1]);
    assert!(close(st.transform.scale, [3.0; 3]), "{st:?}");
    assert!(close(st.transform.translate, [0.2, 1.0, -0.6]), "{st:?}");
    let v = log
        .document()
        .get(ObjectId(1))
        .unwrap()
        .mesh
        .signed_volume();
    assert!((v - 27.0 * 0.12f64.fpowi(3)).abs() < 1e-9, "{v}");
}

#[test]
fn scale_ratio_clamps_at_four() {
    let mut p = with_box();
    p.set(R, Button::Grab, true).set(L, Button::Grab, true);
    p.move_to(L, at(-1.5, 1.0, 0.3), 0.3);
    p.set(L, Button::Grab, false)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, _) = run(&p);
    let st = set_transform(&cmds[1]);
    assert!(close(st.transform.scale, [4.0; 3]), "{st:?}");
}

#[test]
pub(crate) fn select_copy_delete_undo_redo() {
    let mut p = with_box();
    p.click(R, Button::Select)
        .click(R, Button::Primary)
        .click(R, Button::Secondary)
        .flick(R, -1.0)
        .flick(R, 1.0)
        .flick(R, -1.0);
    // Deselect by selecting empty space, then place another box.
    p.aim(R, DVec3::new(0.0, 1.0, 0.3), DVec3::new(0.0, 2.0, 0.3), 0.1)
        .click(R, Button::Select)
        .click(R, Button::Primary);
    let (cmds, log) = run(&p);
    let want = [
        "add_solid",
        "duplicate",
        "delete",
        "undo",
        "redo",
        "undo",
        "add_solid",
    ];
    let got: Vec<&str> = cmds.iter().map(ScriptCommand::name).collect();
    assert_eq!(got, want);
    assert_eq!(
        cmds[1],
        ScriptCommand::Op(Op::Duplicate(Duplicate { id: ObjectId(1) }))
    );
    assert_eq!(
        cmds[2],
        ScriptCommand::Op(Op::Delete(Delete { id: ObjectId(1) }))
    );
    // Box 1, its copy 2 (the delete was undone), the new box 3.
    let ids: Vec<u32> = log.document().objects().map(|(id, _)| id.0).collect();
    assert_eq!(ids, [1, 2, 3]);
}

#[test]
fn tracking_lost_during_a_drag_cancels_it() {
    let base = with_box();
    let (_, log0) = run(&base);
    let hash0 = log0.document().content_hash();
    let mut p = base.clone();
    p.set(R, Button::Grab, true)
        .move_to(R, at(0.1, 1.0, 0.3), 0.3)
        .lose_tracking(R, 0.5)
        .move_to(R, at(0.3, 1.0, 0.3), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, log) = run(&p);
    assert_eq!(cmds.len(), 1, "only the placement: {cmds:?}");
    assert_eq!(log.document().content_hash(), hash0);
    // A short dropout (under the grace period) does not end the drag.
    let mut p = base.clone();
    p.set(R, Button::Grab, true)
        .move_to(R, at(0.1, 1.0, 0.3), 0.3)
        .lose_tracking(R, 0.1)
        .move_to(R, at(0.3, 1.0, 0.3), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, _) = run(&p);
    assert_eq!(cmds.len(), 2);
    assert!(close(
        set_transform(&cmds[1]).transform.translate,
        [0.3, 1.0, 0.0]
    ));
}

#[test]
fn teleport_mid_drag_commits_before_the_jump() {
    let mut p = with_box();
    p.set(R, Button::Grab, true)
        .move_to(R, at(0.1, 1.0, 0.3), 0.3)
        .teleport(R, DVec3::new(2.0, 0.0, 0.0))
        .move_to(R, at(2.5, 1.0, 0.3), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, log) = run(&p);
    assert_eq!(cmds.len(), 2, "{cmds:?}");
    assert!(close(
        set_transform(&cmds[1]).transform.translate,
        [0.1, 1.0, 0.0]
    ));
    assert!(close(transform_of(&log, 1).translate, [0.1, 1.0, 0.0]));
}

#[test]
fn nan_samples_mid_drag_change_nothing() {
    let drag = |nan: bool| {
        let mut p = with_box();
        p.set(R, Button::Grab, true);
        for k in 1..=20 {
            p.move_to(R, at(0.01 * k as f64, 1.0, 0.3), 0.0);
            if nan && k % 3 == 0 {
                p.nan_frame(R);
            }
        }
        p.set(R, Button::Grab, false).wait(0.1);
        run(&p)
    };
    let (clean, log_a) = drag(false);
    let (noisy, log_b) = drag(true);
    assert_eq!(clean, noisy);
    assert_eq!(
        log_a.document().content_hash(),
        log_b.document().content_hash()
    );
}

fn hand_scene() -> (OpLog, u64) {
    let mut log = OpLog::new();
    log.apply(Op::AddSolid(AddSolid {
        shape: SolidShape::Box {
            size: [0.12, 0.12, 0.12],
        },
        segments: 32,
        transform: Transform::translation([0.0, 1.2, 0.0]),
    }))
    .unwrap();
    let h = log.document().content_hash();
    (log, h)
}

#[test]
fn open_to_fist_grabs_and_moves_with_a_tracked_hand() {
    let (mut log, _) = hand_scene();
    let mut p = Puppet::new(90.0);
    p.hand(R, GestureLabel::Open, at(0.0, 1.2, 0.3))
        .wait(0.2)
        .gesture(R, GestureLabel::Fist, 0.2)
        .wait(0.1)
        .move_to(R, at(0.2, 1.3, 0.3), 0.5)
        .wait(0.1)
        .gesture(R, GestureLabel::Open, 0.2)
        .wait(0.2);
    let mut trace = p.trace(identity(), "hand");
    // NaN joints in a few frames mid-move: those frames lose the hand
    // briefly (under the grace period) and the drag goes on.
    for f in trace.frames.iter_mut().skip(60).step_by(7).take(4) {
        if let Some(h) = f.hands[1].as_mut() {
            h.joints[10].pose.position.x = f64::NAN;
        }
    }
    let cmds = run_on(&mut log, &trace);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    // The palm position carries the puppet's 1 mm tracking jitter.
    let st = set_transform(&cmds[0]);
    let d = DVec3::from_array(st.transform.translate) - DVec3::new(0.2, 1.3, 0.0);
    assert!(d.length() < 0.005, "{st:?}");
    assert!(DQuat::from_array(st.transform.rotate).angle_between(DQuat::IDENTITY) < 1e-9);
}

#[test]
fn hand_vanishing_mid_gesture_leaves_the_document_unchanged() {
    let (mut log, hash0) = hand_scene();
    let mut p = Puppet::new(90.0);
    p.hand(R, GestureLabel::Open, at(0.0, 1.2, 0.3))
        .wait(0.2)
        .gesture(R, GestureLabel::Fist, 0.2)
        .wait(0.1)
        .move_to(R, at(0.1, 1.2, 0.3), 0.3)
        .hide_hand(R)
        .wait(0.5)
        .hand(R, GestureLabel::Open, at(0.3, 1.2, 0.3))
        .wait(0.3);
    let cmds = run_on(&mut log, &p.trace(identity(), "vanish"));
    assert!(cmds.is_empty(), "{cmds:?}");
    assert_eq!(log.document().content_hash(), hash0);
}

#[test]
fn preview_follows_the_drag_without_touching_the_document() {
    let p = {
        let mut p = with_box();
        p.set(R, Button::Grab, true)
            .move_to(R, at(0.1, 1.0, 0.3), 0.3);
        p
    };
    let trace = p.trace(identity(), "preview");
    let mut log = OpLog::new();
    let mut s = Session::new(Box::new(ObjectTool::default()), Similarity::IDENTITY);
    for f in &trace.frames {
        if let Some(c) = s.step(f, log.document()) {
            log.apply_command(&c).unwrap();
        }
    }
    let m = s.preview().moving.clone().unwrap();
    assert!(close(m.transform.translate, [0.1, 1.0, 0.0]));
    let mesh = s.preview().preview_mesh(log.document()).unwrap();
    let (lo, hi) = mesh.bbox().unwrap();
    assert!(((lo + hi) * 0.5 - DVec3::new(0.1, 1.0, 0.0)).length() < 1e-9);
    assert!(close(transform_of(&log, 1).translate, [0.0, 1.0, 0.0]));
}
