//! A kinematic hand model that poses a hand in the XR_EXT_hand_tracking
//! layout: hands made from controllers at run time, and (in
//! [`crate::interact::testkit`]) the gesture classifier's labelled test
//! set and the hand half of the scripted puppet.
//!
//! Fingers are chains of rigid bones (adult bone lengths, scaled per hand)
//! flexed at MCP, PIP and DIP in fixed proportion to a `curl` in `[0, 1]`,
//! spread by a `splay` angle. The thumb is a three-bone chain laid along a
//! quadratic curve from its base to a tip target that blends between
//! extended, tucked over the fingers and opposed to the index tip at a
//! given gap (a pinch); this is a simplification of the thumb's saddle
//! joint, adequate for what the classifier reads (the tip position).
//! Tracking jitter is independent Gaussian noise on every joint position.

use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};

use crate::interact::gesture::GestureLabel;
use crate::interact::input::{Hand, Joint, Pose, JOINT_COUNT};

/// A small deterministic generator (SplitMix64), so generated test sets are
/// the same on every machine.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.unit().max(1e-300);
        let u2 = self.unit();
        (-2.0 * u1.fln()).sqrt() * (std::f64::consts::TAU * u2).fcos()
    }

    /// A uniformly random unit vector.
    pub fn unit_vector(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.normal(), self.normal(), self.normal());
            if v.length_squared() > 1e-6 {
                return v.normalize();
            }
        }
    }
}

/// The pose parameters of one hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandParams {
    /// Curl of index, middle, ring, little: 0 straight, 1 fully curled.
    pub curls: [f64; 4],
    /// Spread between neighbouring fingers, radians.
    pub splay: f64,
    /// Thumb: 0 extended sideways, 1 tucked over the curled fingers.
    pub thumb_tuck: f64,
    /// Weight of the pinch: 0 thumb as `thumb_tuck` says, 1 thumb tip
    /// opposed to the index tip at `pinch_gap`.
    pub pinch: f64,
    /// Thumb-tip to index-tip distance in a pinch, metres.
    pub pinch_gap: f64,
    /// Hand size relative to an average adult hand.
    pub size: f64,
}

impl HandParams {
    /// Linear blend from `self` (t = 0) to `other` (t = 1).
    pub fn lerp(&self, other: &HandParams, t: f64) -> HandParams {
        let l = |a: f64, b: f64| a + (b - a) * t;
        HandParams {
            curls: [0, 1, 2, 3].map(|i| l(self.curls[i], other.curls[i])),
            splay: l(self.splay, other.splay),
            thumb_tuck: l(self.thumb_tuck, other.thumb_tuck),
            pinch: l(self.pinch, other.pinch),
            pinch_gap: l(self.pinch_gap, other.pinch_gap),
            size: l(self.size, other.size),
        }
    }

    /// Random parameters of a hand showing `label`, varied as real hands
    /// vary (how far fingers curl, spread, hand size).
    pub fn sample(label: GestureLabel, rng: &mut Rng) -> HandParams {
        let mut p = HandParams {
            curls: [0.0; 4],
            splay: rng.range(0.0, 0.15),
            thumb_tuck: 0.0,
            pinch: 0.0,
            pinch_gap: 0.05,
            size: rng.range(0.85, 1.15),
        };
        let curled = |rng: &mut Rng| rng.range(0.8, 1.0);
        let straight = |rng: &mut Rng| rng.range(0.0, 0.12);
        match label {
            GestureLabel::Open => {
                p.curls = [0; 4].map(|_| straight(rng));
                p.splay = rng.range(0.05, 0.2);
                p.thumb_tuck = rng.range(0.0, 0.15);
            }
            GestureLabel::Fist => {
                p.curls = [0; 4].map(|_| curled(rng));
                p.splay = rng.range(0.0, 0.05);
                p.thumb_tuck = rng.range(0.8, 1.0);
            }
            GestureLabel::Point => {
                p.curls = [straight(rng), curled(rng), curled(rng), curled(rng)];
                p.thumb_tuck = rng.range(0.6, 1.0);
            }
            GestureLabel::PinchOpen | GestureLabel::PinchClosed => {
                p.curls = [
                    rng.range(0.38, 0.55),
                    rng.range(0.1, 0.9),
                    rng.range(0.1, 0.9),
                    rng.range(0.1, 0.9),
                ];
                p.pinch = 1.0;
                p.pinch_gap = if label == GestureLabel::PinchOpen {
                    rng.range(0.028, 0.06)
                } else {
                    rng.range(0.0, 0.008)
                };
            }
        }
        p
    }
}

// Right hand, in the wrist frame: fingers along -Z, back of the hand +Y,
// thumb on -X. Per finger: knuckle x, palm length, phalanx lengths.
const FINGER_X: [f64; 4] = [-0.025, -0.005, 0.015, 0.032];
const PALM_LEN: [f64; 4] = [0.085, 0.085, 0.08, 0.072];
const PHALANX: [[f64; 3]; 4] = [
    [0.040, 0.025, 0.022],
    [0.045, 0.028, 0.023],
    [0.042, 0.027, 0.022],
    [0.033, 0.019, 0.020],
];
/// Flexion at MCP, PIP and DIP for curl 1 (radians).
pub const FLEX_MAX: [f64; 3] = [1.45, 1.75, 1.2];
const THUMB_BASE: DVec3 = DVec3::new(-0.02, -0.01, -0.02);
const THUMB_EXTENDED: DVec3 = DVec3::new(-0.07, 0.0, -0.06);
const THUMB_FRACTIONS: [f64; 3] = [0.43, 0.73, 1.0];

