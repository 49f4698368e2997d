//! Reading one tracked hand for the GC tool: its gesture, a filtered ray
//! (palm along the wrist-to-knuckles direction), the filtered palm (what a
//! FIST drags) and the filtered index tip (the pen of a POINT sketch), and
//! whether it teleported.
//!
//! Hand-tracking joints jitter by about a millimetre; a ray through two
//! joints 8 cm apart then swings by ~1°, which is centimetres at arm's
//! length. The ray direction uses the mean of the four knuckles and both
//! ray and points are low-pass filtered (exponential, time constants in
//! [`super::GcToolSettings`]); the filter restarts whenever the hand
//! reappears or teleports, so it never drags an old position along.

use crate::math::fm::DetMath as _;
use crate::math::DVec3;

use super::GcToolSettings;
use crate::interact::gesture::{Gesture, GestureState};
use crate::interact::input::{Hand, Joint};
use crate::interact::tools::pick::Ray;
use crate::interact::tools::ToolContext;

/// One hand this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HandIn {
    /// The debounced gesture (`None` without tracking).
    pub gesture: Gesture,
    /// The classifier's state.
    pub state: GestureState,
    /// Filtered ray (world).
    pub ray: Option<Ray>,
    /// Filtered palm centre (world).
    pub palm: Option<DVec3>,
    /// Filtered index tip (world).
    pub pen: Option<DVec3>,
    /// The hand moved faster than a hand can since the last frame.
    pub teleported: bool,
}

impl HandIn {
    /// Tracked with a recognized gesture and usable positions.
    pub fn tracked(&self) -> bool {
        self.gesture != Gesture::None && self.palm.is_some() && self.ray.is_some()
    }
}

/// Filter state of one hand.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct HandFilter {
    last: Option<Filtered>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Filtered {
    time: f64,
    raw_palm: DVec3,
    origin: DVec3,
    dir: DVec3,
    palm: DVec3,
    pen: DVec3,
}

fn blend(old: DVec3, new: DVec3, dt: f64, tau: f64) -> DVec3 {
    if tau <= 0.0 {
        return new;
    }
    let a = 1.0 - (-dt / tau).fexp();
    old + (new - old) * a
}

impl HandFilter {
    /// Reads `hand` from the frame and updates the filter.
    pub fn read(&mut self, cx: &ToolContext, hand: Hand, s: &GcToolSettings) -> HandIn {
        let state = cx.gestures[hand.index()];
        let none = HandIn {
            gesture: Gesture::None,
            state,
            ray: None,
            palm: None,
            pen: None,
            teleported: false,
        };
        let Some(h) = cx.frame.hand(hand) else {
            self.last = None;
            return none;
        };
        let knuckles = [
            Joint::IndexProximal,
            Joint::MiddleProximal,
            Joint::RingProximal,
            Joint::LittleProximal,
        ]
        .map(|j| h.pos(j));
        let (Some(wrist), Some(tip)) = (h.pos(Joint::Wrist), h.pos(Joint::IndexTip)) else {
            return none;
        };
        let Some(k) = knuckles
            .iter()
            .try_fold(DVec3::ZERO, |acc, k| k.map(|k| acc + k))
        else {
            return none;
        };
        let k = k * 0.25;
        let Some(dir) = (k - wrist).try_normalize() else {
            return none;
        };
        let palm = h
            .pos(Joint::Palm)
            .unwrap_or((wrist + h.pos(Joint::MiddleProximal).unwrap_or(k)) * 0.5);
        let t = cx.frame.time;
        let mut teleported = false;
        let next = match self.last {
            Some(f) if t > f.time => {
                let dt = t - f.time;
                teleported = (palm - f.raw_palm).length() / dt > s.max_hand_speed;
                if teleported {
                    None
                } else {
                    Some(Filtered {
                        time: t,
                        raw_palm: palm,
                        origin: blend(f.origin, palm, dt, s.ray_smoothing),
                        dir: blend(f.dir, dir, dt, s.ray_smoothing).normalize_or(dir),
                        palm: blend(f.palm, palm, dt, s.point_smoothing),
                        pen: blend(f.pen, tip, dt, s.point_smoothing),
                    })
                }
            }
            _ => None,
        };
        let f = next.unwrap_or(Filtered {
            time: t,
            raw_palm: palm,
            origin: palm,
            dir,
            palm,
            pen: tip,
        });
        self.last = Some(f);
        HandIn {
            gesture: state.gesture,
            state,
            ray: Some(Ray {
                origin: f.origin,
                dir: f.dir,
            }),
            palm: Some(f.palm),
            pen: Some(f.pen),
            teleported,
        }
    }
}
