//! The modeler session as a user meets it: the palette opens on the off
//! hand, every tool and every choice is one pick away, picks never reach
//! the tool, and switching keeps the document, the history and each
//! tool's choices.

use crate::doc::{Create, Op, ScriptCommand};
use crate::sdf::SdfCreate;

use crate::interact::palette::PaletteAction;
use crate::interact::testkit::{Button, Driver};
use crate::interact::{replay, Hand, Pose, TOOL_NAMES};
use crate::math::{DQuat, DVec3};

#[test]
pub(crate) fn the_palette_reaches_every_tool_and_every_choice() {
    let mut d = Driver::new(72.0, "object");
    // A volume, so the CSG grid-step choice has something to set.
    d.log
        .apply(Op::SdfCreate(Create(SdfCreate {
            step: crate::sdf::volume::DEFAULT_STEP,
        })))
        .unwrap();
    d.open_palette();
    let view = d
        .session()
        .palette()
        .expect("the left menu button opens it");
    for label in crate::interact::palette::TOOL_LABELS {
        assert!(view.labels().contains(&label), "{label} missing");
    }
    assert_eq!(
        TOOL_NAMES.len(),
        crate::interact::palette::TOOL_LABELS.len()
    );
    let mut picked = 0;
    for name in TOOL_NAMES {
        d.pick_tool(name).unwrap();
        assert_eq!(d.session().tool().name(), name);
        let groups = d.session().tool().choices();
        for (g, group) in groups.iter().enumerate() {
            for o in 0..group.options.len() {
                let before = d.commands.len();
                d.pick_choice(g, o).unwrap();
                let now = &d.session().tool().choices()[g];
                if ["Fused result", "Release", "Component from"].contains(&group.name) {
                    // An action on the fused result: nothing to copy in an
                    // empty volume (tested on the cup below).
                    assert_eq!(d.commands.len(), before);
                } else if ["Grid step", "Wall", "Overlaps", "Printer"].contains(&group.name) {
                    // A document setting: its op, applied, then shown.
                    let stepped =
                        d.commands.len() > before || d.session().tool().choices()[g].active == o;
                    assert!(stepped, "grid step {o} did nothing");
                    d.puppet.wait(0.05);
                    d.sync();
                    assert_eq!(d.session().tool().choices()[g].active, o);
                } else {
                    assert_eq!(now.active, o, "{name}: {} option {o}", group.name);
                    assert_eq!(d.commands.len(), before, "a choice made an op");
                }
                picked += 1;
            }
        }
    }
    // object shapes 7 + csg (components + 4 ops + 4 axes + 5 steps) +
    // curve 5 + sculpt (presets + 6 sizes): more than 60 picks.
    assert!(picked > 60, "{picked} picks");
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    // Every op came from a grid-step choice (4 of the 5 steps differ from
    // the default): no pick reached a tool as a trigger press.
    let names: Vec<_> = d.commands.iter().map(|c| c.name()).collect();
    assert!(
        d.commands.iter().all(|c| matches!(
            c,
            ScriptCommand::Op(
                Op::SdfSetStep(_)
                    | Op::SetWallThickness(_)
                    | Op::SetSelfIntersectionPolicy(_)
                    | Op::SetPrinter(_)
            )
        )),
        "{names:?}"
    );
    // Choices survive switching away and back.
    d.pick_tool("sculpt").unwrap();
    let brush = d.session().tool().choices()[0].active;
    d.pick_tool("object").unwrap().pick_tool("sculpt").unwrap();
    assert_eq!(d.session().tool().choices()[0].active, brush);
}

