//! Two-handed manipulation.
//!
//! - [`HandleBar`]: the handle-bar metaphor (Song et al. 2012, used by
//!   paper 1 §4 for the bimanual FIST): an imaginary bar between the two
//!   hands gives 7 DOF — its midpoint translates, its direction rotates (plus
//!   the hands' mean roll about the bar), its length scales.
//! - [`two_hand_scale`]: the two-controller scaling ratio of paper 2
//!   (EasyVRModeling §4.3, Eq. 1): current over initial hand distance,
//!   clamped to `[0.4, 4]` ([`SCALE_RANGE`]).
//! - [`ModelFrame`] and [`OrientGrab`]: paper 4's (warp brush §6)
//!   two-handed paradigm — the non-dominant hand orients the model while the
//!   other one works on it; model and brush are scaled together by the
//!   distance between the hands. Tools express the working hand's position
//!   in model coordinates through the frame, so a sculpt stroke is recorded
//!   in model space whatever the view.

use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};

use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::Pose;

/// The clamp of two-hand scaling ratios (paper 2, Eq. 1).
pub const SCALE_RANGE: (f64, f64) = (0.4, 4.0);

/// Hands closer than this (metres) define no bar.
pub const MIN_BAR: f64 = 0.02;

/// The two-hand scale ratio `|a1 - b1| / |a0 - b0|`, clamped to
/// [`SCALE_RANGE`]; `None` when the initial distance is below [`MIN_BAR`] or
/// a position is not finite.
pub fn two_hand_scale(a0: DVec3, b0: DVec3, a1: DVec3, b1: DVec3) -> Option<f64> {
    let d0 = (b0 - a0).length();
    let d1 = (b1 - a1).length();
    if !(d0.is_finite() && d1.is_finite()) || d0 < MIN_BAR {
        return None;
    }
    Some((d1 / d0).clamp(SCALE_RANGE.0, SCALE_RANGE.1))
}

/// A handle bar held between two hands, started at their grab poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandleBar {
    a0: Pose,
    b0: Pose,
}

impl HandleBar {
    /// A bar from the grab poses of the two hands, or `None` when they are
    /// closer than [`MIN_BAR`] (the bar's direction would be noise).
    pub fn new(a: Pose, b: Pose) -> Option<HandleBar> {
        ((b.position - a.position).length() >= MIN_BAR).then_some(HandleBar { a0: a, b0: b })
    }

    /// The world-space increment that maps the object as it was at the
    /// grab to where the hands put it now: `p -> m1 + s R (p - m0)`.
    /// `None` when the hands now are closer than [`MIN_BAR`].
    pub fn transform(&self, a: &Pose, b: &Pose) -> Option<Similarity> {
        let d0 = self.b0.position - self.a0.position;
        let d1 = b.position - a.position;
        if d1.length() < MIN_BAR {
            return None;
        }
        let s = two_hand_scale(self.a0.position, self.b0.position, a.position, b.position)?;
        let axis0 = d0.normalize();
        let swing = DQuat::from_rotation_arc(axis0, d1.normalize());
        // Roll about the bar: each hand's rotation with the swing taken
        // out, its twist about the initial axis, averaged.
        let twist = |start: &Pose, now: &Pose| {
            let delta = swing.inverse() * now.orientation * start.orientation.inverse();
            let v = DVec3::new(delta.x, delta.y, delta.z);
            let mut angle = 2.0 * v.dot(axis0).fatan2(delta.w);
            if angle > std::f64::consts::PI {
                angle -= std::f64::consts::TAU;
            } else if angle < -std::f64::consts::PI {
                angle += std::f64::consts::TAU;
            }
            angle
        };
        let roll = 0.5 * (twist(&self.a0, a) + twist(&self.b0, b));
        let r = (swing * DQuat::from_axis_angle(axis0, roll)).normalize();
        let m0 = (self.a0.position + self.b0.position) * 0.5;
        let m1 = (a.position + b.position) * 0.5;
        let out = Similarity {
            translate: m1 - r * (m0 * s),
            rotate: r,
            scale: s,
        };
        out.is_valid().then_some(out)
    }
}

