//! Sanitized input frames and the [`FrameSink`] that receives them.
//!
//! A pose reaches the sink only if the runtime set both its position and
//! orientation VALID bits, every component is finite and the quaternion is
//! close to unit length; anything else is counted and dropped (the
//! contents of a pose without VALID bits are undefined by the spec).

use serde::{Deserialize, Serialize};
use shapewright::interact;
use shapewright::math::{DQuat, DVec3};

/// A rigid pose in the session's base (LOCAL) space, meters, OpenXR axes
/// (Y up).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position.
    pub position: [f32; 3],
    /// Unit quaternion `[x, y, z, w]`.
    pub orientation: [f32; 4],
}

/// One hand's input this frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HandInput {
    /// Grip pose, if tracked.
    pub grip: Option<Pose>,
    /// Aim pose, if tracked.
    pub aim: Option<Pose>,
    /// Whether any of the hand's button actions is active (a controller,
    /// or a tracked hand under the hand-interaction profile, is bound).
    #[serde(default)]
    pub active: bool,
    /// Select / trigger / pinch, 0..1 (the `select` action).
    pub select: f32,
    /// Squeeze / grasp, 0..1 (the `grab` action).
    pub squeeze: f32,
    /// Menu button.
    pub menu: bool,
    /// Primary face button (A / X).
    pub primary: bool,
    /// Secondary face button (B / Y).
    #[serde(default)]
    pub secondary: bool,
    /// Thumbstick or trackpad `[x, y]`, each -1..1.
    #[serde(default)]
    pub stick: [f32; 2],
    /// The 26 `XR_EXT_hand_tracking` joints (palm, wrist, thumb..little),
    /// each None if its pose was not valid; empty when no hand tracking.
    pub joints: Vec<Option<Pose>>,
}

/// Everything the interaction core needs from one frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InputFrame {
    /// Frame counter since the host started (across session recreation).
    pub index: u64,
    /// The runtime's time for this frame (XrTime, nanoseconds).
    pub time_ns: i64,
    /// Head (VIEW space) pose, if tracked.
    pub head: Option<Pose>,
    /// Left (0) and right (1) hands.
    pub hands: [HandInput; 2],
}

/// Lifecycle notifications (for autosave on session loss and the like).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LifecycleEvent {
    /// The session changed state (the OpenXR state name).
    State(String),
    /// The session was lost (LOSS_PENDING or ERROR_SESSION_LOST).
    SessionLost,
    /// The instance was lost; the host will retry.
    InstanceLost,
    /// A new session was created (after start or recreation).
    SessionCreated,
}

/// Receives sanitized input each frame. `core::interact` plugs in here.
pub trait FrameSink {
    /// Called once per frame while the session is running.
    fn frame(&mut self, frame: &InputFrame);
    /// Called on lifecycle changes (default: ignored).
    fn lifecycle(&mut self, _event: &LifecycleEvent) {}
    /// What to draw for the document and the tool (default: nothing; the
    /// headset then draws only `--model` and the aim rays).
    fn scene(&self) -> Option<&crate::interaction::Scene> {
        None
    }
}

/// A sink that keeps every frame (tests, recording).
#[derive(Debug, Default)]
pub struct CollectSink {
    /// Frames received.
    pub frames: Vec<InputFrame>,
    /// Lifecycle events received.
    pub events: Vec<LifecycleEvent>,
}

impl FrameSink for CollectSink {
    fn frame(&mut self, frame: &InputFrame) {
        self.frames.push(frame.clone());
    }
    fn lifecycle(&mut self, event: &LifecycleEvent) {
        self.events.push(event.clone());
    }
}

/// The pose if the runtime marked it valid and it is numerically sane.
pub fn sanitize_pose(
    position_valid: bool,
    orientation_valid: bool,
    position: [f32; 3],
    orientation: [f32; 4],
) -> Option<Pose> {
    if !(position_valid && orientation_valid) {
        return None;
    }
    if !position.iter().chain(&orientation).all(|c| c.is_finite()) {
        return None;
    }
    if position.iter().any(|c| c.abs() > 1.0e4) {
        return None;
    }
    let n = orientation.iter().map(|c| c * c).sum::<f32>().sqrt();
    if !(0.9..=1.1).contains(&n) {
        return None;
    }
    Some(Pose {
        position,
        orientation: orientation.map(|c| c / n),
    })
}

