//! The script a test hands the runtime (JSON, path in
//! `SHAPEWRIGHT_TESTRT_SCRIPT`): keyframed poses and buttons indexed by
//! the runtime's step counter (one step per xrSyncActions call, so a
//! script plays back the same whatever the wall clock does), plus
//! injected faults.

use serde::{Deserialize, Serialize};

/// A scripted pose.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScriptPose {
    /// Position (meters, STAGE space: the floor at y = 0). As on real
    /// runtimes, LOCAL's origin is the head's pose at the session's first
    /// locate (eye height), and LOCAL_FLOOR is LOCAL dropped to the floor.
    pub p: [f32; 3],
    /// Orientation `[x, y, z, w]`.
    #[serde(default = "identity")]
    pub q: [f32; 4],
    /// Whether the runtime reports the pose as tracked (VALID bits). If
    /// false the runtime writes the sentinel position [`SENTINEL`].
    #[serde(default = "yes")]
    pub valid: bool,
    /// Report NaN coordinates with VALID bits set (a faulty runtime).
    #[serde(default)]
    pub nan: bool,
}

/// The position written into untracked poses: a host that shows it has
/// read a pose whose VALID bits were unset.
pub const SENTINEL: f32 = 12345.0;

fn identity() -> [f32; 4] {
    [0.0, 0.0, 0.0, 1.0]
}
fn yes() -> bool {
    true
}

/// One hand's scripted controller and joints.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScriptHand {
    /// Grip pose (None: the action is inactive).
    pub grip: Option<ScriptPose>,
    /// Aim pose.
    pub aim: Option<ScriptPose>,
    /// Trigger / select value.
    #[serde(default)]
    pub select: f32,
    /// Squeeze value.
    #[serde(default)]
    pub squeeze: f32,
    /// Menu button.
    #[serde(default)]
    pub menu: bool,
    /// Primary button (A / X, trackpad click).
    #[serde(default)]
    pub primary: bool,
    /// Secondary button (B / Y).
    #[serde(default)]
    pub secondary: bool,
    /// Thumbstick / trackpad `[x, y]`.
    #[serde(default)]
    pub stick: [f32; 2],
    /// Wrist pose from which the 26 joints are laid out 1 cm apart along
    /// +X (None: the hand tracker is inactive).
    pub joints: Option<ScriptPose>,
    /// Joint indices reported untracked.
    #[serde(default)]
    pub invalid_joints: Vec<usize>,
}

/// A keyframe: from step `at` on, these values hold (until the next keyframe).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Keyframe {
    /// First step this keyframe applies to.
    pub at: u64,
    /// Head pose.
    pub head: Option<ScriptPose>,
    /// Left hand.
    #[serde(default)]
    pub left: ScriptHand,
    /// Right hand.
    #[serde(default)]
    pub right: ScriptHand,
}

/// A fault to inject.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Fault {
    /// Queue LOSS_PENDING for the session; it then answers ERROR_SESSION_LOST.
    LossPending,
    /// Queue XrEventDataInstanceLossPending; the instance then answers
    /// ERROR_INSTANCE_LOST, and the next `refuse_creates` xrCreateInstance
    /// calls fail with ERROR_RUNTIME_FAILURE.
    InstanceLoss,
    /// The runtime stops the session itself (STOPPING, then EXITING after
    /// xrEndSession).
    RuntimeExit,
}

/// A fault at a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FaultAt {
    /// The step (sync count) at which it fires, once per process.
    pub at: u64,
    /// What happens.
    pub fault: Fault,
}

/// The whole script.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Script {
    /// Offer XR_EXT_hand_tracking.
    #[serde(default = "yes")]
    pub hand_tracking: bool,
    /// Offer XR_KHR_vulkan_enable2 (graphics sessions on the app's
    /// Vulkan device: swapchains, frames, views).
    #[serde(default)]
    pub vulkan: bool,
    /// Write the first submitted projection layer's left-eye pixels here
    /// (u32 width, u32 height, little-endian, then RGBA8 rows).
    #[serde(default)]
    pub capture_path: Option<String>,
    /// Write frame statistics (JSON) here when a session is destroyed.
    #[serde(default)]
    pub stats_path: Option<String>,
    /// The interaction profile the "connected" controllers have.
    #[serde(default = "touch")]
    pub profile: String,
    /// Keyframes, sorted by `at`.
    #[serde(default)]
    pub keyframes: Vec<Keyframe>,
    /// Faults.
    #[serde(default)]
    pub faults: Vec<FaultAt>,
    /// xrCreateInstance calls refused after an instance loss.
    #[serde(default)]
    pub refuse_creates: u32,
    /// A stepped clock: xrConvertTimespecTimeToTimeKHR answers
    /// `step * step_ns` (plus one second) instead of the wall clock, so the
    /// time the host sees advances exactly one step per synced frame.
    #[serde(default)]
    pub step_ns: Option<i64>,
    /// Offer XR_EXT_local_floor (and the LOCAL_FLOOR space).
    #[serde(default = "yes")]
    pub local_floor: bool,
    /// Offer the STAGE space.
    #[serde(default = "yes")]
    pub stage: bool,
    /// Whether the system can track hands. False: XR_EXT_hand_tracking is
    /// still offered (if `hand_tracking`), `supportsHandTracking` is false
    /// and xrCreateHandTrackerEXT fails with FEATURE_UNSUPPORTED, as on
    /// Monado's `simulated` system and most PC headsets.
    #[serde(default = "yes")]
    pub hands_supported: bool,
    /// Offer XR_EXT_hand_tracking_data_source and report this source for
    /// active hands: `"unobstructed"` or `"controller"`.
    #[serde(default)]
    pub hand_source: Option<String>,
    /// What the runtime offers but then refuses (as validation layers and
    /// real runtimes do): the host must fall back, not end the session.
    #[serde(default)]
    pub refuse: Refusals,
}