#[test]
fn undo_redo_save_and_snapping_are_in_the_palette_and_replay_identically() {
    let mut d = Driver::new(72.0, "object");
    d.sync();
    // Place a box with the object tool (primary), then undo and redo it
    // from the palette.
    d.close_palette();
    d.puppet.click(Hand::Right, Button::Primary);
    d.sync();
    assert_eq!(d.log.document().len(), 1);
    d.pick_action(PaletteAction::Undo).unwrap();
    assert_eq!(d.log.document().len(), 0);
    d.pick_action(PaletteAction::Redo).unwrap();
    assert_eq!(d.log.document().len(), 1);
    d.pick_action(PaletteAction::Save).unwrap();
    assert_eq!(d.saves, 1);
    d.pick_action(PaletteAction::Grid).unwrap();
    d.pick_action(PaletteAction::Angle).unwrap();
    let snap = d.session().snap();
    assert!(snap.grid > 0.0 && snap.angle > 0.0);
    // The menu press of the off hand toggles the palette and nothing else;
    // a closed palette hides.
    d.close_palette();
    assert!(d.session().palette().is_none());
    // A drag with snapping on: the box (placed at the right controller)
    // grabbed, moved 2.37 cm and turned 20 degrees lands on the 1 mm grid
    // and at 15 degrees; the readout says so while dragging.
    let boxed = DVec3::new(0.2, 1.1, -0.3); // where the right hand placed it
    d.puppet
        .aim(Hand::Right, boxed + DVec3::new(0.0, 0.0, 0.2), boxed, 0.3);
    d.puppet.set(Hand::Right, Button::Grab, true);
    let moved = Pose::new(
        d.puppet.frames().last().unwrap().controllers[1]
            .unwrap()
            .grip
            .position
            + DVec3::new(0.0237, 0.0, 0.0),
        d.puppet.frames().last().unwrap().controllers[1]
            .unwrap()
            .grip
            .orientation
            * DQuat::from_rotation_y(20f64.to_radians()),
    );
    d.puppet.move_to(Hand::Right, moved, 0.3);
    d.sync();
    let readout = d.session().preview().readout.clone();
    assert!(
        readout.contains("grid 1 mm") && readout.contains("snap 15°"),
        "{readout}"
    );
    d.puppet.set(Hand::Right, Button::Grab, false).wait(0.1);
    d.sync();
    let Some(ScriptCommand::Op(Op::SetTransform(t))) = d.commands.last() else {
        panic!("no set_transform: {:?}", d.commands.last())
    };
    for c in t.transform.translate {
        assert!(
            (c * 1000.0 - (c * 1000.0).round()).abs() < 1e-6,
            "{c} off the grid"
        );
    }
    let angle = DQuat::from_array(t.transform.rotate)
        .to_axis_angle()
        .1
        .to_degrees();
    assert!((angle - 15.0).abs() < 1e-6, "{angle}");
    let trace = d.trace("palette undo/redo/save");
    let text = trace.to_jsonl();
    let back = crate::interact::Trace::from_jsonl(&text).unwrap();
    assert!(back.header.modeler);
    for _ in 0..2 {
        let r = replay(&back).unwrap();
        assert_eq!(r.commands, d.commands);
        assert_eq!(r.saves.len(), 1);
        assert_eq!(r.log.document().len(), 1);
        assert!(matches!(
            r.commands.last(),
            Some(ScriptCommand::Op(Op::SetTransform(_)))
        ));
    }
}