/// A 0..1 analog value, NaN mapped to 0.
pub fn sanitize_value(v: f32) -> f32 {
    sanitize_axis(v).max(0.0)
}

/// A -1..1 axis value, NaN mapped to 0.
pub fn sanitize_axis(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

impl Pose {
    /// The pose in the interaction core's f64 types.
    pub fn to_interact(&self) -> interact::Pose {
        let [x, y, z] = self.position.map(f64::from);
        let [qx, qy, qz, qw] = self.orientation.map(f64::from);
        interact::Pose::new(DVec3::new(x, y, z), DQuat::from_xyzw(qx, qy, qz, qw))
    }
}

/// A sample the runtime did not mark valid: the identity pose with the
/// valid flag unset, so the core never sees the runtime's undefined values.
fn raw_pose(p: Option<Pose>) -> (interact::Pose, bool) {
    p.map_or((interact::Pose::IDENTITY, false), |p| {
        (p.to_interact(), true)
    })
}

impl HandInput {
    /// The controller sample the core reads (None: no controller bound).
    fn controller(&self) -> Option<interact::ControllerSample> {
        if !self.active && self.grip.is_none() && self.aim.is_none() {
            return None;
        }
        let (grip, grip_valid) = raw_pose(self.grip);
        let (aim, aim_valid) = raw_pose(self.aim);
        Some(interact::ControllerSample {
            grip,
            grip_valid,
            aim,
            aim_valid,
            buttons: interact::ControllerButtons {
                select: f64::from(self.select),
                grab: f64::from(self.squeeze),
                primary: self.primary,
                secondary: self.secondary,
                menu: self.menu,
                stick: self.stick.map(f64::from),
            },
            buttons_valid: self.active,
        })
    }

    /// The tracked hand the core reads (None: no joints this frame).
    fn hand(&self) -> Option<interact::HandSample> {
        if self.joints.len() != interact::JOINT_COUNT {
            return None;
        }
        let mut joints = [interact::JointSample::default(); interact::JOINT_COUNT];
        for (j, p) in joints.iter_mut().zip(&self.joints) {
            if let Some(p) = p {
                j.pose = p.to_interact();
                j.valid = true;
            }
        }
        Some(interact::HandSample {
            active: true,
            joints,
        })
    }
}

impl InputFrame {
    /// The frame as `core::interact` takes it: time in seconds, poses in
    /// f64, every pose that was dropped here marked invalid (identity
    /// contents), controllers and hands present as the runtime reported.
    /// This is the one conversion the headless and headset loops share.
    pub fn to_interact(&self) -> interact::InputFrame {
        interact::InputFrame {
            time: self.time_ns as f64 * 1e-9,
            head: self.head.map(|p| p.to_interact()),
            hands: [self.hands[0].hand(), self.hands[1].hand()],
            controllers: [self.hands[0].controller(), self.hands[1].controller()],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_bits_nan_and_bad_quaternions_are_dropped() {
        let p = [0.1, 1.5, -0.3];
        let q = [0.0, 0.0, 0.0, 1.0];
        assert!(sanitize_pose(true, true, p, q).is_some());
        assert!(sanitize_pose(false, true, p, q).is_none());
        assert!(sanitize_pose(true, false, p, q).is_none());
        assert!(sanitize_pose(true, true, [f32::NAN, 0.0, 0.0], q).is_none());
        assert!(sanitize_pose(true, true, p, [0.0, f32::INFINITY, 0.0, 1.0]).is_none());
        assert!(sanitize_pose(true, true, p, [0.0, 0.0, 0.0, 0.0]).is_none());
        assert!(sanitize_pose(true, true, [1e9, 0.0, 0.0], q).is_none());
        let r = sanitize_pose(true, true, p, [0.0, 0.0, 0.0, 1.05]).unwrap();
        assert!((r.orientation[3] - 1.0).abs() < 1e-6);
        assert_eq!(sanitize_value(f32::NAN), 0.0);
        assert_eq!(sanitize_value(2.0), 1.0);
    }
}
