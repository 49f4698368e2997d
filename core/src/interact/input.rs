//! Per-frame input as hosts deliver it ([`InputFrame`]), and the
//! sanitizing layer ([`Sanitizer`]) that every tool sits behind.
//!
//! Coordinates are the OpenXR stage space: metres, +Y up, right-handed.
//! Hands are indexed by [`Hand`] (`0` left, `1` right).
//!
//! Raw samples carry validity flags exactly as OpenXR reports them
//! (`XrSpaceLocationFlags`, `XrHandJointLocationEXT::locationFlags`, the
//! `isActive` of each action). The sanitizer turns a raw frame into a
//! [`Frame`] in which an untracked or non-finite sample is simply absent
//! (`None`), so a tool cannot read a NaN by mistake: a sample that fails is
//! dropped and never changes any state downstream.

use serde::{Deserialize, Serialize};

use crate::math::{DQuat, DVec3};

/// Left or right.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Hand {
    /// The left hand (index 0).
    Left,
    /// The right hand (index 1).
    Right,
}

impl Hand {
    /// Both hands, left first.
    pub const BOTH: [Hand; 2] = [Hand::Left, Hand::Right];

    /// 0 for left, 1 for right.
    pub fn index(self) -> usize {
        match self {
            Hand::Left => 0,
            Hand::Right => 1,
        }
    }

    /// The other hand.
    pub fn other(self) -> Hand {
        match self {
            Hand::Left => Hand::Right,
            Hand::Right => Hand::Left,
        }
    }
}

/// A rigid pose: position and orientation (a unit quaternion).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position in metres (`"p"` in traces).
    #[serde(rename = "p")]
    pub position: DVec3,
    /// Orientation `[x, y, z, w]` (`"q"` in traces).
    #[serde(rename = "q")]
    pub orientation: DQuat,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// At the origin, unrotated.
    pub const IDENTITY: Pose = Pose {
        position: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
    };

    /// A pose at `position` with `orientation`.
    pub fn new(position: DVec3, orientation: DQuat) -> Self {
        Self {
            position,
            orientation,
        }
    }

    /// True when every component is finite and the quaternion has a usable
    /// length (it is normalized by [`Pose::sanitized`]).
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.orientation.length_squared() > 1e-12
    }

    /// The pose with its quaternion normalized, or `None` if it is not
    /// finite.
    pub fn sanitized(&self) -> Option<Pose> {
        self.is_finite().then(|| Pose {
            position: self.position,
            orientation: self.orientation.normalize(),
        })
    }

    /// The pose's forward direction, OpenXR's -Z.
    pub fn forward(&self) -> DVec3 {
        self.orientation * DVec3::NEG_Z
    }

    /// Maps a point from this pose's local frame to the parent frame.
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        self.position + self.orientation * p
    }

    /// `self` after `inner`: the pose of `inner` given in this pose's frame.
    pub fn compose(&self, inner: &Pose) -> Pose {
        Pose {
            position: self.transform_point(inner.position),
            orientation: (self.orientation * inner.orientation).normalize(),
        }
    }

    /// The inverse pose.
    pub fn inverse(&self) -> Pose {
        let q = self.orientation.inverse();
        Pose {
            position: q * -self.position,
            orientation: q,
        }
    }
}

/// Number of hand joints in the XR_EXT_hand_tracking layout.
pub const JOINT_COUNT: usize = 26;

/// The 26 joints of XR_EXT_hand_tracking (`XrHandJointEXT`), in its order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum Joint {
    Palm = 0,
    Wrist = 1,
    ThumbMetacarpal = 2,
    ThumbProximal = 3,
    ThumbDistal = 4,
    ThumbTip = 5,
    IndexMetacarpal = 6,
    IndexProximal = 7,
    IndexIntermediate = 8,
    IndexDistal = 9,
    IndexTip = 10,
    MiddleMetacarpal = 11,
    MiddleProximal = 12,
    MiddleIntermediate = 13,
    MiddleDistal = 14,
    MiddleTip = 15,
    RingMetacarpal = 16,
    RingProximal = 17,
    RingIntermediate = 18,
    RingDistal = 19,
    RingTip = 20,
    LittleMetacarpal = 21,
    LittleProximal = 22,
    LittleIntermediate = 23,
    LittleDistal = 24,
    LittleTip = 25,
}

