//! The styling ops' payloads and how each changes a [`CurveNetwork`]. Each
//! held tool application is one op carrying its sampled pointer path (one
//! frame per sample), so replay recomputes the same frames in the same
//! order and reproduces the result bit for bit. The document names the
//! network and applies each to a copy of it, stored only on success, so a
//! failing op changes nothing. Each `apply_to` returns the work it did (for
//! the log's checkpoint spacing).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::id::ObjectId;
use crate::math::{DAffine3, DQuat, DVec3};

use super::attract::{AttractParams, Attractor};
use super::budget::Budget;
use super::curve::{fit_curve, FitMode};
use super::frame::{stroke_in_held_frame, ModelingFrame};
use super::network::{CurveNetwork, Piece};
use super::surface::SurfaceWeights;
use super::surface_hold::{hold_equilibrium, hold_pull, EquilibriumHold};
use super::tools::{check_path, CurveSession, PullParams, SharpenLimits, SmoothParams, StopReason};
use super::StylingError;

use crate::id::index_type;

index_type!(
    /// A curve of a network, by index in creation order. Serialized as a
    /// plain number.
    CurveId,
    "curve",
    "A curve of the network, by index (0 is the first drawn)."
);
index_type!(
    /// A patch of a network, by index in fill order. Serialized as a plain
    /// number.
    PatchId,
    "patch",
    "A patch of the network, by index (0 is the first filled)."
);

/// Create an empty curve network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveNetworkCreate {
    /// Mesh samples per patch side (2..=256).
    #[schemars(range(min = 2, max = 256))]
    pub resolution: u32,
    /// Displacement control points per patch side for the surface tools
    /// (4..=64).
    #[schemars(range(min = 4, max = 64))]
    pub surface_n: u32,
}

/// Draw a curve into a network from tracked samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveDraw {
    /// Tracked samples (at least 4, finite, no consecutive duplicates).
    #[schemars(extend("x-unit" = "m"))]
    pub samples: Vec<[f64; 3]>,
    /// Interpolate or approximate to a tolerance.
    pub fit: FitMode,
    /// Arc-length resampling spacing applied first, if any.
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub resample: Option<f64>,
    /// Closest approach under which an existing curve is intersected.
    #[schemars(extend("x-unit" = "m"), range(min = 0.0))]
    pub snap_tol: f64,
}

/// Draw a curve in the modeling frame held by the non-dominant hand
/// (paper 3 §5.4): the network is held in the frame and moves with it, so
/// each sample is taken in the frame as it was at that sample (see
/// [`super::frame::stroke_in_held_frame`]); after the stroke the
/// network's placement has moved with the frame. Holding the frame
/// without drawing is `transform_by` of the network by the hand's motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveDrawInFrame {
    /// The curve network object drawn into (held in the frame).
    pub id: ObjectId,
    /// Tracked samples of the drawing hand, model space (at least 4,
    /// finite, no consecutive duplicates once in the frame).
    #[schemars(extend("x-unit" = "m"))]
    pub samples: Vec<[f64; 3]>,
    /// The modeling frame held by the other hand: one for the whole
    /// stroke (a frame fixed in place) or one per sample.
    pub frames: Vec<ModelingFrame>,
    /// Project each sample on its frame's drawing plane (local `z = 0`).
    #[serde(default)]
    pub onto_plane: bool,
    /// Also draw the stroke's mirror image across the frame's symmetry
    /// plane (local `x = 0`).
    #[serde(default)]
    pub mirror: bool,
    /// Interpolate or approximate to a tolerance.
    pub fit: FitMode,
    /// Arc-length resampling spacing applied first, if any.
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub resample: Option<f64>,
    /// Closest approach under which an existing curve is intersected.
    #[schemars(extend("x-unit" = "m"), range(min = 0.0))]
    pub snap_tol: f64,
}

/// Smoother held along a pointer path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveSmooth {
    /// The curve.
    pub curve: CurveId,
    /// Weights.
    pub params: SmoothParams,
    /// Pointer tip per frame.
    #[schemars(extend("x-unit" = "m"))]
    pub path: Vec<[f64; 3]>,
}

/// Sharpener held along a pointer path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveSharpen {
    /// The curve.
    pub curve: CurveId,
    /// Weights (used negated).
    pub params: SmoothParams,
    /// Where it stops.
    pub limits: SharpenLimits,
    /// Pointer tip per frame.
    #[schemars(extend("x-unit" = "m"))]
    pub path: Vec<[f64; 3]>,
}

/// Puller: the curve point closest to the first sample follows the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurvePull {
    /// The curve.
    pub curve: CurveId,
    /// Weights.
    pub params: PullParams,
    /// Pointer tip per frame (the first picks the point).
    #[schemars(extend("x-unit" = "m"))]
    pub path: Vec<[f64; 3]>,
}