/// Joint poses of a hand with parameters `p`, its wrist at `wrist`
/// (fingers along the wrist's -Z, back of the hand along +Y).
pub fn hand_pose(p: &HandParams, hand: Hand, wrist: &Pose) -> [Pose; JOINT_COUNT] {
    let s = p.size;
    let mut local = [Pose::IDENTITY; JOINT_COUNT];
    local[Joint::Wrist.index()] = Pose::IDENTITY;
    for (f, joints) in Joint::FINGERS.iter().enumerate() {
        let base = DVec3::new(FINGER_X[f] * 0.4, 0.0, -0.01) * s;
        let knuckle = DVec3::new(FINGER_X[f], 0.0, -PALM_LEN[f]) * s;
        let meta_rot = DQuat::from_rotation_arc(DVec3::NEG_Z, (knuckle - base).normalize());
        local[joints[0].index()] = Pose::new(base, meta_rot);
        let splay = p.splay * (f as f64 - 1.0);
        let mut rot = meta_rot * DQuat::from_rotation_y(-splay);
        let mut at = knuckle;
        for b in 0..3 {
            rot *= DQuat::from_rotation_x(-FLEX_MAX[b] * p.curls[f]);
            local[joints[b + 1].index()] = Pose::new(at, rot);
            at += rot * DVec3::new(0.0, 0.0, -PHALANX[f][b] * s);
        }
        local[joints[4].index()] = Pose::new(at, rot);
    }
    // Palm centre: midway between the wrist and the middle knuckle.
    local[Joint::Palm.index()] = Pose::new(
        local[Joint::MiddleProximal.index()].position * 0.5,
        DQuat::IDENTITY,
    );
    // Thumb: tip target, then a quadratic curve from the base.
    let base = THUMB_BASE * s;
    let extended = base + THUMB_EXTENDED * s;
    let mid_i = local[Joint::MiddleIntermediate.index()].position;
    let mid_d = local[Joint::MiddleDistal.index()].position;
    let tucked = (mid_i + mid_d) * 0.5 + DVec3::new(0.0, -0.012, 0.0) * s;
    let free = extended.lerp(tucked, p.thumb_tuck);
    let index_tip = local[Joint::IndexTip.index()].position;
    let toward = (extended - index_tip).normalize_or(DVec3::NEG_X);
    let pinched = index_tip + toward * p.pinch_gap;
    let tip = free.lerp(pinched, p.pinch);
    let ctrl = (base + tip) * 0.5 + DVec3::new(-0.02, 0.01, 0.0) * s;
    let bez = |t: f64| base * (1.0 - t) * (1.0 - t) + ctrl * 2.0 * t * (1.0 - t) + tip * t * t;
    local[Joint::ThumbMetacarpal.index()] = Pose::new(base, DQuat::IDENTITY);
    for (k, j) in Joint::THUMB[1..].iter().enumerate() {
        let a = bez(THUMB_FRACTIONS[k]);
        let prev = bez(THUMB_FRACTIONS[k] - 0.05);
        let rot = DQuat::from_rotation_arc(DVec3::NEG_Z, (a - prev).normalize_or(DVec3::NEG_Z));
        local[j.index()] = Pose::new(a, rot);
    }
    let mirror = hand == Hand::Left;
    local.map(|l| {
        let (pos, rot) = if mirror {
            // Mirror across the YZ plane: x -> -x; a rotation mirrors as
            // (x, y, z, w) -> (x, -y, -z, w).
            let q = l.orientation;
            (
                DVec3::new(-l.position.x, l.position.y, l.position.z),
                DQuat::from_xyzw(q.x, -q.y, -q.z, q.w),
            )
        } else {
            (l.position, l.orientation)
        };
        wrist.compose(&Pose::new(pos, rot))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_finger_has_its_bone_lengths() {
        let p = HandParams::sample(GestureLabel::Open, &mut Rng::new(3));
        let p = HandParams {
            curls: [0.0; 4],
            size: 1.0,
            ..p
        };
        let j = hand_pose(&p, Hand::Right, &Pose::IDENTITY);
        let len = (j[Joint::IndexTip.index()].position - j[Joint::IndexProximal.index()].position)
            .length();
        assert!((len - 0.087).abs() < 1e-12, "{len}");
        // Thumb on -X for the right hand, +X for the left.
        assert!(j[Joint::ThumbTip.index()].position.x < -0.05);
        let l = hand_pose(&p, Hand::Left, &Pose::IDENTITY);
        assert!(l[Joint::ThumbTip.index()].position.x > 0.05);
    }

    #[test]
    fn pinch_puts_thumb_tip_at_the_gap() {
        let mut p = HandParams::sample(GestureLabel::PinchOpen, &mut Rng::new(5));
        p.pinch_gap = 0.04;
        let j = hand_pose(&p, Hand::Right, &Pose::IDENTITY);
        let gap =
            (j[Joint::ThumbTip.index()].position - j[Joint::IndexTip.index()].position).length();
        assert!((gap - 0.04).abs() < 1e-9, "{gap}");
    }
}