/// Hand tracking without controllers: the left hand held palm up shows
/// the palette, the right index fingertip picks by touching an item, and
/// turning the palm down hides it again.
#[test]
fn a_palm_up_hand_shows_the_palette_and_a_fingertip_picks() {
    use crate::interact::gesture::handmodel::hand_pose;
    use crate::interact::gesture::GestureLabel;
    use crate::interact::testkit::feed_quietly;
    use crate::interact::testkit::Puppet;
    use crate::interact::{Joint, ModelPlacement, Pose, Session};
    use crate::math::{DQuat, DVec3};

    let params = crate::interact::testkit::hand_params;
    let joint =
        |label, hand, wrist: Pose, j: Joint| hand_pose(&params(label), hand, &wrist)[j.index()];
    // A wrist turn that puts the left palm facing up (and one facing down).
    let turns: Vec<DQuat> = (0..4)
        .flat_map(|i| (0..4).map(move |k| (i, k)))
        .map(|(i, k)| {
            DQuat::from_rotation_z(i as f64 * std::f64::consts::FRAC_PI_2)
                * DQuat::from_rotation_x(k as f64 * std::f64::consts::FRAC_PI_2)
        })
        .collect();
    let palm_up = |q: DQuat| {
        let palm = joint(
            GestureLabel::Open,
            Hand::Left,
            Pose::new(DVec3::ZERO, q),
            Joint::Palm,
        );
        (palm.orientation * -DVec3::Y).y
    };
    let up = *turns
        .iter()
        .max_by(|a, b| palm_up(**a).total_cmp(&palm_up(**b)))
        .unwrap();
    let down = *turns
        .iter()
        .min_by(|a, b| palm_up(**a).total_cmp(&palm_up(**b)))
        .unwrap();
    assert!(palm_up(up) > 0.9 && palm_up(down) < -0.9);

    let model = ModelPlacement::desk().similarity().unwrap();
    let mut s = Session::modeler("object", Hand::Right, model).unwrap();
    let doc = crate::doc::Document::default();
    let left = DVec3::new(-0.25, 1.0, -0.3);
    let mut p = Puppet::new(60.0);
    p.look_at(DVec3::new(0.0, 0.95, -0.5))
        .hand(Hand::Left, GestureLabel::Open, Pose::new(left, up))
        .hand(
            Hand::Right,
            GestureLabel::Point,
            Pose::new(DVec3::new(0.3, 1.0, -0.2), DQuat::IDENTITY),
        )
        .wait(0.3);
    let mut fed = 0;
    let mut feed = |p: &Puppet, s: &mut Session| feed_quietly(p, s, &doc, &mut fed);
    feed(&p, &mut s);
    let view = s
        .palette()
        .expect("a palm-up left hand shows the palette")
        .clone();
    assert!(view.pose.position.y > left.y, "above the hand");
    // Touch "CSG": the right index tip from 4 cm in front to 2 mm.
    let k = view.labels().iter().position(|l| *l == "CSG").unwrap();
    let r = view.items[k].rect;
    let target = view.to_world((r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0);
    let n = view.pose.orientation * DVec3::Z;
    let tip = joint(
        GestureLabel::Point,
        Hand::Right,
        Pose::IDENTITY,
        Joint::IndexTip,
    )
    .position;
    let wrist_for = |at: DVec3| Pose::new(at - tip, DQuat::IDENTITY);
    p.move_to(Hand::Right, wrist_for(target + n * 0.04), 0.3);
    feed(&p, &mut s);
    assert_eq!(s.tool().name(), "object", "no pick before the touch");
    assert!(s.palette().unwrap().hovered.is_some() || s.palette().unwrap().pointer.is_some());
    p.move_to(Hand::Right, wrist_for(target + n * 0.002), 0.3)
        .wait(0.2);
    feed(&p, &mut s);
    assert_eq!(s.tool().name(), "csg", "the fingertip picked CSG");
    // Staying on the item does not pick again; turning the palm down
    // hides the palette.
    p.move_to(Hand::Right, wrist_for(target + n * 0.05), 0.2)
        .move_to(Hand::Left, Pose::new(left, down), 0.3)
        .wait(0.1);
    feed(&p, &mut s);
    assert!(s.palette().is_none());
    assert_eq!(s.tool().name(), "csg");
}

/// However many rows the active tool's choices take, the palette grows
/// upwards: no item reaches down to the hand that holds it.
#[test]
fn the_palette_floats_above_the_hand_for_every_tool() {
    let mut d = Driver::new(72.0, "object");
    for name in TOOL_NAMES {
        d.pick_tool(name).unwrap();
        let view = d.session().palette().unwrap().clone();
        let hand = d.puppet.frames().last().unwrap().controllers[Hand::Left.index()]
            .unwrap()
            .grip
            .position;
        let lowest = view
            .items
            .iter()
            .flat_map(|i| {
                let [x0, y0, x1, y1] = i.rect;
                [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
            })
            .map(|(x, y)| view.to_world(x, y).y)
            .fold(f64::INFINITY, f64::min);
        println!(
            "{name}: {} items, lowest {:.3} m above the hand",
            view.items.len(),
            lowest - hand.y
        );
        assert!(
            lowest > hand.y + 0.04,
            "{name}: an item {:.3} m above the hand",
            lowest - hand.y
        );
    }
}

/// From afar, a tracked hand points with its wrist-to-knuckle ray and
/// picks by closing a pinch; an open pinch only hovers.
#[test]
fn a_tracked_hand_picks_from_afar_by_pinching() {
    use crate::interact::gesture::handmodel::hand_pose;
    use crate::interact::gesture::GestureLabel;
    use crate::interact::testkit::feed_quietly;
    use crate::interact::testkit::Puppet;
    use crate::interact::{Joint, ModelPlacement, Session};

    let params = crate::interact::testkit::hand_params;
    let model = ModelPlacement::desk().similarity().unwrap();
    let mut s = Session::modeler("object", Hand::Right, model).unwrap();
    let doc = crate::doc::Document::default();
    let mut p = Puppet::new(60.0);
    p.look_at(DVec3::new(0.0, 0.95, -0.5))
        .controller(
            Hand::Left,
            Pose::new(DVec3::new(-0.25, 1.05, -0.3), DQuat::IDENTITY),
        )
        .hand(
            Hand::Right,
            GestureLabel::Open,
            Pose::new(DVec3::new(0.3, 0.8, 0.0), DQuat::IDENTITY),
        )
        .click(Hand::Left, Button::Menu)
        .wait(0.1);
    let mut fed = 0;
    let mut feed = |p: &Puppet, s: &mut Session| feed_quietly(p, s, &doc, &mut fed);
    feed(&p, &mut s);
    let view = s.palette().expect("the menu button opened it").clone();
    let k = view.labels().iter().position(|l| *l == "Curve").unwrap();
    let r = view.items[k].rect;
    let target = view.to_world((r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0);
    let n = view.pose.orientation * DVec3::Z;
    // A wrist turn whose wrist-to-knuckle ray points into the palette.
    let ray_of = |label, q: DQuat| {
        let j = hand_pose(&params(label), Hand::Right, &Pose::new(DVec3::ZERO, q));
        let knuckle = j[Joint::IndexProximal.index()].position;
        (
            knuckle,
            (knuckle - j[Joint::Wrist.index()].position).normalize(),
        )
    };
    let q = (0..24)
        .flat_map(|i| (0..24).map(move |k| (i, k)))
        .map(|(i, k)| {
            DQuat::from_rotation_y(i as f64 * std::f64::consts::TAU / 24.0)
                * DQuat::from_rotation_x(k as f64 * std::f64::consts::TAU / 24.0)
        })
        .max_by(|a, b| {
            let along = |q: DQuat| -ray_of(GestureLabel::PinchOpen, q).1.dot(n);
            along(*a).total_cmp(&along(*b))
        })
        .unwrap();
    // 35 cm away along the ray, for each pinch state.
    let wrist_for = |label| {
        let (knuckle, dir) = ray_of(label, q);
        Pose::new(target - dir * 0.35 - knuckle, q)
    };
    p.hand(
        Hand::Right,
        GestureLabel::PinchOpen,
        wrist_for(GestureLabel::PinchOpen),
    )
    .wait(0.2);
    feed(&p, &mut s);
    let v = s.palette().unwrap();
    assert_eq!(v.hovered, Some(k), "the ray hovers Curve");
    assert_eq!(s.tool().name(), "object", "an open pinch does not pick");
    p.hand(
        Hand::Right,
        GestureLabel::PinchClosed,
        wrist_for(GestureLabel::PinchClosed),
    )
    .wait(0.2);
    feed(&p, &mut s);
    assert_eq!(s.tool().name(), "curve", "closing the pinch picked Curve");
    // Holding the pinch does not pick again; the next item needs a new pinch.
    let j = view.labels().iter().position(|l| *l == "Sculpt").unwrap();
    let r = view.items[j].rect;
    let other = view.to_world((r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0);
    let (knuckle, dir) = ray_of(GestureLabel::PinchClosed, q);
    p.hand(
        Hand::Right,
        GestureLabel::PinchClosed,
        Pose::new(other - dir * 0.35 - knuckle, q),
    )
    .wait(0.2);
    feed(&p, &mut s);
    assert_eq!(s.tool().name(), "curve");
}

/// The CSG tool's "Fused result: copy beside" is `sdf_copy_fused` on the
/// volume, with a fresh component name each time; it applies.
#[test]
pub(crate) fn the_fused_result_is_copied_from_the_palette() {
    use crate::doc::OpLog;
    use crate::interact::tools::Tool;
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/csg_cup.jsonl"),
    )
    .unwrap();
    let mut log = OpLog::new();
    for l in text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
    {
        log.apply(serde_json::from_str(l).unwrap()).unwrap();
    }
    let mut tool = crate::interact::CsgTool::default();
    let g = tool
        .choices()
        .iter()
        .position(|g| g.name == "Fused result")
        .unwrap();
    for k in 1..=2 {
        let Some(ScriptCommand::Op(op @ Op::SdfCopyFused(_))) = tool.choose(log.document(), g, 0)
        else {
            panic!("no sdf_copy_fused")
        };
        let Op::SdfCopyFused(c) = &op else {
            unreachable!()
        };
        assert_eq!(c.edit.name, format!("result {k}"));
        // As a host applies what a tool chose.
        log.apply_command(&ScriptCommand::Op(op)).unwrap();
    }
    let (_, obj) = log.document().objects().next().unwrap();
    let crate::doc::ObjectKind::SdfVolume(v) = &obj.kind else {
        panic!("the cup is a volume")
    };
    assert_eq!(v.pending.len(), 2);
    assert!(v.user_components.contains_key("result 2"));
}

/// Paper 3 §5.4 in the headset: with "Draw in: left hand" chosen, a
/// stroke drawn while the left hand turns the frame is one
/// `curve_draw_in_frame` with the frame at every sample; it applies, and
/// the network has moved with the hand.
#[test]
pub(crate) fn strokes_drawn_in_the_left_hands_frame_move_with_it() {
    use crate::doc::OpLog;
    use crate::interact::testkit::Puppet;
    use crate::interact::tools::Tool;
    use crate::interact::{CurveNetworkTool, ModelPlacement, Session};

    let mut tool = CurveNetworkTool::default();
    let g = tool
        .choices()
        .iter()
        .position(|g| g.name == "Draw in")
        .unwrap();
    tool.choose(&crate::doc::Document::default(), g, 1);
    assert_eq!(tool.choices()[g].active, 1);
    let model = ModelPlacement::desk().similarity().unwrap();
    let mut s = Session::new(Box::new(tool), model);
    let left = Pose::new(DVec3::new(-0.2, 1.0, -0.4), DQuat::IDENTITY);
    let mut p = Puppet::new(60.0);
    p.controller(Hand::Left, left)
        .controller(
            Hand::Right,
            Pose::new(DVec3::new(0.1, 1.0, -0.4), DQuat::IDENTITY),
        )
        .wait(0.1)
        .set(Hand::Right, Button::Select, true);
    // Draw 10 cm sideways while the left hand turns 40 degrees.
    for k in 1..=40 {
        let a = k as f64 / 40.0;
        p.move_to(
            Hand::Right,
            Pose::new(
                DVec3::new(0.1 + 0.1 * a, 1.0 + 0.03 * a, -0.4),
                DQuat::IDENTITY,
            ),
            0.0,
        )
        .move_to(
            Hand::Left,
            Pose::new(
                left.position,
                DQuat::from_rotation_y(40f64.to_radians() * a),
            ),
            0.0,
        );
    }
    p.set(Hand::Right, Button::Select, false).wait(0.1);
    let mut log = OpLog::new();
    let mut cmds = Vec::new();
    for f in p.frames() {
        if let Some(c) = s.step(f, log.document()) {
            log.apply_command(&c).unwrap();
            cmds.push(c);
        }
    }
    let names: Vec<_> = cmds.iter().map(|c| c.name()).collect();
    assert_eq!(names, ["curve_network_create", "curve_draw_in_frame"]);
    let Some(ScriptCommand::Op(Op::CurveDrawInFrame(d))) = cmds.last() else {
        unreachable!()
    };
    assert!(d.samples.len() >= 4 && d.frames.len() == d.samples.len());
    let q = |f: &crate::styling::ModelingFrame| DQuat::from_array(f.rotation);
    let (first, last) = (d.frames.first().unwrap(), d.frames.last().unwrap());
    let turned = q(first).angle_between(q(last)).to_degrees();
    assert!(turned > 30.0, "the frame turned {turned} degrees");
    // The network moved with the hand: its placement turned too.
    let (_, obj) = log.document().objects().next().unwrap();
    let q = DQuat::from_array(obj.transform().rotate);
    assert!(
        q.angle_between(DQuat::IDENTITY).to_degrees() > 30.0,
        "{q:?}"
    );
}
