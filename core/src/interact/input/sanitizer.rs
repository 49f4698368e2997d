//! [`Sanitizer`]: raw frames in, [`Frame`]s out, with its limits
//! ([`SanitizerSettings`]) and what it dropped ([`SanitizerStats`]).

use serde::{Deserialize, Serialize};

use super::frame::{Controller, Frame, HandJoints};
use super::joints::{HandSample, HandSource, Joint};
use super::pose::Pose;
use super::raw::{ControllerButtons, ControllerSample, InputFrame};
use crate::math::DVec3;

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
    pub(super) settings: SanitizerSettings,
    pub(super) last_time: Option<f64>,
    pub(super) last_grip: [Option<(f64, DVec3)>; 2],
    pub(super) stats: SanitizerStats,
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
    pub(super) fn checked(&mut self, p: &Pose, valid: bool) -> Option<Pose> {
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

    pub(super) fn usable(&self, p: &Pose) -> Option<Pose> {
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

    pub(super) fn hand(&mut self, h: &HandSample) -> Option<HandJoints> {
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

    pub(super) fn controller(&mut self, i: usize, time: f64, c: &ControllerSample) -> Controller {
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