impl Joint {
    /// The joint's index in the 26-joint array.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The five joints (metacarpal to tip) of each finger, index to little.
    pub const FINGERS: [[Joint; 5]; 4] = [
        [
            Joint::IndexMetacarpal,
            Joint::IndexProximal,
            Joint::IndexIntermediate,
            Joint::IndexDistal,
            Joint::IndexTip,
        ],
        [
            Joint::MiddleMetacarpal,
            Joint::MiddleProximal,
            Joint::MiddleIntermediate,
            Joint::MiddleDistal,
            Joint::MiddleTip,
        ],
        [
            Joint::RingMetacarpal,
            Joint::RingProximal,
            Joint::RingIntermediate,
            Joint::RingDistal,
            Joint::RingTip,
        ],
        [
            Joint::LittleMetacarpal,
            Joint::LittleProximal,
            Joint::LittleIntermediate,
            Joint::LittleDistal,
            Joint::LittleTip,
        ],
    ];

    /// The thumb's joints, metacarpal to tip.
    pub const THUMB: [Joint; 4] = [
        Joint::ThumbMetacarpal,
        Joint::ThumbProximal,
        Joint::ThumbDistal,
        Joint::ThumbTip,
    ];
}

/// One raw joint sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSample {
    /// The joint's pose.
    pub pose: Pose,
    /// The joint's radius (metres).
    pub radius: f64,
    /// Position and orientation valid (both OpenXR validity bits set).
    pub valid: bool,
}

impl Default for JointSample {
    fn default() -> Self {
        Self {
            pose: Pose::IDENTITY,
            radius: 0.01,
            valid: false,
        }
    }
}

/// One raw hand sample: the 26 joints and whether the hand is tracked.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandSample {
    /// `XrHandJointLocationsEXT::isActive`.
    pub active: bool,
    /// The joints, indexed by [`Joint`].
    pub joints: [JointSample; JOINT_COUNT],
}

/// Raw controller buttons and axes, named by the actions of
/// [`super::bindings`] (hosts fill them through the binding map).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ControllerButtons {
    /// `select` (trigger) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero")]
    pub select: f64,
    /// `grab` (squeeze/grip) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero")]
    pub grab: f64,
    /// `primary` button (A / X) pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub primary: bool,
    /// `secondary` button (B / Y) pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub secondary: bool,
    /// `menu` button pressed.
    #[serde(skip_serializing_if = "is_false")]
    pub menu: bool,
    /// `stick` (thumbstick or trackpad) `[x, y]`, each in `[-1, 1]`.
    #[serde(skip_serializing_if = "is_zero2")]
    pub stick: [f64; 2],
}

// Exact comparisons: a default value is left out of traces, anything else
// (including -0.0 and NaN) is written.
fn is_zero(x: &f64) -> bool {
    x.to_bits() == 0
}

fn is_zero2(x: &[f64; 2]) -> bool {
    is_zero(&x[0]) && is_zero(&x[1])
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// One raw controller sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ControllerSample {
    /// The grip pose.
    pub grip: Pose,
    /// Grip pose valid.
    pub grip_valid: bool,
    /// The aim pose (the ray origin and direction, -Z).
    pub aim: Pose,
    /// Aim pose valid.
    pub aim_valid: bool,
    /// Buttons and axes.
    pub buttons: ControllerButtons,
    /// Buttons and axes valid (the controller is connected and the action
    /// set is active).
    pub buttons_valid: bool,
}

/// Everything a host reads in one frame. Any part may be missing or
/// invalid; the [`Sanitizer`] decides what is usable.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InputFrame {
    /// Predicted display time in seconds; must increase from frame to frame.
    pub time: f64,
    /// The head (view) pose, if located.
    pub head: Option<Pose>,
    /// Hand joints, left and right, if the runtime reports them.
    pub hands: [Option<HandSample>; 2],
    /// Controllers, left and right, if present.
    pub controllers: [Option<ControllerSample>; 2],
}

/// A sanitized hand: joint positions of the tracked joints. A joint that
/// was invalid or non-finite is `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct HandJoints {
    /// Joint poses, indexed by [`Joint`].
    pub joints: [Option<Pose>; JOINT_COUNT],
}

impl HandJoints {
    /// The position of `j`, if tracked.
    pub fn pos(&self, j: Joint) -> Option<DVec3> {
        self.joints[j.index()].map(|p| p.position)
    }

    /// The pose of `j`, if tracked.
    pub fn pose(&self, j: Joint) -> Option<Pose> {
        self.joints[j.index()]
    }
}

/// A sanitized controller. Poses are present only when valid and finite;
/// buttons only when valid, finite and (after clamping) in range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller {
    /// Grip pose.
    pub grip: Option<Pose>,
    /// Aim pose.
    pub aim: Option<Pose>,
    /// Buttons and axes.
    pub buttons: Option<ControllerButtons>,
    /// The grip moved faster than [`SanitizerSettings::max_speed`] since the
    /// last accepted sample: a locomotion teleport or a tracking glitch.
    /// Tools must not treat the jump as hand motion.
    pub teleported: bool,
}

