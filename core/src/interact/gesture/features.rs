//! [`HandFeatures`]: the per-hand numbers the classifier reads (finger
//! curls, pinch distance, palm), computed from the sanitized joints.

use crate::math::DVec3;

use crate::interact::gesture::handmodel::FLEX_MAX;
use crate::interact::input::{HandJoints, Joint};

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

    pub(super) fn blend(&self, newer: &HandFeatures, a: f64) -> HandFeatures {
        let l = |x: f64, y: f64| x + (y - x) * a;
        HandFeatures {
            curls: [0, 1, 2, 3].map(|i| l(self.curls[i], newer.curls[i])),
            gap: l(self.gap, newer.gap),
            palm: l(self.palm, newer.palm),
            centre: newer.centre,
        }
    }
}
