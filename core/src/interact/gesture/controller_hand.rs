//! Hands made from controllers, so that the hand-gesture tool of paper 1
//! (§4: OPEN, FIST, POINT, PINCH) also runs where no hand is tracked:
//! Blender's VR session (controllers only), and headsets whose runtime
//! lacks `XR_EXT_hand_tracking`.
//!
//! The buttons choose the pose, the aim pose places it:
//!
//! | buttons                       | hand                                  |
//! |-------------------------------|---------------------------------------|
//! | none                          | OPEN: the ray selects                 |
//! | trigger                       | POINT: the index tip sketches         |
//! | grip                          | FIST: drag, hold, two-hand view       |
//! | A/X (primary)                 | PINCH, the gap closing as the trigger is pressed (fully: closed) |
//!
//! The hand is the kinematic hand model's pose for that gesture (the
//! parameters the puppet uses), its palm at the aim position and its ray
//! (palm along the mean knuckle direction, as the tool reads it) along the
//! aim direction, back of the hand towards the aim pose's +Y. The gesture
//! classifier then reads it like any tracked hand, with the same debounce;
//! nothing downstream knows the difference. A synthesized hand is used only
//! for a hand the runtime does not track, and only when the active tool
//! asks for hands ([`crate::interact::Tool::uses_hands`]).

use crate::math::{DQuat, DVec3};

use crate::interact::gesture::handmodel::{hand_pose, HandParams, Rng};
use crate::interact::gesture::GestureLabel;
use crate::interact::input::{
    Controller, ControllerButtons, Hand, HandJoints, Joint, Pose, JOINT_COUNT,
};

/// The widest pinch gap (trigger released), metres.
const MAX_PINCH_GAP: f64 = 0.06;

/// The gesture `buttons` stand for, and the pinch gap (metres) for a
/// pinch.
pub fn controller_gesture(b: &ControllerButtons) -> (GestureLabel, f64) {
    if b.grab > 0.5 {
        (GestureLabel::Fist, 0.0)
    } else if b.primary {
        let gap = MAX_PINCH_GAP * (1.0 - b.select.clamp(0.0, 1.0));
        if gap < 0.004 {
            (GestureLabel::PinchClosed, gap)
        } else {
            (GestureLabel::PinchOpen, gap)
        }
    } else if b.select > 0.5 {
        (GestureLabel::Point, 0.0)
    } else {
        (GestureLabel::Open, 0.0)
    }
}

/// The hand model's parameters for `label` (as the puppet shows it).
fn params(label: GestureLabel, gap: f64) -> HandParams {
    let mut rng = Rng::new(label as u64 + 100);
    let mut p = HandParams::sample(label, &mut rng);
    p.size = 1.0;
    if matches!(label, GestureLabel::PinchOpen | GestureLabel::PinchClosed) {
        p.pinch_gap = gap;
    }
    p
}

/// The wrist pose that puts the palm at `aim`'s position with the hand's
/// ray along `aim`'s forward (-Z), for a hand in pose `p`.
fn wrist_for(aim: &Pose, p: &HandParams, hand: Hand) -> Pose {
    let local = hand_pose(p, hand, &Pose::IDENTITY);
    let at = |j: Joint| local[j.index()].position;
    let knuckles = [
        Joint::IndexProximal,
        Joint::MiddleProximal,
        Joint::RingProximal,
        Joint::LittleProximal,
    ];
    let k = knuckles.iter().map(|&j| at(j)).sum::<DVec3>() * 0.25;
    let ray = (k - at(Joint::Wrist)).normalize_or(DVec3::NEG_Z);
    let q = aim.orientation * DQuat::from_rotation_arc(ray, DVec3::NEG_Z);
    Pose::new(aim.position - q * at(Joint::Palm), q)
}

/// The hand a controller stands for (its aim pose and buttons), or `None`
/// without a valid aim pose and buttons.
pub fn controller_hand(c: &Controller, hand: Hand) -> Option<HandJoints> {
    let (aim, buttons) = (c.aim?, c.buttons?);
    let (label, gap) = controller_gesture(&buttons);
    let p = params(label, gap);
    let joints = hand_pose(&p, hand, &wrist_for(&aim, &p, hand));
    let mut out = HandJoints {
        joints: [None; JOINT_COUNT],
    };
    for (o, j) in out.joints.iter_mut().zip(joints) {
        *o = j.sanitized();
    }
    Some(out)
}