/// A sanitized frame: only usable data, and the time step since the last
/// accepted frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Time in seconds.
    pub time: f64,
    /// Seconds since the previous accepted frame (0 for the first).
    pub dt: f64,
    /// Head pose.
    pub head: Option<Pose>,
    /// Hands, left and right.
    pub hands: [Option<HandJoints>; 2],
    /// Controllers, left and right.
    pub controllers: [Option<Controller>; 2],
}

impl Frame {
    /// The hand `h`.
    pub fn hand(&self, h: Hand) -> Option<&HandJoints> {
        self.hands[h.index()].as_ref()
    }

    /// The controller `h`.
    pub fn controller(&self, h: Hand) -> Option<&Controller> {
        self.controllers[h.index()].as_ref()
    }
}

/// Limits of the sanitizer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SanitizerSettings {
    /// Grip speeds above this (m/s) count as a teleport, not motion. Human
    /// hands peak around 5 m/s.
    pub max_speed: f64,
    /// Fewer valid joints than this and the hand is dropped.
    pub min_joints: usize,
}

impl Default for SanitizerSettings {
    fn default() -> Self {
        Self {
            max_speed: 12.0,
            min_joints: 20,
        }
    }
}

/// The sanitizing layer: raw frames in, [`Frame`]s out.
///
/// Dropped: a frame whose time is non-finite or not after the last accepted
/// one; a pose that is invalid or non-finite; a hand that is inactive, has
/// fewer than [`SanitizerSettings::min_joints`] valid finite joints or lacks
/// the wrist or a fingertip; buttons that are invalid or non-finite. The
/// sanitizer's own state (the last accepted time and grip positions)
/// changes only on accepted samples.
#[derive(Clone, Debug, Default)]
pub struct Sanitizer {
    settings: SanitizerSettings,
    last_time: Option<f64>,
    last_grip: [Option<(f64, DVec3)>; 2],
}

impl Sanitizer {
    /// A sanitizer with `settings`.
    pub fn new(settings: SanitizerSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Sanitizes `raw`, or returns `None` when the whole frame is unusable
    /// (bad time).
    pub fn accept(&mut self, raw: &InputFrame) -> Option<Frame> {
        if !raw.time.is_finite() {
            return None;
        }
        let dt = match self.last_time {
            Some(t) if raw.time <= t => return None,
            Some(t) => raw.time - t,
            None => 0.0,
        };
        self.last_time = Some(raw.time);
        let head = raw.head.as_ref().and_then(Pose::sanitized);
        let hands = [0, 1].map(|i| raw.hands[i].as_ref().and_then(|h| self.hand(h)));
        let controllers = [0, 1].map(|i| {
            raw.controllers[i]
                .as_ref()
                .map(|c| self.controller(i, raw.time, c))
        });
        Some(Frame {
            time: raw.time,
            dt,
            head,
            hands,
            controllers,
        })
    }

    fn hand(&self, h: &HandSample) -> Option<HandJoints> {
        if !h.active {
            return None;
        }
        let joints = h
            .joints
            .map(|j| if j.valid { j.pose.sanitized() } else { None });
        let count = joints.iter().filter(|j| j.is_some()).count();
        let needed = [
            Joint::Wrist,
            Joint::ThumbTip,
            Joint::IndexTip,
            Joint::MiddleProximal,
        ];
        if count < self.settings.min_joints || needed.iter().any(|j| joints[j.index()].is_none()) {
            return None;
        }
        Some(HandJoints { joints })
    }

    fn controller(&mut self, i: usize, time: f64, c: &ControllerSample) -> Controller {
        let grip = if c.grip_valid {
            c.grip.sanitized()
        } else {
            None
        };
        let aim = if c.aim_valid { c.aim.sanitized() } else { None };
        let b = &c.buttons;
        let buttons_ok = c.buttons_valid
            && b.select.is_finite()
            && b.grab.is_finite()
            && b.stick.iter().all(|x| x.is_finite());
        let buttons = buttons_ok.then(|| ControllerButtons {
            select: b.select.clamp(0.0, 1.0),
            grab: b.grab.clamp(0.0, 1.0),
            stick: b.stick.map(|x| x.clamp(-1.0, 1.0)),
            ..*b
        });
        let mut teleported = false;
        if let Some(g) = grip {
            if let Some((t0, p0)) = self.last_grip[i] {
                let dt = (time - t0).max(1e-6);
                teleported = (g.position - p0).length() / dt > self.settings.max_speed;
            }
            self.last_grip[i] = Some((time, g.position));
        }
        Controller {
            grip,
            aim,
            buttons,
            teleported,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        });
        assert!(s.accept(&f).unwrap().hands[0].is_none());
        joints[Joint::IndexTip.index()].pose.position.x = 0.0;
        f.hands[0] = Some(HandSample {
            active: true,
            joints,
        });
        f.time = 1.0;
        assert!(s.accept(&f).unwrap().hands[0].is_some());
    }
}
