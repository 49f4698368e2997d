//! Bad input and per-gesture behaviour of the CSG and sculpt tools, driven
//! by the puppet through a [`Session`].

use crate::doc::{Create, Edit, ObjectId, ObjectKind, Op, OpLog, ScriptCommand};
use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3, Transform};
use crate::mesh;
use crate::sculpt::{SculptBase, SculptCreate};
use crate::sdf::{Component, CsgOp, ScaleAxis};
use crate::sdf::{SdfAddOperand, SdfCreate};
use crate::solid::SolidShape;

use crate::interact::testkit::{Button, Puppet};
use crate::interact::{
    BrushTool, BrushToolSettings, CsgTool, Hand, ModelPlacement, Pose, Preview, Session,
    Similarity, Tool,
};

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

/// Runs `frames` through a session with `tool` (model at the stage
/// origin, scale 1), applying commands; returns them and every preview.
fn drive(tool: Box<dyn Tool>, log: &mut OpLog, p: &Puppet) -> (Vec<ScriptCommand>, Vec<Preview>) {
    let mut s = Session::new(tool, Similarity::IDENTITY);
    let trace = p.trace(ModelPlacement::desk(), "");
    let mut cmds = Vec::new();
    let mut previews = Vec::new();
    for f in &trace.frames {
        if let Some(c) = s.step(f, log.document()) {
            log.apply_command(&c).unwrap();
            cmds.push(c);
        }
        previews.push(s.preview().clone());
    }
    (cmds, previews)
}

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::new(DVec3::new(x, y, z), DQuat::IDENTITY)
}

/// A volume with one pending cylinder (r 0.05, h 0.1) at the origin.
fn csg_log() -> OpLog {
    let mut log = OpLog::new();
    log.apply(Op::SdfCreate(Create(SdfCreate { step: 0.01 })))
        .unwrap();
    log.apply(Op::SdfAddOperand(Edit::new(
        ObjectId(1),
        SdfAddOperand {
            component: Component::Solid {
                shape: SolidShape::Cylinder {
                    radius: 0.05,
                    height: 0.1,
                },
            },
            csg: CsgOp::Union,
            transform: Transform::IDENTITY,
        },
    )))
    .unwrap();
    log
}

fn operand_transform(log: &OpLog) -> Transform {
    match &log.document().get(ObjectId(1)).unwrap().kind {
        ObjectKind::SdfVolume(v) => v.pending[0].transform,
        other => panic!("{}", other.name()),
    }
}

/// Right hand grabs the cylinder at the origin.
fn grab_operand(p: &mut Puppet) {
    p.controller(R, at(0.02, 0.0, 0.3))
        .controller(L, at(-0.3, 0.0, 0.3))
        .wait(0.1)
        .move_to(R, at(0.02, 0.0, 0.0), 0.2)
        .set(R, Button::Grab, true)
        .wait(0.05);
}