/// Where the index tip of the POINT hand lies in the aim frame (a sketch
/// is drawn there): the controller pose that puts the tip at a point is
/// that point minus this offset, rotated.
pub fn point_tip_offset(hand: Hand) -> DVec3 {
    let p = params(GestureLabel::Point, 0.0);
    let wrist = wrist_for(&Pose::IDENTITY, &p, hand);
    hand_pose(&p, hand, &wrist)[Joint::IndexTip.index()].position
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interact::gesture::{Gesture, GestureClassifier};

    fn controller(aim: Pose, b: ControllerButtons) -> Controller {
        Controller {
            grip: Some(aim),
            aim: Some(aim),
            buttons: Some(b),
            teleported: false,
        }
    }

    /// Every button combination reads as its gesture through the real
    /// classifier, for both hands and a tilted aim pose.
    #[test]
    fn buttons_classify_as_their_gestures() {
        let aim = Pose::new(
            DVec3::new(0.2, 1.2, -0.3),
            DQuat::from_euler(glam::EulerRot::YXZ, 0.4, -0.5, 0.2),
        );
        let head = Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY);
        let cases = [
            (ControllerButtons::default(), Gesture::Open, false),
            (
                ControllerButtons {
                    select: 1.0,
                    ..Default::default()
                },
                Gesture::Point,
                false,
            ),
            (
                ControllerButtons {
                    grab: 1.0,
                    ..Default::default()
                },
                Gesture::Fist,
                false,
            ),
            (
                ControllerButtons {
                    primary: true,
                    ..Default::default()
                },
                Gesture::Pinch,
                false,
            ),
            (
                ControllerButtons {
                    primary: true,
                    select: 1.0,
                    ..Default::default()
                },
                Gesture::Pinch,
                true,
            ),
        ];
        for hand in Hand::BOTH {
            for (b, want, closed) in cases {
                let h = controller_hand(&controller(aim, b), hand).expect("a hand");
                let mut c = GestureClassifier::default();
                let mut s = c.state();
                for k in 0..30 {
                    s = c.update(k as f64 / 90.0, Some(&h), Some(&head));
                }
                assert_eq!(s.gesture, want, "{hand:?} {b:?}");
                if want == Gesture::Pinch {
                    assert_eq!(s.pinch_closed, closed, "{hand:?} {b:?}");
                }
            }
        }
    }

    /// The tool's ray (palm, mean knuckle direction) is the aim ray.
    #[test]
    fn the_hand_ray_is_the_aim_ray() {
        let aim = Pose::new(
            DVec3::new(-0.1, 1.1, -0.4),
            DQuat::from_euler(glam::EulerRot::YXZ, -0.7, 0.3, 0.0),
        );
        for hand in Hand::BOTH {
            let h = controller_hand(&controller(aim, ControllerButtons::default()), hand)
                .expect("a hand");
            let palm = h.pos(Joint::Palm).expect("palm");
            let wrist = h.pos(Joint::Wrist).expect("wrist");
            let k = [
                Joint::IndexProximal,
                Joint::MiddleProximal,
                Joint::RingProximal,
                Joint::LittleProximal,
            ]
            .map(|j| h.pos(j).expect("knuckle"))
            .iter()
            .sum::<DVec3>()
                * 0.25;
            assert!((palm - aim.position).length() < 1e-12);
            let dir = (k - wrist).normalize();
            assert!(dir.dot(aim.forward()) > 1.0 - 1e-12, "{hand:?}");
        }
    }

    #[test]
    fn no_aim_or_buttons_no_hand() {
        let mut c = controller(Pose::IDENTITY, ControllerButtons::default());
        c.aim = None;
        assert!(controller_hand(&c, Hand::Right).is_none());
        let mut c = controller(Pose::IDENTITY, ControllerButtons::default());
        c.buttons = None;
        assert!(controller_hand(&c, Hand::Left).is_none());
    }
}
