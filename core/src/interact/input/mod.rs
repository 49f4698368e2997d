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
//!
//! This is the one sanitizer both hosts use: the OpenXR host copies what
//! the runtime reported (poses with their VALID bits, action values,
//! joints) into an [`InputFrame`] without judging it, and the Blender
//! add-on does the same with Blender's XR events. The checks and the
//! counts of what was dropped ([`SanitizerStats`]) live here only.
//!
//! **Hands versus controllers** (issue 16): runtimes such as Monado and
//! SteamVR with Index controllers report hand joints *derived from the
//! controller* (finger curls from the grip sensors) through
//! `XR_EXT_hand_tracking`. When a hand sample and valid controller buttons
//! arrive together, the buttons are the user's intent, so the sanitizer
//! drops the hand and tools that read hands make one from the buttons
//! ([`crate::interact::gesture::controller_hand`]), unless the runtime said the joints come
//! from optical tracking ([`HandSource::Optical`], from
//! `XR_EXT_hand_tracking_data_source`).
//!
//! Traces store non-finite numbers (a faulty runtime's NaN) as the strings
//! `"NaN"`, `"inf"` and `"-inf"`, since JSON has no such numbers; finite
//! numbers are written exactly as before (shortest round-trip form).

pub(crate) mod bindings;
pub(crate) mod ctl_input;

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
    #[serde(rename = "p", with = "num::vec3")]
    pub position: DVec3,
    /// Orientation `[x, y, z, w]` (`"q"` in traces).
    #[serde(rename = "q", with = "num::quat")]
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

/// Where a hand's joints come from (`XrHandTrackingDataSourceEXT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HandSource {
    /// The runtime did not say (no `XR_EXT_hand_tracking_data_source`).
    #[default]
    Unknown,
    /// Optical hand tracking (`XR_HAND_TRACKING_DATA_SOURCE_UNOBSTRUCTED_EXT`):
    /// the fingers are the user's.
    Optical,
    /// Derived from a held controller (`XR_HAND_TRACKING_DATA_SOURCE_CONTROLLER_EXT`):
    /// the fingers follow the controller's sensors, the buttons carry intent.
    Controller,
}

impl HandSource {
    fn is_unknown(&self) -> bool {
        *self == HandSource::Unknown
    }
}

/// One raw hand sample: the 26 joints and whether the hand is tracked.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandSample {
    /// `XrHandJointLocationsEXT::isActive`.
    pub active: bool,
    /// The joints, indexed by [`Joint`].
    pub joints: [JointSample; JOINT_COUNT],
    /// Where the joints come from (left out of traces when unknown).
    #[serde(default, skip_serializing_if = "HandSource::is_unknown")]
    pub source: HandSource,
}

/// Raw controller buttons and axes, named by the actions of
/// [`crate::interact::input::bindings`] (hosts fill them through the binding map).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ControllerButtons {
    /// `select` (trigger) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero", with = "num::f64")]
    pub select: f64,
    /// `grab` (squeeze/grip) value in `[0, 1]`.
    #[serde(skip_serializing_if = "is_zero", with = "num::f64")]
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
    #[serde(skip_serializing_if = "is_zero2", with = "num::arr2")]
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
    #[serde(with = "num::f64")]
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
#[serde(default)]
pub struct SanitizerSettings {
    /// Grip speeds above this (m/s) count as a teleport, not motion. Human
    /// hands peak around 5 m/s.
    pub max_speed: f64,
    /// Fewer valid joints than this and the hand is dropped.
    pub min_joints: usize,
    /// Positions farther than this from the origin (metres) are dropped: no
    /// room is 10 km wide, and runtimes write such values into untracked
    /// poses.
    pub max_coordinate: f64,
    /// Quaternions whose length is off 1 by more than this are dropped
    /// (a runtime's quaternions are unit up to rounding; anything else is
    /// garbage, not a rotation to be normalized).
    pub unit_tolerance: f64,
    /// Drop a hand whose joints are not from optical tracking when the
    /// same hand's controller buttons are valid: the buttons carry the
    /// user's intent (see the module doc).
    pub buttons_over_hands: bool,
}

impl Default for SanitizerSettings {
    fn default() -> Self {
        Self {
            max_speed: 12.0,
            min_joints: 20,
            max_coordinate: 1.0e4,
            unit_tolerance: 0.1,
            buttons_over_hands: true,
        }
    }
}