/// Creations the runtime refuses although it offers them.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Refusals {
    /// xrCreateReferenceSpace(LOCAL_FLOOR) fails with
    /// XR_ERROR_VALIDATION_FAILURE (Debian's OpenXR 1.0.20 core validation
    /// layer, which predates LOCAL_FLOOR, answers so).
    pub local_floor: bool,
    /// xrCreateReferenceSpace(STAGE) fails with XR_ERROR_RUNTIME_FAILURE
    /// (a runtime whose play area is not set up).
    pub stage: bool,
    /// xrLocateSpace between LOCAL and STAGE fails with
    /// XR_ERROR_RUNTIME_FAILURE.
    pub locate_stage: bool,
    /// xrCreateHandTrackerEXT with XrHandTrackingDataSourceInfoEXT chained
    /// fails with XR_ERROR_VALIDATION_FAILURE (a layer that does not know
    /// the struct); plain creation works.
    pub hand_data_source: bool,
    /// xrCreateHandTrackerEXT fails with XR_ERROR_RUNTIME_FAILURE although
    /// the system says it can track hands.
    pub hand_trackers: bool,
    /// xrSuggestInteractionProfileBindings fails with
    /// XR_ERROR_VALIDATION_FAILURE for these profiles.
    pub profiles: Vec<String>,
}

impl Refusals {
    /// Nothing refused (`const` for the runtime's static state).
    pub const NONE: Refusals = Refusals {
        local_floor: false,
        stage: false,
        locate_stage: false,
        hand_data_source: false,
        hand_trackers: false,
        profiles: Vec::new(),
    };
}

fn touch() -> String {
    "/interaction_profiles/oculus/touch_controller".into()
}

impl Default for Script {
    fn default() -> Self {
        Self {
            profile: touch(),
            ..Self::base()
        }
    }
}

impl Script {
    /// The defaults with no interaction profile (a `const` the runtime's
    /// static state starts from; [`Default`] adds the Touch profile).
    pub const fn base() -> Self {
        Self {
            hand_tracking: true,
            vulkan: false,
            stats_path: None,
            capture_path: None,
            profile: String::new(),
            keyframes: Vec::new(),
            faults: Vec::new(),
            refuse_creates: 0,
            step_ns: None,
            local_floor: true,
            stage: true,
            hands_supported: true,
            hand_source: None,
            refuse: Refusals::NONE,
        }
    }

    /// The keyframe in force at `step` (the last with `at <= step`).
    pub fn at(&self, step: u64) -> Keyframe {
        self.keyframes
            .iter()
            .filter(|k| k.at <= step)
            .max_by_key(|k| k.at)
            .cloned()
            .unwrap_or_default()
    }

    /// What the devices track at `step` for reference spaces and views,
    /// which a real runtime tracks whether or not the app has synced: the
    /// keyframe in force, or the first keyframe before it starts (the
    /// headset is somewhere before the first `xrSyncActions`).
    pub fn live(&self, step: u64) -> Keyframe {
        let first = self.keyframes.iter().map(|k| k.at).min().unwrap_or(0);
        self.at(step.max(first))
    }

    /// Reads the script named by `SHAPEWRIGHT_TESTRT_SCRIPT` (default script
    /// if unset or unreadable; a parse error is reported on stderr).
    pub fn from_env() -> Self {
        let Ok(path) = std::env::var("SHAPEWRIGHT_TESTRT_SCRIPT") else {
            return Self::default();
        };
        match std::fs::read_to_string(&path).map(|t| serde_json::from_str::<Script>(&t)) {
            Ok(Ok(s)) => s,
            Ok(Err(e)) => {
                eprintln!("shapewright-xr-testrt: bad script {path}: {e}");
                Self::default()
            }
            Err(e) => {
                eprintln!("shapewright-xr-testrt: cannot read {path}: {e}");
                Self::default()
            }
        }
    }
}