#[test]
pub(crate) fn csg_drag_is_one_op_with_nan_frames_ignored() {
    let mut log = csg_log();
    let mut p = Puppet::new(72.0);
    grab_operand(&mut p);
    p.move_to(R, at(0.07, 0.0, 0.0), 0.3)
        .nan_frame(R)
        .move_to(R, at(0.12, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, previews) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    assert!(matches!(
        cmds[0],
        ScriptCommand::Op(Op::SdfSetOperandTransform(_))
    ));
    let t = operand_transform(&log);
    assert!((DVec3::from_array(t.translate) - DVec3::new(0.1, 0.0, 0.0)).length() < 1e-6);
    // The moving operand was previewed during the drag, and the grabbed
    // operand was highlighted before it.
    assert!(previews
        .iter()
        .any(|p| p.csg().is_some_and(|c| c.moving_operand.is_some())));
    assert!(previews
        .iter()
        .any(|p| p.csg().is_some_and(|c| c.highlighted_operand == Some(0))));
    assert!(previews
        .last()
        .unwrap()
        .csg()
        .is_none_or(|c| c.moving_operand.is_none()));
}

#[test]
fn csg_teleport_commits_the_last_good_placement() {
    let mut log = csg_log();
    let mut p = Puppet::new(72.0);
    grab_operand(&mut p);
    p.move_to(R, at(0.07, 0.0, 0.0), 0.3)
        .teleport(R, DVec3::new(1.0, 0.0, 0.0))
        .move_to(R, at(1.2, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, _) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    let t = operand_transform(&log);
    assert!((DVec3::from_array(t.translate) - DVec3::new(0.05, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn csg_tracking_lost_during_a_drag_leaves_the_document_unchanged() {
    let mut log = csg_log();
    let before = log.document().content_hash();
    let mut p = Puppet::new(72.0);
    grab_operand(&mut p);
    p.move_to(R, at(0.07, 0.0, 0.0), 0.3)
        .lose_tracking(R, 0.5)
        .move_to(R, at(0.1, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, _) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert!(cmds.is_empty(), "{cmds:?}");
    assert_eq!(log.document().content_hash(), before);
    // A short dropout (below the grace time) does not end the drag.
    let mut p = Puppet::new(72.0);
    grab_operand(&mut p);
    p.move_to(R, at(0.07, 0.0, 0.0), 0.3)
        .lose_tracking(R, 0.1)
        .move_to(R, at(0.1, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, _) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
}

#[test]
pub(crate) fn csg_two_hand_scale_is_clamped_and_per_axis() {
    let mut log = csg_log();
    let mut p = Puppet::new(72.0);
    grab_operand(&mut p);
    p.move_to(L, at(-0.02, 0.0, 0.0), 0.2)
        .set(L, Button::Grab, true)
        .wait(0.1)
        // Right stick up: the Y quadrant.
        .flick_y(R, 1.0)
        .move_to(R, at(0.5, 0.0, 0.0), 0.3)
        .move_to(L, at(-0.5, 0.0, 0.0), 0.3)
        .set(L, Button::Grab, false)
        .set(R, Button::Grab, false)
        .wait(0.1);
    let (cmds, previews) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    let ScriptCommand::Op(Op::SdfScaleTwoHand(op)) = &cmds[0] else {
        panic!("{cmds:?}")
    };
    assert_eq!(op.axis, ScaleAxis::Y);
    // Hands 4 cm apart -> 1 m: the ratio is clamped to 4.
    assert_eq!(operand_transform(&log).scale, [1.0, 4.0, 1.0]);
    assert!(previews.iter().any(|p| p
        .csg()
        .and_then(|c| c.moving_operand)
        .is_some_and(|m| m.transform.scale == [1.0, 4.0, 1.0])));
}

#[test]
pub(crate) fn csg_select_copy_delete_update_and_undo() {
    let mut log = csg_log();
    let mut p = Puppet::new(72.0);
    p.controller(R, at(0.02, 0.0, 0.3))
        .controller(L, at(-0.3, 0.0, 0.3))
        .wait(0.1)
        // Select by ray from 30 cm away, copy with the update button.
        .click(R, Button::Select)
        .click(R, Button::Secondary)
        // Double click on the copy (15 cm to +x) deletes it.
        .move_to(R, at(0.17, 0.0, 0.3), 0.3)
        .click(R, Button::Select)
        .click(R, Button::Select)
        // Undo the delete, redo it.
        .flick(L, -1.0)
        .flick(L, 1.0)
        // Nothing selected: update.
        .click(R, Button::Secondary);
    let (cmds, _) = drive(Box::new(CsgTool::default()), &mut log, &p);
    assert_eq!(
        crate::interact::testkit::ctl_traces::names(&cmds),
        [
            "sdf_copy_operand",
            "sdf_cancel_operand",
            "undo",
            "redo",
            "sdf_update"
        ]
    );
    let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(1)).unwrap().kind else {
        panic!()
    };
    assert_eq!((v.fused.len(), v.pending.len()), (1, 0));
    let r = mesh::validate(
        &log.document().get(ObjectId(1)).unwrap().mesh,
        &Default::default(),
    );
    assert!(r.is_closed_manifold());
    let exact = std::f64::consts::PI * 0.05f64.fpowi(2) * 0.1;
    assert!(
        (r.signed_volume - exact).abs() / exact < 0.1,
        "{}",
        r.signed_volume
    );
}

/// `presses` clicks of A by the right controller, with `tool`, on an empty
/// document: the commands' names and the log.
fn presses_of_a(tool: Box<dyn Tool>, presses: usize) -> (Vec<String>, OpLog) {
    let mut log = OpLog::new();
    let mut p = Puppet::new(72.0);
    p.controller(R, at(0.0, 0.0, 0.3))
        .controller(L, at(-0.3, 0.0, 0.3))
        .wait(0.1);
    for _ in 0..presses {
        p.click(R, Button::Primary);
    }
    let (cmds, _) = drive(tool, &mut log, &p);
    (crate::interact::testkit::ctl_traces::names(&cmds), log)
}

/// With no SDF volume in the document, SceneOperate (A) first creates one,
/// then a second A places the active component in it.
#[test]
pub(crate) fn a_with_no_volume_creates_one_then_places_the_component() {
    let (names, log) = presses_of_a(Box::new(CsgTool::default()), 2);
    assert_eq!(names, ["sdf_create", "sdf_add_operand"]);
    let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(1)).unwrap().kind else {
        panic!("no volume")
    };
    assert_eq!(v.pending.len(), 1);
}

/// With no sculpt in the document, A makes the sphere to sculpt.
#[test]
pub(crate) fn a_with_no_sculpt_creates_a_sphere() {
    let (names, log) = presses_of_a(Box::new(BrushTool::default()), 1);
    assert_eq!(names, ["sculpt_create"]);
    let obj = log.document().get(ObjectId(1)).unwrap();
    assert!(
        matches!(obj.kind, ObjectKind::SculptMesh(_)),
        "{}",
        obj.kind.name()
    );
}

fn sculpt_log() -> OpLog {
    let mut log = OpLog::new();
    log.apply(Op::SculptCreate(Create(SculptCreate {
        base: SculptBase::Sphere {
            radius: 0.1,
            edge_length: 0.02,
        },
        transform: Transform::IDENTITY,
    })))
    .unwrap();
    log
}

fn strokes(cmds: &[ScriptCommand]) -> Vec<&crate::sculpt::SculptStroke> {
    cmds.iter()
        .filter_map(|c| match c {
            ScriptCommand::Op(Op::SculptStroke(s)) => Some(&s.edit),
            _ => None,
        })
        .collect()
}

/// Right controller at the sphere's +x side, trigger at `pressure`.
fn begin_stroke(p: &mut Puppet, pressure: f64) {
    p.controller(R, at(0.3, 0.0, 0.0))
        .controller(L, at(-0.3, 0.0, 0.3))
        .wait(0.1)
        .move_to(R, at(0.11, 0.0, 0.0), 0.2)
        .trigger(R, pressure);
}

#[test]
fn brush_stroke_is_one_op_with_trigger_pressure_and_nan_ignored() {
    let mut log = sculpt_log();
    let mut p = Puppet::new(60.0);
    begin_stroke(&mut p, 0.3);
    p.move_to(R, at(0.14, 0.0, 0.0), 0.2)
        .nan_frame(R)
        .move_to(R, at(0.16, 0.0, 0.0), 0.2)
        .trigger(R, 0.0)
        .wait(0.1);
    let (cmds, previews) = drive(Box::new(BrushTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    let s = strokes(&cmds)[0];
    assert!(s.samples.len() >= 3);
    assert!(s.samples.iter().all(|x| x.pressure == 0.3));
    assert!(s
        .samples
        .iter()
        .all(|x| x.position.iter().all(|v| v.is_finite())));
    let end = DVec3::from_array(s.samples.last().unwrap().position);
    assert!((end - DVec3::new(0.16, 0.0, 0.0)).length() < 1e-6, "{end}");
    // The brush was previewed at the controller, with its world radius.
    let b = previews
        .iter()
        .find_map(|p| p.brush().copied().flatten().filter(|b| b.stroking))
        .unwrap();
    assert_eq!(b.radius, 0.07);
    assert!(previews.iter().any(|p| !p.sketch.is_empty()));
    let m = &log.document().get(ObjectId(1)).unwrap().mesh;
    assert!(mesh::validate(m, &Default::default()).is_closed_manifold());
}

#[test]
fn brush_teleport_and_lost_tracking_commit_the_stroke_cleanly() {
    // Teleport: the stroke ends at the last good sample.
    let mut log = sculpt_log();
    let mut p = Puppet::new(60.0);
    begin_stroke(&mut p, 1.0);
    p.move_to(R, at(0.14, 0.0, 0.0), 0.2)
        .teleport(R, DVec3::new(0.0, 1.0, 0.0))
        .move_to(R, at(0.2, 1.0, 0.0), 0.2)
        .trigger(R, 0.0)
        .wait(0.1);
    let (cmds, _) = drive(Box::new(BrushTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    let s = strokes(&cmds)[0];
    assert!(s.samples.iter().all(|x| x.position[1].abs() < 1e-9));
    let r = mesh::validate(
        &log.document().get(ObjectId(1)).unwrap().mesh,
        &Default::default(),
    );
    assert!(r.is_closed_manifold(), "{}", r.problems());
    // Tracking lost past the grace time: committed with what was drawn.
    let mut log = sculpt_log();
    let mut p = Puppet::new(60.0);
    begin_stroke(&mut p, 1.0);
    p.move_to(R, at(0.14, 0.0, 0.0), 0.2)
        .lose_tracking(R, 0.5)
        .move_to(R, at(0.3, 0.3, 0.0), 0.2)
        .trigger(R, 0.0)
        .wait(0.1);
    let (cmds, _) = drive(Box::new(BrushTool::default()), &mut log, &p);
    assert_eq!(cmds.len(), 1, "{cmds:?}");
    let end = DVec3::from_array(strokes(&cmds)[0].samples.last().unwrap().position);
    assert!((end - DVec3::new(0.14, 0.0, 0.0)).length() < 1e-6, "{end}");
}

#[test]
fn brush_orienting_hand_turns_and_scales_model_and_brush() {
    let mut log = sculpt_log();
    let mut p = Puppet::new(60.0);
    let hold = at(-0.3, 0.0, 0.0);
    p.controller(R, at(0.3, 0.3, 0.0))
        .controller(L, hold)
        .wait(0.1)
        .set(L, Button::Grab, true)
        .move_to(
            L,
            Pose::new(hold.position, DQuat::from_rotation_y(1.0)),
            0.3,
        )
        .move_to(R, at(-0.2, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, true)
        .move_to(R, at(-0.1, 0.0, 0.0), 0.3)
        .set(R, Button::Grab, false)
        .set(L, Button::Grab, false)
        .wait(0.1);
    let (cmds, previews) = drive(Box::new(BrushTool::default()), &mut log, &p);
    // Orienting and scaling are view changes, not edits.
    assert!(cmds.is_empty(), "{cmds:?}");
    let view = previews.last().unwrap().view.unwrap();
    assert!((view.scale - 2.0).abs() < 1e-3, "{}", view.scale);
    assert!(view.rotate.angle_between(DQuat::from_rotation_y(1.0)) < 1e-3);
    // A stroke now carries the brush at half size in model units.
    let mut s = Session::new(
        Box::new(BrushTool::new(BrushToolSettings::default())),
        Similarity::IDENTITY,
    );
    let mut q = p.clone();
    let tip = view.apply(DVec3::new(0.1, 0.0, 0.0));
    q.move_to(R, Pose::new(tip, DQuat::IDENTITY), 0.3)
        .trigger(R, 1.0)
        .move_to(
            R,
            Pose::new(tip + DVec3::new(0.02, 0.0, 0.0), DQuat::IDENTITY),
            0.2,
        )
        .trigger(R, 0.0);
    let mut out = Vec::new();
    for f in &q.trace(ModelPlacement::desk(), "").frames {
        if let Some(c) = s.step(f, log.document()) {
            log.apply_command(&c).unwrap();
            out.push(c);
        }
    }
    let st = strokes(&out);
    assert_eq!(st.len(), 1, "{out:?}");
    assert!((st[0].settings.brush_scale - 0.5).abs() < 1e-3);
    let first = DVec3::from_array(st[0].samples[0].position);
    assert!(
        (first - DVec3::new(0.1, 0.0, 0.0)).length() < 1e-4,
        "{first}"
    );
}

#[test]
fn tools_are_named_in_traces() {
    for name in crate::interact::TOOL_NAMES {
        assert_eq!(
            crate::interact::tools::tool_named(name).unwrap().name(),
            name
        );
    }
    let e = crate::interact::tools::tool_named("nope")
        .err()
        .expect("unknown");
    for name in crate::interact::TOOL_NAMES {
        assert!(e.to_string().contains(name), "{e}");
    }
}

#[test]
fn csg_menu_lists_library_components_by_name() {
    // The menu's library entries are the starters after their seven
    // primitive solids: those must be the solid kinds, and the rest the
    // 15 chair, cup and organic parts, each existing, once.
    let kinds: std::collections::BTreeSet<&str> = crate::solid::SOLID_KINDS.into_iter().collect();
    let first: std::collections::BTreeSet<&str> = crate::sdf::library::STARTER_NAMES[..7]
        .iter()
        .copied()
        .collect();
    assert_eq!(first, kinds);
    assert_eq!(super::csg_tool::MENU_LIBRARY.len(), 15);
    let mut seen = std::collections::BTreeSet::new();
    for name in super::csg_tool::MENU_LIBRARY {
        assert!(
            crate::sdf::library::starter_mesh(name).is_ok(),
            "menu entry {name} is not in the library"
        );
        assert!(seen.insert(*name), "menu entry {name} listed twice");
    }
    // The menu: the tool's primitives, then exactly the listed components.
    let menu = crate::interact::CsgToolSettings::default().components;
    let library: Vec<&str> = menu
        .iter()
        .filter_map(|c| match c {
            Component::Library { name } => Some(name.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(library, super::csg_tool::MENU_LIBRARY);
    let first_library = menu
        .iter()
        .position(|c| matches!(c, Component::Library { .. }))
        .expect("library entries on the menu");
    assert!(menu[..first_library]
        .iter()
        .all(|c| matches!(c, Component::Solid { .. })));
}