/// Attractor held on a curve (paper §2.2 eq. 5, §3.3): the curve, or its
/// part around the pointer, is drawn towards a point, a line, a plane or
/// another curve of the network for `frames` frames; the network's other
/// curves follow at their junctions, patches keep their boundaries.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveAttract {
    /// The attracted curve.
    pub curve: CurveId,
    /// What it is drawn towards.
    pub attractor: Attractor,
    /// Weights and locality.
    pub params: AttractParams,
    /// Pointer tip: the curve point nearest it centres the gaussian of a
    /// local attraction (`params.alpha > 0`, then required; ignored with
    /// `alpha = 0`).
    #[schemars(extend("x-unit" = "m"))]
    pub at: Option<[f64; 3]>,
    /// Frames the tool is held (1..=100000); each frame moves the curve
    /// `weight / (weight + wp0)` of the way for a uniform attraction.
    #[schemars(range(min = 1, max = 100000))]
    pub frames: u32,
}

/// Delete a curve (and the patches using it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveDelete {
    /// The curve.
    pub curve: CurveId,
}

/// Fill an explicitly picked loop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveFillLoop {
    /// 3 to 16 pieces (`ngon::MAX_SIDES`) head to tail.
    pub pieces: Vec<Piece>,
}

/// Fill every loop found automatically.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveFillAuto {}

/// Surface smoother (`0 < f < 1`) or sharpener (`f > 1`) on a patch, one
/// frame per path sample, acting where the path passes (within `radius`)
/// and stopping before the patch would overhang its boundary (see
/// [`super::surface_hold`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceEquilibrium {
    /// The patch.
    pub patch: PatchId,
    /// Internal energy weights.
    pub weights: SurfaceWeights,
    /// Factor applied to `w_q` each frame where the pointer is: in (0, 1)
    /// for the smoother, (1, 2] for the sharpener.
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 2.0))]
    pub f: f64,
    /// Cap on `w_q` (sharpener bound).
    #[schemars(range(min = 1.0, max = 100.0))]
    pub wq_max: f64,
    /// Pointer tip per frame: the tool acts around it.
    #[schemars(extend("x-unit" = "m"))]
    pub path: Vec<[f64; 3]>,
    /// How far from the pointer the tool acts: the gaussian radius of its
    /// weight on the patch. Absent: the whole patch at once (the paper's
    /// global tool; only the number of frames matters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub radius: Option<f64>,
    /// The most any point of the patch moves in one frame. Absent:
    /// unbounded (the sharpener then grows by `f` per frame up to
    /// `wq_max`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub max_step: Option<f64>,
}

/// Surface puller: the patch point at `(u0, v0)` follows the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfacePull {
    /// The patch.
    pub patch: PatchId,
    /// Internal energy weights.
    pub weights: SurfaceWeights,
    /// Attractor weight.
    pub wpp: f64,
    /// Patch parameter of the pulled point.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub u0: f64,
    /// Patch parameter of the pulled point.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub v0: f64,
    /// Target per frame.
    #[schemars(extend("x-unit" = "m"))]
    pub path: Vec<[f64; 3]>,
}

/// Surface smoother: [`SurfaceEquilibrium`] with `0 < f < 1`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(transparent)]
pub struct SurfaceSmooth(pub SurfaceEquilibrium);

/// Surface sharpener: [`SurfaceEquilibrium`] with `1 < f <= 2`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(transparent)]
pub struct SurfaceSharpen(pub SurfaceEquilibrium);

impl CurveNetworkCreate {
    /// The new, empty network.
    pub fn build(&self) -> Result<CurveNetwork, StylingError> {
        CurveNetwork::new(self.resolution, self.surface_n)
    }
}

impl CurveDraw {
    /// Fits the samples and adds the curve (intersecting existing ones).
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        let c = fit_curve(&self.samples, self.fit, self.resample)?;
        let work = (c.n() * net.curves.len()) as u64;
        net.add_curve(c, self.snap_tol)?;
        Ok(work)
    }
}

impl CurveDrawInFrame {
    /// Adds the stroke (and its mirror) to `net`, whose placement at the
    /// stroke's start is `placement`. Returns the work done and the
    /// frame's motion over the stroke (the placement moves by it).
    pub fn apply_to(
        &self,
        net: &mut CurveNetwork,
        placement: &DAffine3,
    ) -> Result<(u64, Option<(DVec3, DQuat)>), StylingError> {
        let held = stroke_in_held_frame(
            &self.samples,
            &self.frames,
            placement,
            self.onto_plane,
            self.mirror,
        )?;
        let mut work = 0;
        for stroke in std::iter::once(&held.local).chain(held.mirrored.as_ref()) {
            let c = fit_curve(stroke, self.fit, self.resample)?;
            work += (c.n() * (net.curves.len() + 1)) as u64;
            net.add_curve(c, self.snap_tol)?;
        }
        Ok((work, held.motion))
    }
}