/// What the sanitizer dropped so far (the host reports these).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SanitizerStats {
    /// Frames accepted.
    pub frames: u64,
    /// Whole frames dropped (non-finite time, or not after the last one).
    pub frames_dropped: u64,
    /// Poses (head, grip, aim) that were absent or marked invalid.
    pub poses_untracked: u64,
    /// Poses marked valid but unusable (non-finite, out of range, not a
    /// unit quaternion).
    pub poses_rejected: u64,
    /// Joints marked valid but unusable.
    pub joints_rejected: u64,
    /// Hands dropped (inactive, too few joints, a key joint missing).
    pub hands_dropped: u64,
    /// Hands set aside because the controller's buttons were valid and
    /// the joints were not optical.
    pub hands_overridden: u64,
    /// Button sets marked valid but holding non-finite values.
    pub buttons_rejected: u64,
}

/// The sanitizing layer: raw frames in, [`Frame`]s out.
///
/// Dropped: a frame whose time is non-finite or not after the last accepted
/// one; a pose that is invalid, non-finite, farther than
/// [`SanitizerSettings::max_coordinate`] or whose quaternion is not unit
/// within [`SanitizerSettings::unit_tolerance`]; a hand that is inactive,
/// has fewer than [`SanitizerSettings::min_joints`] usable joints, lacks
/// the wrist or a fingertip, or is controller-derived while its
/// controller's buttons are valid; buttons that are invalid or
/// non-finite. The sanitizer's own state (the last accepted time and grip
/// positions) changes only on accepted samples.
#[derive(Clone, Debug, Default)]
pub struct Sanitizer {
    settings: SanitizerSettings,
    last_time: Option<f64>,
    last_grip: [Option<(f64, DVec3)>; 2],
    stats: SanitizerStats,
}