/// Rigid poses: (position, unit quaternion [x, y, z, w]).
pub mod pose {
    /// A rigid pose.
    pub type Pose = ([f32; 3], [f32; 4]);

    /// The identity pose.
    pub const IDENTITY: Pose = ([0.0; 3], [0.0, 0.0, 0.0, 1.0]);

    /// The yaw part of `q` (rotation about +Y), normalized.
    pub fn yaw(q: [f32; 4]) -> [f32; 4] {
        let (y, w) = (q[1], q[3]);
        let n = (y * y + w * w).sqrt();
        if n < 1e-6 {
            [0.0, 0.0, 0.0, 1.0]
        } else {
            [0.0, y / n, 0.0, w / n]
        }
    }

    /// Quaternion product a*b.
    pub fn qmul(a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
        let [ax, ay, az, aw] = a;
        let [bx, by, bz, bw] = b;
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    }
    /// Rotates v by q.
    pub fn rotate(q: [f32; 4], v: [f32; 3]) -> [f32; 3] {
        let r = qmul(
            qmul(q, [v[0], v[1], v[2], 0.0]),
            [-q[0], -q[1], -q[2], q[3]],
        );
        [r[0], r[1], r[2]]
    }
    /// a ∘ b (b expressed in a's frame).
    pub fn compose(a: ([f32; 3], [f32; 4]), b: ([f32; 3], [f32; 4])) -> ([f32; 3], [f32; 4]) {
        let t = rotate(a.1, b.0);
        (
            [a.0[0] + t[0], a.0[1] + t[1], a.0[2] + t[2]],
            qmul(a.1, b.1),
        )
    }
    /// Inverse pose.
    pub fn inverse(a: ([f32; 3], [f32; 4])) -> ([f32; 3], [f32; 4]) {
        let qi = [-a.1[0], -a.1[1], -a.1[2], a.1[3]];
        let t = rotate(qi, a.0);
        ([-t[0], -t[1], -t[2]], qi)
    }
}

/// What the runtime writes to `stats_path` when a session is destroyed.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameStats {
    /// xrEndFrame calls that succeeded.
    pub frames_ended: u64,
    /// Valid projection layers submitted.
    pub projection_layers: u64,
    /// Whether the session was a Vulkan one.
    pub graphics: bool,
    /// xrApplyHapticFeedback calls, per hand (left, right).
    #[serde(default)]
    pub haptics: [u64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyframes_hold_until_the_next_one() {
        let s = Script {
            keyframes: vec![
                Keyframe {
                    at: 0,
                    head: Some(ScriptPose {
                        p: [0.0; 3],
                        q: identity(),
                        valid: true,
                        nan: false,
                    }),
                    ..Default::default()
                },
                Keyframe {
                    at: 5,
                    ..Default::default()
                },
            ],
            ..Default::default()
        };
        assert!(s.at(0).head.is_some() && s.at(4).head.is_some());
        assert!(s.at(5).head.is_none() && s.at(99).head.is_none());
        let late = Script {
            keyframes: s
                .keyframes
                .iter()
                .map(|k| Keyframe {
                    at: k.at + 3,
                    ..k.clone()
                })
                .collect(),
            ..Default::default()
        };
        assert!(late.at(0).head.is_none() && late.live(0).head.is_some());
        let parsed: Script =
            serde_json::from_str(r#"{"keyframes":[{"at":1,"right":{"grip":{"p":[1,2,3]}}}]}"#)
                .unwrap();
        let g = parsed.keyframes[0].right.grip.unwrap();
        assert!(g.valid && !g.nan && g.q == identity() && parsed.hand_tracking && !parsed.vulkan);
    }

    #[test]
    fn pose_compose_and_inverse_round_trip() {
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let a = ([1.0, 2.0, 3.0], [0.0, h, 0.0, h]); // 90° about Y
        let b = ([0.5, 0.0, -1.0], [h, 0.0, 0.0, h]);
        let (p, q) = pose::compose(pose::inverse(a), pose::compose(a, b));
        assert!(p.iter().zip(b.0).all(|(x, y)| (x - y).abs() < 1e-5));
        assert!(q.iter().zip(b.1).all(|(x, y)| (x - y).abs() < 1e-5));
        // 90° about Y takes +X to -Z.
        let r = pose::rotate(a.1, [1.0, 0.0, 0.0]);
        assert!((r[2] + 1.0).abs() < 1e-6 && r[0].abs() < 1e-6);
    }
}