impl CurveSmooth {
    /// Runs the smoother along the path.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        self.params.validate()?;
        let path = check_path(&self.path)?;
        let mut s = CurveSession::new(net.curve(self.curve.0)?.clone())?;
        s.smooth(&self.params, &path)?;
        let work = (s.curve.n() * path.len()) as u64;
        net.set_curve(self.curve.0, s.curve)?;
        Ok(work)
    }
}

impl CurveSharpen {
    /// Runs the sharpener along the path. Stopping early is not an error:
    /// the frames before the stop are kept (the tool is released there).
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        self.params.validate()?;
        self.limits.validate()?;
        let path = check_path(&self.path)?;
        let mut s = CurveSession::new(net.curve(self.curve.0)?.clone())?;
        let (frames, _stop): (usize, Option<StopReason>) =
            s.sharpen(&self.params, &self.limits, &path)?;
        let work = (s.curve.n() * frames.max(1)) as u64;
        net.set_curve(self.curve.0, s.curve)?;
        Ok(work)
    }
}

impl CurvePull {
    /// Runs the puller along the path.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        self.params.validate()?;
        let path = check_path(&self.path)?;
        let curve = net.curve(self.curve.0)?.clone();
        let (t0, _) = curve.closest(path[0]);
        let mut s = CurveSession::new(curve)?;
        s.pull(&self.params, t0, &path)?;
        let work = (s.curve.n() * path.len()) as u64;
        net.set_curve(self.curve.0, s.curve)?;
        Ok(work)
    }
}

impl CurveAttract {
    /// Runs the attractor for `frames` frames.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        let frames = self.frames as usize;
        net.attract(self.curve.0, &self.params, &self.attractor, self.at, frames)?;
        Ok((net.curve(self.curve.0)?.n() * frames.max(1)) as u64)
    }
}

impl CurveDelete {
    /// Deletes the curve and the patches using it.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        net.delete_curve(self.curve.0)?;
        Ok(1)
    }
}

impl CurveFillLoop {
    /// Fills the loop.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        net.fill(&self.pieces)?;
        Ok(1)
    }
}

impl CurveFillAuto {
    /// Fills every loop found.
    pub fn apply_to(&self, net: &mut CurveNetwork) -> Result<u64, StylingError> {
        net.fill_all()?;
        Ok(1)
    }
}

impl SurfaceEquilibrium {
    /// The smoother (`sharpen = false`) or sharpener along the path.
    /// Stopping before an overhang or a crease tighter than the print's
    /// `wall` (the document's) is not an error: the frames before the
    /// stop are kept.
    pub fn apply_to(
        &self,
        net: &mut CurveNetwork,
        sharpen: bool,
        wall: f64,
    ) -> Result<u64, StylingError> {
        let path = check_path(&self.path)?;
        Budget::default().check_extent("path", &path)?;
        let f_ok = if sharpen {
            self.f > 1.0 && self.f <= 2.0
        } else {
            self.f > 0.0 && self.f < 1.0
        };
        if !f_ok || !self.f.is_finite() {
            return Err(StylingError::BadParameter(
                "f must be in (0, 1) for the smoother and (1, 2] for the sharpener",
            ));
        }
        if !(self.wq_max.is_finite() && (1.0..=100.0).contains(&self.wq_max)) {
            return Err(StylingError::BadParameter("wq_max must be in [1, 100]"));
        }
        let positive = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v > 0.0);
        if !positive(self.radius) {
            return Err(StylingError::BadParameter("radius must be > 0"));
        }
        if !positive(self.max_step) {
            return Err(StylingError::BadParameter("max_step must be > 0"));
        }
        let k = self.patch.0;
        let hold = EquilibriumHold {
            f: self.f,
            wq_max: self.wq_max,
            radius: self.radius,
            max_step: self.max_step,
        };
        let (frames, _stop) = hold_equilibrium(net, k, &self.weights, &hold, &path, wall)?;
        Ok((net.patches[k].disp.len() * frames.max(1)) as u64)
    }
}

impl SurfacePull {
    /// The puller along the path, stopping (not failing) before a frame
    /// that would make the patch overhang its boundary or crease it
    /// tighter than the print's `wall` (the document's).
    pub fn apply_to(&self, net: &mut CurveNetwork, wall: f64) -> Result<u64, StylingError> {
        let path = check_path(&self.path)?;
        if !((0.0..=1.0).contains(&self.u0) && (0.0..=1.0).contains(&self.v0)) {
            return Err(StylingError::BadParameter("u0 and v0 must be in [0, 1]"));
        }
        let k = self.patch.0;
        net.patch(k)?;
        let (frames, _stop) = hold_pull(
            net,
            k,
            &self.weights,
            (self.u0, self.v0),
            self.wpp,
            &path,
            wall,
        )?;
        Ok((net.patches[k].disp.len() * frames.max(1)) as u64)
    }
}