impl Sanitizer {
    /// A sanitizer with `settings`.
    pub fn new(settings: SanitizerSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// What was accepted and dropped so far.
    pub fn stats(&self) -> SanitizerStats {
        self.stats
    }

    /// Sanitizes `raw`, or returns `None` when the whole frame is unusable
    /// (bad time).
    pub fn accept(&mut self, raw: &InputFrame) -> Option<Frame> {
        if !raw.time.is_finite() {
            self.stats.frames_dropped += 1;
            return None;
        }
        let dt = match self.last_time {
            Some(t) if raw.time <= t => {
                self.stats.frames_dropped += 1;
                return None;
            }
            Some(t) => raw.time - t,
            None => 0.0,
        };
        self.last_time = Some(raw.time);
        self.stats.frames += 1;
        let head = match &raw.head {
            Some(p) => self.checked(p, true),
            None => {
                self.stats.poses_untracked += 1;
                None
            }
        };
        let controllers = [0, 1].map(|i| {
            raw.controllers[i]
                .as_ref()
                .map(|c| self.controller(i, raw.time, c))
        });
        let hands = [0, 1].map(|i| {
            let h = raw.hands[i].as_ref()?;
            let buttons = controllers[i].as_ref().is_some_and(|c| c.buttons.is_some());
            if self.settings.buttons_over_hands && buttons && h.source != HandSource::Optical {
                self.stats.hands_overridden += 1;
                return None;
            }
            self.hand(h)
        });
        Some(Frame {
            time: raw.time,
            dt,
            head,
            hands,
            controllers,
        })
    }

    /// A pose the runtime marked `valid`, if it is usable (normalized).
    fn checked(&mut self, p: &Pose, valid: bool) -> Option<Pose> {
        if !valid {
            self.stats.poses_untracked += 1;
            return None;
        }
        let r = self.usable(p);
        if r.is_none() {
            self.stats.poses_rejected += 1;
        }
        r
    }

    fn usable(&self, p: &Pose) -> Option<Pose> {
        let s = &self.settings;
        let ok = p.is_finite()
            && p.position.abs().max_element() <= s.max_coordinate
            && (p.orientation.length() - 1.0).abs() <= s.unit_tolerance;
        if ok {
            p.sanitized()
        } else {
            None
        }
    }

    fn hand(&mut self, h: &HandSample) -> Option<HandJoints> {
        if !h.active {
            self.stats.hands_dropped += 1;
            return None;
        }
        let mut rejected = 0;
        let joints = h.joints.map(|j| {
            if !j.valid {
                return None;
            }
            let p = self.usable(&j.pose);
            rejected += u64::from(p.is_none());
            p
        });
        self.stats.joints_rejected += rejected;
        let count = joints.iter().filter(|j| j.is_some()).count();
        let needed = [
            Joint::Wrist,
            Joint::ThumbTip,
            Joint::IndexTip,
            Joint::MiddleProximal,
        ];
        if count < self.settings.min_joints || needed.iter().any(|j| joints[j.index()].is_none()) {
            self.stats.hands_dropped += 1;
            return None;
        }
        Some(HandJoints { joints })
    }

    fn controller(&mut self, i: usize, time: f64, c: &ControllerSample) -> Controller {
        let grip = self.checked(&c.grip, c.grip_valid);
        let aim = self.checked(&c.aim, c.aim_valid);
        let b = &c.buttons;
        let finite =
            b.select.is_finite() && b.grab.is_finite() && b.stick.iter().all(|x| x.is_finite());
        if c.buttons_valid && !finite {
            self.stats.buttons_rejected += 1;
        }
        let buttons = (c.buttons_valid && finite).then(|| ControllerButtons {
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

/// Serde for numbers that may be non-finite: finite values as JSON
/// numbers (unchanged), NaN and infinities as the strings `"NaN"`, `"inf"`,
/// `"-inf"`.
mod num {
    use serde::de::{self, Deserializer, SeqAccess, Visitor};
    use serde::ser::{SerializeTuple, Serializer};
    use serde::{Deserialize, Serialize};

    /// One number, finite or not.
    #[derive(Clone, Copy)]
    struct Lenient(f64);

    impl Serialize for Lenient {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let x = self.0;
            if x.is_finite() {
                s.serialize_f64(x)
            } else if x.is_nan() {
                s.serialize_str("NaN")
            } else if x > 0.0 {
                s.serialize_str("inf")
            } else {
                s.serialize_str("-inf")
            }
        }
    }

    struct LenientVisitor;

    impl Visitor<'_> for LenientVisitor {
        type Value = Lenient;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str(r#"a number, "NaN", "inf" or "-inf""#)
        }
        fn visit_f64<E>(self, v: f64) -> Result<Lenient, E> {
            Ok(Lenient(v))
        }
        fn visit_i64<E>(self, v: i64) -> Result<Lenient, E> {
            Ok(Lenient(v as f64))
        }
        fn visit_u64<E>(self, v: u64) -> Result<Lenient, E> {
            Ok(Lenient(v as f64))
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<Lenient, E> {
            match v {
                "NaN" | "nan" => Ok(Lenient(f64::NAN)),
                "inf" | "Infinity" => Ok(Lenient(f64::INFINITY)),
                "-inf" | "-Infinity" => Ok(Lenient(f64::NEG_INFINITY)),
                _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
            }
        }
    }

    impl<'de> Deserialize<'de> for Lenient {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Lenient, D::Error> {
            d.deserialize_any(LenientVisitor)
        }
    }

    fn ser_array<S: Serializer, const N: usize>(v: [f64; N], s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(N)?;
        for x in v {
            t.serialize_element(&Lenient(x))?;
        }
        t.end()
    }

    fn de_array<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<[f64; N], D::Error> {
        struct ArrayVisitor<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for ArrayVisitor<N> {
            type Value = [f64; N];
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of {N} numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; N], A::Error> {
                let mut out = [0.0; N];
                for (i, o) in out.iter_mut().enumerate() {
                    let Lenient(x) = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                    *o = x;
                }
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(N + 1, &self));
                }
                Ok(out)
            }
        }
        d.deserialize_tuple(N, ArrayVisitor::<N>)
    }

    /// A single `f64`.
    pub mod f64 {
        use super::*;
        /// Serializes.
        pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
            Lenient(*x).serialize(s)
        }
        /// Deserializes.
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
            Lenient::deserialize(d).map(|l| l.0)
        }
    }

    /// `[f64; 2]`.
    pub mod arr2 {
        use super::*;
        /// Serializes.
        pub fn serialize<S: Serializer>(x: &[f64; 2], s: S) -> Result<S::Ok, S::Error> {
            ser_array(*x, s)
        }
        /// Deserializes.
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
            de_array(d)
        }
    }

    /// `DVec3` as `[x, y, z]`.
    pub mod vec3 {
        use super::*;
        use crate::math::DVec3;
        /// Serializes.
        pub fn serialize<S: Serializer>(v: &DVec3, s: S) -> Result<S::Ok, S::Error> {
            ser_array(v.to_array(), s)
        }
        /// Deserializes.
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DVec3, D::Error> {
            de_array(d).map(DVec3::from_array)
        }
    }

    /// `DQuat` as `[x, y, z, w]`.
    pub mod quat {
        use super::*;
        use crate::math::DQuat;
        /// Serializes.
        pub fn serialize<S: Serializer>(q: &DQuat, s: S) -> Result<S::Ok, S::Error> {
            ser_array(q.to_array(), s)
        }
        /// Deserializes.
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DQuat, D::Error> {
            de_array(d).map(DQuat::from_array)
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
}
