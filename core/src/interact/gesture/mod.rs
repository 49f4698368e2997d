//! The hand gesture classifier of paper 1 (gc-assembly, §4): OPEN, FIST,
//! POINT and PINCH (open or closed, with the finger gap as a value), plus
//! DOWN when the hand is below the centre of the body.
//!
//! Choices:
//! - **Features, not a learned model.** Each finger's curl is the sum of the
//!   bend angles at MCP, PIP and DIP (from joint positions, so it does not
//!   depend on the hand's orientation or on joint rotations, which runtimes
//!   estimate less well), normalized to `[0, 1]`; the pinch gap is the
//!   thumb-tip to index-tip distance, compared relative to the palm length
//!   so that small and large hands classify alike. Four rules on these
//!   features are transparent and need no training data.
//! - **Hysteresis:** every class has a strict region to enter it and a
//!   wider one to stay in it ([`GestureSettings::margin`]), and PINCH
//!   open/closed has two gap thresholds.
//! - **Debounce:** a new class is output only after it was seen for
//!   [`GestureSettings::debounce`] seconds in a row. Frames that fit no
//!   class keep the current output; after [`GestureSettings::ambiguous_timeout`]
//!   seconds of them the output becomes [`Gesture::None`].
//! - Features are smoothed with an exponential filter (time constant
//!   [`GestureSettings::smoothing`]) to take out tracking jitter.
//! - A lost hand outputs [`Gesture::None`] at once (no debounce: tools must
//!   stop acting on a hand they cannot see).

pub(crate) mod bimanual;
pub(crate) mod controller_hand;
pub(crate) mod handmodel;
pub(crate) mod similarity;

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};

use crate::math::DVec3;

use crate::interact::gesture::handmodel::FLEX_MAX;
use crate::interact::input::{HandJoints, Joint, Pose};

/// A classified hand gesture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Gesture {
    /// No hand, or no gesture recognized.
    None,
    /// Open palm: select by ray.
    Open,
    /// Fist: grab and manipulate.
    Fist,
    /// Index pointing, the others curled: sketch.
    Point,
    /// Thumb and index opposed: shape type and thickness.
    Pinch,
}

/// The five poses the classifier tells apart (PINCH split by open/closed):
/// the labels of the test set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GestureLabel {
    /// OPEN.
    Open,
    /// FIST.
    Fist,
    /// POINT.
    Point,
    /// PINCH with a gap.
    PinchOpen,
    /// PINCH with the fingers touching.
    PinchClosed,
}

impl GestureLabel {
    /// Every label.
    pub const ALL: [GestureLabel; 5] = [
        GestureLabel::Open,
        GestureLabel::Fist,
        GestureLabel::Point,
        GestureLabel::PinchOpen,
        GestureLabel::PinchClosed,
    ];

    /// The gesture this label belongs to.
    pub fn gesture(self) -> Gesture {
        match self {
            GestureLabel::Open => Gesture::Open,
            GestureLabel::Fist => Gesture::Fist,
            GestureLabel::Point => Gesture::Point,
            GestureLabel::PinchOpen | GestureLabel::PinchClosed => Gesture::Pinch,
        }
    }
}

/// Per-hand features.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandFeatures {
    /// Curl of index, middle, ring, little in `[0, 1]`.
    pub curls: [f64; 4],
    /// Thumb-tip to index-tip distance, metres.
    pub gap: f64,
    /// Palm length (wrist to middle knuckle), metres.
    pub palm: f64,
    /// Palm centre position.
    pub centre: DVec3,
}

impl HandFeatures {
    /// Features of `hand`, or `None` if a joint they need is missing.
    pub fn of(hand: &HandJoints) -> Option<HandFeatures> {
        let max: f64 = FLEX_MAX.iter().sum();
        let mut curls = [0.0; 4];
        for (f, joints) in Joint::FINGERS.iter().enumerate() {
            let p = joints.map(|j| hand.pos(j));
            let mut sum = 0.0;
            for b in 0..3 {
                let (a, m, c) = (p[b]?, p[b + 1]?, p[b + 2]?);
                sum += (m - a).angle_between(c - m);
            }
            curls[f] = (sum / max).clamp(0.0, 1.0);
        }
        let wrist = hand.pos(Joint::Wrist)?;
        let knuckle = hand.pos(Joint::MiddleProximal)?;
        let palm = (knuckle - wrist).length();
        if palm < 1e-3 {
            return None;
        }
        let gap = (hand.pos(Joint::ThumbTip)? - hand.pos(Joint::IndexTip)?).length();
        let centre = hand.pos(Joint::Palm).unwrap_or((wrist + knuckle) * 0.5);
        Some(HandFeatures {
            curls,
            gap,
            palm,
            centre,
        })
    }

    fn blend(&self, newer: &HandFeatures, a: f64) -> HandFeatures {
        let l = |x: f64, y: f64| x + (y - x) * a;
        HandFeatures {
            curls: [0, 1, 2, 3].map(|i| l(self.curls[i], newer.curls[i])),
            gap: l(self.gap, newer.gap),
            palm: l(self.palm, newer.palm),
            centre: newer.centre,
        }
    }
}

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
    settings: GestureSettings,
    features: Option<HandFeatures>,
    last_time: f64,
    stable: Option<GestureLabel>,
    since: f64,
    candidate: Option<(GestureLabel, f64)>,
    ambiguous_since: Option<f64>,
    down: bool,
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

    fn lose(&mut self, time: f64) {
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
    fn classify(&self, f: &HandFeatures) -> Option<GestureLabel> {
        if let Some(cur) = self.stable {
            if self.fits(cur, f, true) {
                return Some(cur);
            }
        }
        GestureLabel::ALL
            .into_iter()
            .find(|&l| self.fits(l, f, false))
    }

    fn fits(&self, label: GestureLabel, f: &HandFeatures, stay: bool) -> bool {
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
