//! [`GestureClassifier`]: hand features in, a debounced [`Gesture`] per
//! hand out, with its thresholds and timings ([`GestureSettings`]) and what
//! it holds between frames ([`GestureState`]).

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};

use super::features::HandFeatures;
use super::label::{Gesture, GestureLabel};
use crate::interact::input::{HandJoints, Pose};

/// Thresholds and timings of the classifier.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GestureSettings {
    /// A finger with curl above this is curled.
    pub curled: f64,
    /// A finger with curl below this is straight.
    pub straight: f64,
    /// Index curl range of a pinch.
    pub pinch_index: (f64, f64),
    /// Largest pinch gap, relative to the palm length.
    pub pinch_gap: f64,
    /// A pinch closes below this gap (metres) ...
    pub pinch_close: f64,
    /// ... and opens again above this one.
    pub pinch_open: f64,
    /// How much wider the region to stay in a class is than the one to
    /// enter it (in curl units; the gap limit widens by the same fraction).
    pub margin: f64,
    /// Seconds a new class must persist before it is output.
    pub debounce: f64,
    /// Seconds of unclassifiable frames before the output becomes `None`.
    pub ambiguous_timeout: f64,
    /// Time constant of the feature filter, seconds (0 = off).
    pub smoothing: f64,
    /// The body centre is this far below the head, metres (DOWN).
    pub torso_drop: f64,
    /// Hysteresis of DOWN, metres.
    pub down_margin: f64,
}

impl Default for GestureSettings {
    fn default() -> Self {
        Self {
            curled: 0.6,
            straight: 0.25,
            pinch_index: (0.3, 0.62),
            pinch_gap: 0.85,
            pinch_close: 0.014,
            pinch_open: 0.022,
            margin: 0.08,
            debounce: 0.035,
            ambiguous_timeout: 0.3,
            smoothing: 0.02,
            torso_drop: 0.55,
            down_margin: 0.05,
        }
    }
}

/// What the classifier says about one hand this frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GestureState {
    /// The debounced gesture.
    pub gesture: Gesture,
    /// For [`Gesture::Pinch`]: the fingers touch.
    pub pinch_closed: bool,
    /// Thumb-tip to index-tip distance, metres (smoothed); 0 without a hand.
    pub pinch_gap: f64,
    /// The hand is below the body centre.
    pub down: bool,
    /// Time the current gesture started.
    pub since: f64,
}

impl GestureState {
    /// The label this state corresponds to, if any.
    pub fn label(&self) -> Option<GestureLabel> {
        Some(match self.gesture {
            Gesture::None => return None,
            Gesture::Open => GestureLabel::Open,
            Gesture::Fist => GestureLabel::Fist,
            Gesture::Point => GestureLabel::Point,
            Gesture::Pinch if self.pinch_closed => GestureLabel::PinchClosed,
            Gesture::Pinch => GestureLabel::PinchOpen,
        })
    }
}

/// The classifier of one hand.
#[derive(Clone, Debug)]
pub struct GestureClassifier {
    pub(super) settings: GestureSettings,
    pub(super) features: Option<HandFeatures>,
    pub(super) last_time: f64,
    pub(super) stable: Option<GestureLabel>,
    pub(super) since: f64,
    pub(super) candidate: Option<(GestureLabel, f64)>,
    pub(super) ambiguous_since: Option<f64>,
    pub(super) down: bool,
}

impl Default for GestureClassifier {
    fn default() -> Self {
        Self::new(GestureSettings::default())
    }
}

impl GestureClassifier {
    /// A classifier with `settings`.
    pub fn new(settings: GestureSettings) -> Self {
        Self {
            settings,
            features: None,
            last_time: f64::NEG_INFINITY,
            stable: None,
            since: 0.0,
            candidate: None,
            ambiguous_since: None,
            down: false,
        }
    }

    /// The current state, without a new frame.
    pub fn state(&self) -> GestureState {
        let label = self.stable;
        GestureState {
            gesture: label.map_or(Gesture::None, GestureLabel::gesture),
            pinch_closed: label == Some(GestureLabel::PinchClosed),
            pinch_gap: self.features.map_or(0.0, |f| f.gap),
            down: self.down,
            since: self.since,
        }
    }