/// Where the model is in the world: a rigid pose and a uniform scale
/// (model-to-world `p -> pose.position + pose.orientation * (scale * p)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelFrame {
    /// Rigid part.
    pub pose: Pose,
    /// Uniform scale (world units per model unit).
    pub scale: f64,
}

impl Default for ModelFrame {
    fn default() -> Self {
        Self {
            pose: Pose::IDENTITY,
            scale: 1.0,
        }
    }
}

impl ModelFrame {
    /// A world point in model coordinates.
    pub fn to_model(&self, world: DVec3) -> DVec3 {
        self.pose.orientation.inverse() * (world - self.pose.position) / self.scale
    }

    /// A model point in world coordinates.
    pub fn to_world(&self, model: DVec3) -> DVec3 {
        self.pose.position + self.pose.orientation * (model * self.scale)
    }

    /// A world-space length (a brush radius the user sees) in model units.
    pub fn length_to_model(&self, world: f64) -> f64 {
        world / self.scale
    }
}

/// The non-dominant hand holding the model: the model follows the hand's
/// rigid motion since the grab. While the other hand also grabs, the
/// distance between the hands scales model (and brush, which is scaled in
/// world space with the model) by [`two_hand_scale`], about the holding
/// hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientGrab {
    hand0: Pose,
    frame0: ModelFrame,
    /// The hands' positions and the frame when scaling started, if scaling.
    scale_from: Option<(DVec3, DVec3, ModelFrame)>,
    /// The last holding pose and frame returned.
    last: (Pose, ModelFrame),
}

impl OrientGrab {
    /// Starts holding the model `frame` with the hand at `hand`.
    pub fn new(hand: Pose, frame: ModelFrame) -> OrientGrab {
        OrientGrab {
            hand0: hand,
            frame0: frame,
            scale_from: None,
            last: (hand, frame),
        }
    }

    /// The model frame with the holding hand at `hand`, and the working
    /// hand at `other` when it is also grabbing (two-hand scaling).
    pub fn frame(&mut self, hand: &Pose, other: Option<DVec3>) -> ModelFrame {
        if other.is_none() && self.scale_from.is_some() {
            // Scaling ended: keep its result and track rigidly from there.
            let (h, f) = self.last;
            *self = OrientGrab::new(h, f);
        }
        let f = self.frame_inner(hand, other);
        self.last = (*hand, f);
        f
    }

