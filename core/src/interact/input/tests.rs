//! Tests of the input layer: the sanitizer against bad frames (NaN,
//! lost tracking, time going backwards) and traces keeping non-finite
//! numbers.

use super::joints::*;
use super::pose::*;
use super::raw::*;
use super::sanitizer::*;
use crate::math::{DQuat, DVec3};

fn controller_at(p: DVec3) -> ControllerSample {
    ControllerSample {
        grip: Pose::new(p, DQuat::IDENTITY),
        grip_valid: true,
        aim: Pose::new(p, DQuat::IDENTITY),
        aim_valid: true,
        buttons: ControllerButtons::default(),
        buttons_valid: true,
    }
}

fn frame(t: f64, c: ControllerSample) -> InputFrame {
    InputFrame {
        time: t,
        head: Some(Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY)),
        hands: [None, None],
        controllers: [None, Some(c)],
    }
}

#[test]
fn drops_bad_times_without_changing_state() {
    let mut s = Sanitizer::default();
    assert!(s.accept(&frame(1.0, controller_at(DVec3::ZERO))).is_some());
    assert!(s
        .accept(&frame(f64::NAN, controller_at(DVec3::ZERO)))
        .is_none());
    assert!(s.accept(&frame(0.5, controller_at(DVec3::ZERO))).is_none());
    let f = s.accept(&frame(1.1, controller_at(DVec3::ZERO))).unwrap();
    assert!((f.dt - 0.1).abs() < 1e-12);
}

#[test]
fn drops_non_finite_samples() {
    let mut s = Sanitizer::default();
    let mut c = controller_at(DVec3::new(f64::NAN, 0.0, 0.0));
    c.buttons.select = f64::INFINITY;
    c.aim.orientation = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let f = s.accept(&frame(0.0, c)).unwrap();
    let c = f.controller(Hand::Right).unwrap();
    assert_eq!((c.grip, c.aim, c.buttons), (None, None, None));
    assert!(!c.teleported);
    // The NaN grip did not become the reference for teleport detection.
    let f = s.accept(&frame(0.01, controller_at(DVec3::ZERO))).unwrap();
    assert!(!f.controller(Hand::Right).unwrap().teleported);
    let f = s
        .accept(&frame(0.02, controller_at(DVec3::new(1.0, 0.0, 0.0))))
        .unwrap();
    assert!(f.controller(Hand::Right).unwrap().teleported);
}

#[test]
fn hand_with_nan_fingertip_is_dropped() {
    let mut s = Sanitizer::default();
    let mut joints = [JointSample {
        valid: true,
        ..Default::default()
    }; JOINT_COUNT];
    joints[Joint::IndexTip.index()].pose.position.x = f64::NAN;
    let mut f = frame(0.0, controller_at(DVec3::ZERO));
    f.hands[0] = Some(HandSample {
        active: true,
        joints,
        source: HandSource::Unknown,
    });
    assert!(s.accept(&f).unwrap().hands[0].is_none());
    joints[Joint::IndexTip.index()].pose.position.x = 0.0;
    f.hands[0] = Some(HandSample {
        active: true,
        joints,
        source: HandSource::Unknown,
    });
    f.time = 1.0;
    assert!(s.accept(&f).unwrap().hands[0].is_some());
}

fn hand_at(source: HandSource) -> HandSample {
    HandSample {
        active: true,
        joints: [JointSample {
            valid: true,
            ..Default::default()
        }; JOINT_COUNT],
        source,
    }
}