    /// Feeds one frame: the hand (already sanitized; `None` when lost) and
    /// the head pose (for DOWN).
    pub fn update(
        &mut self,
        time: f64,
        hand: Option<&HandJoints>,
        head: Option<&Pose>,
    ) -> GestureState {
        let Some(raw) = hand.and_then(HandFeatures::of) else {
            self.lose(time);
            return self.state();
        };
        let s = self.settings;
        let f = match self.features {
            Some(prev) if s.smoothing > 0.0 && time > self.last_time => {
                let a = 1.0 - (-(time - self.last_time) / s.smoothing).fexp();
                prev.blend(&raw, a)
            }
            _ => raw,
        };
        self.features = Some(f);
        self.last_time = time;
        if let Some(h) = head {
            let centre = h.position.y - s.torso_drop;
            let limit = if self.down {
                centre + s.down_margin
            } else {
                centre
            };
            self.down = f.centre.y < limit;
        }
        let candidate = self.classify(&f);
        match candidate {
            None => {
                self.candidate = None;
                let since = *self.ambiguous_since.get_or_insert(time);
                if time - since >= s.ambiguous_timeout && self.stable.is_some() {
                    self.stable = None;
                    self.since = time;
                }
            }
            Some(c) => {
                self.ambiguous_since = None;
                if Some(c) == self.stable {
                    self.candidate = None;
                } else {
                    let start = match self.candidate {
                        Some((k, t0)) if k == c => t0,
                        _ => time,
                    };
                    self.candidate = Some((c, start));
                    if time - start >= s.debounce - 1e-9 {
                        self.stable = Some(c);
                        self.since = time;
                        self.candidate = None;
                    }
                }
            }
        }
        self.state()
    }

    pub(super) fn lose(&mut self, time: f64) {
        if self.stable.is_some() {
            self.since = time;
        }
        self.features = None;
        self.stable = None;
        self.candidate = None;
        self.ambiguous_since = None;
    }

    /// The class the features fall in: the current one if they are within
    /// its wide region, else the first whose strict region holds them.
    pub(super) fn classify(&self, f: &HandFeatures) -> Option<GestureLabel> {
        if let Some(cur) = self.stable {
            if self.fits(cur, f, true) {
                return Some(cur);
            }
        }
        GestureLabel::ALL
            .into_iter()
            .find(|&l| self.fits(l, f, false))
    }

    pub(super) fn fits(&self, label: GestureLabel, f: &HandFeatures, stay: bool) -> bool {
        let s = &self.settings;
        let m = if stay { s.margin } else { 0.0 };
        let index = f.curls[0];
        let others_min = f.curls[1..].iter().copied().fold(f64::INFINITY, f64::min);
        let others_max = f.curls[1..].iter().copied().fold(0.0, f64::max);
        let pinch = || {
            index > s.pinch_index.0 - m
                && index < s.pinch_index.1 + m
                && f.gap / f.palm < s.pinch_gap * (1.0 + m)
        };
        match label {
            GestureLabel::Fist => index > s.curled + 0.05 - m && others_min > s.curled - m,
            GestureLabel::Point => index < s.straight + m && others_min > s.curled - m,
            GestureLabel::Open => index < s.straight + m && others_max < s.straight + 0.15 + m,
            // Open <-> closed: close below `pinch_close`, open above
            // `pinch_open`; entering from another gesture, the midpoint.
            GestureLabel::PinchClosed => {
                let limit = match (stay, self.stable) {
                    (true, _) => s.pinch_open,
                    (false, Some(GestureLabel::PinchOpen)) => s.pinch_close,
                    (false, _) => 0.5 * (s.pinch_close + s.pinch_open),
                };
                pinch() && f.gap < limit
            }
            GestureLabel::PinchOpen => {
                let limit = match (stay, self.stable) {
                    (true, _) => s.pinch_close,
                    (false, Some(GestureLabel::PinchClosed)) => s.pinch_open,
                    (false, _) => 0.5 * (s.pinch_close + s.pinch_open),
                };
                pinch() && f.gap >= limit
            }
        }
    }
}