    fn frame_inner(&mut self, hand: &Pose, other: Option<DVec3>) -> ModelFrame {
        // Rigid: hand_now * hand0^-1 * model0.
        let delta = hand.compose(&self.hand0.inverse());
        let rigid = ModelFrame {
            pose: delta.compose(&self.frame0.pose),
            scale: self.frame0.scale,
        };
        match other {
            None => rigid,
            Some(o) => {
                let (h0, o0, f0) = *self.scale_from.get_or_insert((hand.position, o, rigid));
                let s = two_hand_scale(h0, o0, hand.position, o).unwrap_or(1.0);
                // Scale about the holding hand.
                let pivot = hand.position;
                let mut f = rigid;
                f.scale = f0.scale * s;
                f.pose.position = pivot + (rigid.pose.position - pivot) * s;
                f
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> Pose {
        Pose::new(DVec3::new(x, y, z), DQuat::IDENTITY)
    }

    fn apply(t: &Similarity, v: DVec3) -> DVec3 {
        t.apply(v)
    }

    #[test]
    fn handle_bar_translates_rotates_scales() {
        let bar = HandleBar::new(p(-0.2, 1.0, 0.0), p(0.2, 1.0, 0.0)).unwrap();
        // Still hands: identity.
        let t = bar
            .transform(&p(-0.2, 1.0, 0.0), &p(0.2, 1.0, 0.0))
            .unwrap();
        assert!(
            (apply(&t, DVec3::new(0.3, 0.5, 0.1)) - DVec3::new(0.3, 0.5, 0.1)).length() < 1e-12
        );
        // Both move +0.1 z: translation.
        let t = bar
            .transform(&p(-0.2, 1.0, 0.1), &p(0.2, 1.0, 0.1))
            .unwrap();
        assert!((apply(&t, DVec3::ZERO) - DVec3::new(0.0, 0.0, 0.1)).length() < 1e-12);
        // Bar turned 90° about Y and twice as long: rotation and scale about
        // the midpoint; the grabbed points stay under the hands.
        let t = bar
            .transform(&p(0.0, 1.0, 0.4), &p(0.0, 1.0, -0.4))
            .unwrap();
        assert_eq!(t.scale, 2.0);
        let a = apply(&t, DVec3::new(-0.2, 1.0, 0.0));
        assert!((a - DVec3::new(0.0, 1.0, 0.4)).length() < 1e-12, "{a}");
        // Roll: both hands turn 30° about the bar axis (X).
        let q = DQuat::from_rotation_x(0.5);
        let t = bar
            .transform(
                &Pose::new(DVec3::new(-0.2, 1.0, 0.0), q),
                &Pose::new(DVec3::new(0.2, 1.0, 0.0), q),
            )
            .unwrap();
        assert!(t.rotate.angle_between(q) < 1e-9);
    }

    #[test]
    fn scale_ratio_is_clamped() {
        let bar = HandleBar::new(p(0.0, 1.0, 0.0), p(0.1, 1.0, 0.0)).unwrap();
        let t = bar.transform(&p(0.0, 1.0, 0.0), &p(1.0, 1.0, 0.0)).unwrap();
        assert_eq!(t.scale, 4.0);
        let t = bar
            .transform(&p(0.0, 1.0, 0.0), &p(0.021, 1.0, 0.0))
            .unwrap();
        assert_eq!(t.scale, 0.4);
        assert!(HandleBar::new(p(0.0, 1.0, 0.0), p(0.01, 1.0, 0.0)).is_none());
        let s = two_hand_scale(DVec3::ZERO, DVec3::X, DVec3::ZERO, DVec3::X * f64::NAN);
        assert_eq!(s, None);
    }

    #[test]
    fn orienting_hand_carries_the_model_and_scaling_scales_the_brush() {
        let mut g = OrientGrab::new(p(0.0, 1.0, 0.0), ModelFrame::default());
        // Hand turns 90° about Y: a model point at +X ends at -Z.
        let turned = Pose::new(
            DVec3::new(0.0, 1.0, 0.0),
            DQuat::from_rotation_y(0.5 * std::f64::consts::PI),
        );
        let f = g.frame(&turned, None);
        let w = f.to_world(DVec3::new(1.0, 1.0, 0.0));
        assert!((w - DVec3::new(0.0, 1.0, -1.0)).length() < 1e-12, "{w}");
        // The working hand at model point (1,1,0) maps back to it.
        assert!((f.to_model(w) - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12);
        // Other hand grabs at 0.3 m, moves to 0.6 m: model doubles, so a
        // 2 cm world brush is 1 cm in model units.
        let f0 = g.frame(&turned, Some(DVec3::new(0.3, 1.0, 0.0)));
        assert_eq!(f0.scale, 1.0);
        let f1 = g.frame(&turned, Some(DVec3::new(0.6, 1.0, 0.0)));
        assert_eq!(f1.scale, 2.0);
        assert!((f1.length_to_model(0.02) - 0.01).abs() < 1e-15);
        // The holding hand is the pivot: the model point under it stays.
        let under = f0.to_model(turned.position);
        assert!((f1.to_world(under) - turned.position).length() < 1e-12);
        // The other hand lets go: the scale stays.
        let f2 = g.frame(&turned, None);
        assert_eq!(f2, f1);
    }
}