#[test]
fn controller_buttons_override_derived_hands_but_not_optical_ones() {
    let mut s = Sanitizer::default();
    let mut f = frame(0.0, controller_at(DVec3::ZERO));
    f.hands[1] = Some(hand_at(HandSource::Controller));
    f.hands[0] = Some(hand_at(HandSource::Controller));
    let out = s.accept(&f).unwrap();
    // Right: valid buttons, controller-derived joints: the buttons win.
    assert!(out.hands[1].is_none());
    // Left: no controller there, so the joints are all there is.
    assert!(out.hands[0].is_some());
    // Unknown source counts as derived; optical joints are kept.
    f.time = 1.0;
    f.hands[1] = Some(hand_at(HandSource::Unknown));
    assert!(s.accept(&f).unwrap().hands[1].is_none());
    f.time = 2.0;
    f.hands[1] = Some(hand_at(HandSource::Optical));
    assert!(s.accept(&f).unwrap().hands[1].is_some());
    // Buttons not valid (controller asleep): the joints are used.
    f.time = 3.0;
    f.hands[1] = Some(hand_at(HandSource::Controller));
    f.controllers[1].as_mut().unwrap().buttons_valid = false;
    assert!(s.accept(&f).unwrap().hands[1].is_some());
    assert_eq!(s.stats().hands_overridden, 2);
    // The rule can be turned off.
    let mut off = Sanitizer::new(SanitizerSettings {
        buttons_over_hands: false,
        ..Default::default()
    });
    let mut f = frame(0.0, controller_at(DVec3::ZERO));
    f.hands[1] = Some(hand_at(HandSource::Controller));
    assert!(off.accept(&f).unwrap().hands[1].is_some());
}

#[test]
fn far_positions_and_non_unit_quaternions_are_rejected_and_counted() {
    let mut s = Sanitizer::default();
    let mut c = controller_at(DVec3::new(2.0e4, 0.0, 0.0));
    c.aim.orientation = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.5);
    let f = s.accept(&frame(0.0, c)).unwrap();
    let c = f.controller(Hand::Right).unwrap();
    assert!(c.grip.is_none() && c.aim.is_none());
    // Slightly off unit (rounding) is normalized, not dropped.
    let mut c = controller_at(DVec3::ZERO);
    c.aim.orientation = DQuat::from_xyzw(0.0, 0.0, 0.0, 1.05);
    let f = s.accept(&frame(1.0, c)).unwrap();
    let aim = f.controller(Hand::Right).unwrap().aim.unwrap();
    assert!((aim.orientation.w - 1.0).abs() < 1e-12);
    let st = s.stats();
    assert_eq!(
        (st.poses_rejected, st.poses_untracked, st.frames),
        (2, 0, 2)
    );
    // An invalid pose is untracked, not rejected; a missing head too.
    let mut c = controller_at(DVec3::ZERO);
    c.grip_valid = false;
    let mut f = frame(2.0, c);
    f.head = None;
    s.accept(&f).unwrap();
    assert_eq!(s.stats().poses_untracked, 2);
    assert!(s.accept(&frame(1.5, controller_at(DVec3::ZERO))).is_none());
    assert_eq!(s.stats().frames_dropped, 1);
}

#[test]
fn non_finite_numbers_survive_a_trace_round_trip() {
    let mut c = controller_at(DVec3::new(f64::NAN, 1.0, f64::NEG_INFINITY));
    c.aim.position = DVec3::new(0.1, 1.0, -0.2);
    c.buttons.select = f64::INFINITY;
    c.buttons.stick = [f64::NAN, 0.5];
    let f = frame(0.25, c);
    let text = serde_json::to_string(&f).unwrap();
    assert!(text.contains(r#""p":["NaN",1.0,"-inf"]"#), "{text}");
    let back: InputFrame = serde_json::from_str(&text).unwrap();
    let b = back.controllers[1].unwrap();
    assert!(b.grip.position.x.is_nan() && b.grip.position.z == f64::NEG_INFINITY);
    assert_eq!(b.buttons.select, f64::INFINITY);
    assert!(b.buttons.stick[0].is_nan() && b.buttons.stick[1] == 0.5);
    // The sanitizer drops exactly these after the round trip.
    let mut s = Sanitizer::default();
    let out = s.accept(&back).unwrap();
    let c = out.controller(Hand::Right).unwrap();
    assert!(c.grip.is_none() && c.buttons.is_none() && c.aim.is_some());
    assert!(serde_json::from_str::<InputFrame>(r#"{"time":"later"}"#).is_err());
}

#[test]
fn recorded_trace_lines_serialize_back_byte_for_byte() {
    // Finite numbers keep their exact form: every fixture line parses
    // and prints back to the same text (hand sources left out).
    for name in ["teapot_controller", "teapot", "csg_cup"] {
        let p = format!(
            "{}/../tests/data/{name}.trace.jsonl",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(p).unwrap();
        for line in text.lines().skip(1).step_by(97) {
            let f: InputFrame = serde_json::from_str(line).unwrap();
            assert_eq!(serde_json::to_string(&f).unwrap(), line);
        }
    }
}
