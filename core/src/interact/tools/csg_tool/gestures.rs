//! The CSG tool's gestures in progress (an operand drag, a drag of the
//! fused result, a two-hand scale), what a ray points at, and the operands'
//! boxes it is picked against.

use crate::doc::{Document, Edit, ObjectId, ObjectKind, Op};
use crate::math::{DAffine3, DVec3, Transform};
use crate::sdf::placement::two_hand_ratio;
use crate::sdf::{OperandIndex, SdfMoveFused, SdfScaleTwoHand};
use crate::sdf::{ScaleAxis, SdfVolume};

use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::{Hand, Pose};
use crate::interact::tools::pick::Ray;

/// What a ray or the selection points at, in the tool's volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Target {
    Operand(usize),
    Volume,
}

/// One hand dragging a pending operand.
#[derive(Clone, Copy, Debug)]
pub(super) struct OperandDrag {
    pub(super) volume: ObjectId,
    pub(super) index: usize,
    pub(super) base: Transform,
    pub(super) hand: Hand,
    pub(super) grip0: Pose,
    /// Model-space motion so far.
    pub(super) motion: Similarity,
    pub(super) lost_since: Option<f64>,
}

impl OperandDrag {
    pub(super) fn transform(&self) -> Transform {
        self.motion.then_transform(&self.base)
    }
}

/// One hand dragging the fused result of a volume.
#[derive(Clone, Copy, Debug)]
pub(super) struct FusedDrag {
    pub(super) volume: ObjectId,
    /// The volume's placement (its own frame to model space).
    pub(super) placement: Transform,
    pub(super) hand: Hand,
    pub(super) grip0: Pose,
    /// Model-space motion so far.
    pub(super) motion: Similarity,
    pub(super) lost_since: Option<f64>,
}

impl FusedDrag {
    /// The op moving the result by the motion so far, in the volume's own
    /// frame; `None` for no motion or a placement with a per-axis scale
    /// (the motion would not stay a similarity there).
    pub(super) fn op(&self) -> Option<Op> {
        let p = &self.placement;
        let [a, b, c] = p.scale;
        if a != b || b != c || a <= 0.0 {
            return None;
        }
        let own = Similarity {
            translate: DVec3::from_array(p.translate),
            rotate: crate::math::DQuat::from_array(p.rotate).normalize(),
            scale: a,
        };
        let local = own.conjugate(&self.motion);
        let transform = local.then_transform(&Transform::IDENTITY);
        if !local.is_valid() || transform.validate().is_err() || transform == Transform::IDENTITY {
            return None;
        }
        Some(Op::SdfMoveFused(Edit::new(
            self.volume,
            SdfMoveFused { transform },
        )))
    }
}

/// Both hands scaling a pending operand.
#[derive(Clone, Copy, Debug)]
pub(super) struct ScaleGesture {
    pub(super) volume: ObjectId,
    pub(super) index: usize,
    pub(super) base: Transform,
    /// Model-space hand positions (left, right) at the start and now.
    pub(super) start: [DVec3; 2],
    pub(super) end: [DVec3; 2],
    pub(super) axis: ScaleAxis,
    pub(super) lost_since: Option<f64>,
}

impl ScaleGesture {
    pub(super) fn op(&self) -> Edit<SdfScaleTwoHand> {
        Edit::new(
            self.volume,
            SdfScaleTwoHand {
                operand: OperandIndex(self.index),
                axis: self.axis,
                hands_start: self.start.map(|p| p.to_array()),
                hands_end: self.end.map(|p| p.to_array()),
            },
        )
    }

    /// The operand's placement if the gesture ended now.
    pub(super) fn transform(&self) -> Transform {
        let op = self.op().edit;
        let r = two_hand_ratio(op.hands_start, op.hands_end).unwrap_or(1.0);
        let mut t = self.base;
        match self.axis {
            ScaleAxis::X => t.scale[0] *= r,
            ScaleAxis::Y => t.scale[1] *= r,
            ScaleAxis::Z => t.scale[2] *= r,
            ScaleAxis::Uniform => t.scale = t.scale.map(|s| s * r),
        }
        t
    }
}

/// Local boxes of the pending operands, for picking.
#[derive(Clone, Debug, Default)]
pub(super) struct OperandBoxes {
    pub(super) key: Option<(ObjectId, Vec<crate::sdf::Operand>)>,
    pub(super) boxes: Vec<Option<(DAffine3, DVec3, DVec3)>>,
}

impl OperandBoxes {
    pub(super) fn refresh(&mut self, id: ObjectId, v: &SdfVolume) {
        if self
            .key
            .as_ref()
            .is_some_and(|(k, p)| *k == id && *p == v.pending)
        {
            return;
        }
        self.boxes = v
            .pending
            .iter()
            .map(|o| {
                let f = v.placed(o).ok()?;
                Some((f.inverse, f.local_box.0, f.local_box.1))
            })
            .collect();
        self.key = Some((id, v.pending.clone()));
    }

    /// The nearest operand box along `ray` (model space) within `max_t`.
    pub(super) fn pick(&self, ray: &Ray, max_t: f64) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, b) in self.boxes.iter().enumerate() {
            let Some((inv, lo, hi)) = b else { continue };
            let o = inv.transform_point3(ray.origin);
            let d = inv.transform_vector3(ray.dir);
            // The local ray's parameter equals the model one (same t).
            let Some(t) = slab(o, d, *lo, *hi) else {
                continue;
            };
            if t <= max_t && best.is_none_or(|(_, bt)| t <= bt) {
                best = Some((i, t));
            }
        }
        best
    }
}

/// Entry parameter of the ray `o + t d` into the box (0 when inside).
pub(super) fn slab(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<f64> {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-15 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then_some(t0)
}

/// The volume the tool edits: `preferred` if still there, else the newest.
pub(super) fn volume(
    doc: &Document,
    preferred: Option<ObjectId>,
) -> Option<(ObjectId, &SdfVolume)> {
    let as_volume = |id: ObjectId| match &doc.get(id).ok()?.kind {
        ObjectKind::SdfVolume(v) => Some((id, v)),
        #[allow(unreachable_patterns)]
        _ => None,
    };
    preferred
        .and_then(as_volume)
        .or_else(|| doc.objects().filter_map(|(id, _)| as_volume(id)).last())
}
