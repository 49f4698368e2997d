//! The styling ops. Each held tool application is one op carrying its
//! sampled pointer path (one frame per sample), so replay recomputes the
//! same frames in the same order and reproduces the result bit for bit.
//! Every op works on a copy of the network and replaces it only on
//! success (and the log applies ops to a copy of the document), so a
//! failing op changes nothing.

use serde::{Deserialize, Serialize};

use crate::doc::{Document, ObjectId, ObjectKind, OpError, OpOutcome};
use crate::math::DVec3;

use super::curve::{fit_curve, FitMode};
use super::network::{CurveNetwork, Piece};
use super::surface::{SurfaceSystem, SurfaceWeights};
use super::tools::{check_path, CurveSession, PullParams, SharpenLimits, SmoothParams, StopReason};
use super::StylingError;

/// Create an empty curve network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveNetworkCreate {
    /// Mesh samples per patch side (2..=256).
    pub resolution: u32,
    /// Displacement control points per patch side for the surface tools
    /// (4..=64).
    pub surface_n: u32,
}

/// Draw a curve into a network from tracked samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveDraw {
    /// The network.
    pub id: ObjectId,
    /// Tracked samples (at least 4, finite, no consecutive duplicates).
    pub samples: Vec<[f64; 3]>,
    /// Interpolate or approximate to a tolerance.
    pub fit: FitMode,
    /// Arc-length resampling spacing applied first, if any.
    pub resample: Option<f64>,
    /// Closest approach under which an existing curve is intersected.
    pub snap_tol: f64,
}

/// Smoother held along a pointer path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSmooth {
    /// The network.
    pub id: ObjectId,
    /// The curve.
    pub curve: usize,
    /// Weights.
    pub params: SmoothParams,
    /// Pointer tip per frame.
    pub path: Vec<[f64; 3]>,
}

/// Sharpener held along a pointer path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSharpen {
    /// The network.
    pub id: ObjectId,
    /// The curve.
    pub curve: usize,
    /// Weights (used negated).
    pub params: SmoothParams,
    /// Where it stops.
    pub limits: SharpenLimits,
    /// Pointer tip per frame.
    pub path: Vec<[f64; 3]>,
}

/// Puller: the curve point closest to the first sample follows the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvePull {
    /// The network.
    pub id: ObjectId,
    /// The curve.
    pub curve: usize,
    /// Weights.
    pub params: PullParams,
    /// Pointer tip per frame (the first picks the point).
    pub path: Vec<[f64; 3]>,
}

/// Delete a curve (and the patches using it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveDelete {
    /// The network.
    pub id: ObjectId,
    /// The curve.
    pub curve: usize,
}

/// Fill an explicitly picked loop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveFillLoop {
    /// The network.
    pub id: ObjectId,
    /// 3 to 8 pieces head to tail.
    pub pieces: Vec<Piece>,
}

/// Fill every loop found automatically.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveFillAuto {
    /// The network.
    pub id: ObjectId,
}

/// Surface smoother (`0 < f < 1`) or sharpener (`f > 1`) on a patch, one
/// frame per path sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceEquilibrium {
    /// The network.
    pub id: ObjectId,
    /// The patch.
    pub patch: usize,
    /// Internal energy weights.
    pub weights: SurfaceWeights,
    /// Factor applied to `w_q` each frame.
    pub f: f64,
    /// Cap on `w_q` (sharpener bound; >= 1).
    pub wq_max: f64,
    /// Pointer tip per frame.
    pub path: Vec<[f64; 3]>,
}

/// Surface puller: the patch point at `(u0, v0)` follows the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfacePull {
    /// The network.
    pub id: ObjectId,
    /// The patch.
    pub patch: usize,
    /// Internal energy weights.
    pub weights: SurfaceWeights,
    /// Attractor weight.
    pub wpp: f64,
    /// Patch parameter of the pulled point.
    pub u0: f64,
    /// Patch parameter of the pulled point.
    pub v0: f64,
    /// Target per frame.
    pub path: Vec<[f64; 3]>,
}

fn network_of(doc: &Document, id: ObjectId, op: &'static str) -> Result<CurveNetwork, OpError> {
    match &doc.get(id)?.kind {
        ObjectKind::CurveNetwork(n) => Ok(n.clone()),
        #[allow(unreachable_patterns)]
        other => Err(OpError::WrongKind {
            id,
            op,
            expected: "curve_network",
            found: other.name(),
        }),
    }
}

fn store(
    doc: &mut Document,
    id: ObjectId,
    net: CurveNetwork,
    work: u64,
) -> Result<OpOutcome, OpError> {
    doc.add_work(work);
    doc.replace(id, ObjectKind::CurveNetwork(net))?;
    Ok(OpOutcome::default())
}

/// `curve_network_create`.
pub fn apply_create(doc: &mut Document, op: &CurveNetworkCreate) -> Result<OpOutcome, OpError> {
    let net = CurveNetwork::new(op.resolution, op.surface_n)?;
    let id = doc.insert(ObjectKind::CurveNetwork(net))?;
    Ok(OpOutcome { created: Some(id) })
}

/// `curve_draw`.
pub fn apply_draw(doc: &mut Document, op: &CurveDraw) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_draw")?;
    let c = fit_curve(&op.samples, op.fit, op.resample)?;
    let work = (c.n() * net.curves.len()) as u64;
    net.add_curve(c, op.snap_tol)?;
    store(doc, op.id, net, work)
}

/// `curve_smooth`.
pub fn apply_smooth(doc: &mut Document, op: &CurveSmooth) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_smooth")?;
    op.params.validate()?;
    let path = check_path(&op.path)?;
    let mut s = CurveSession::new(net.curve(op.curve)?.clone())?;
    s.smooth(&op.params, &path)?;
    let work = (s.curve.n() * path.len()) as u64;
    net.set_curve(op.curve, s.curve)?;
    store(doc, op.id, net, work)
}

/// `curve_sharpen`. Stopping early is not an error: the frames before the
/// stop are kept (the tool is released there).
pub fn apply_sharpen(doc: &mut Document, op: &CurveSharpen) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_sharpen")?;
    op.params.validate()?;
    op.limits.validate()?;
    let path = check_path(&op.path)?;
    let mut s = CurveSession::new(net.curve(op.curve)?.clone())?;
    let (frames, _stop): (usize, Option<StopReason>) = s.sharpen(&op.params, &op.limits, &path)?;
    let work = (s.curve.n() * frames.max(1)) as u64;
    net.set_curve(op.curve, s.curve)?;
    store(doc, op.id, net, work)
}

/// `curve_pull`.
pub fn apply_pull(doc: &mut Document, op: &CurvePull) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_pull")?;
    op.params.validate()?;
    let path = check_path(&op.path)?;
    let curve = net.curve(op.curve)?.clone();
    let (t0, _) = curve.closest(path[0]);
    let mut s = CurveSession::new(curve)?;
    s.pull(&op.params, t0, &path)?;
    let work = (s.curve.n() * path.len()) as u64;
    net.set_curve(op.curve, s.curve)?;
    store(doc, op.id, net, work)
}

/// `curve_delete`.
pub fn apply_delete(doc: &mut Document, op: &CurveDelete) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_delete")?;
    net.delete_curve(op.curve)?;
    store(doc, op.id, net, 1)
}

/// `curve_fill_loop`.
pub fn apply_fill_loop(doc: &mut Document, op: &CurveFillLoop) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_fill_loop")?;
    net.fill(&op.pieces)?;
    store(doc, op.id, net, 1)
}

/// `curve_fill_auto`.
pub fn apply_fill_auto(doc: &mut Document, op: &CurveFillAuto) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "curve_fill_auto")?;
    net.fill_all()?;
    store(doc, op.id, net, 1)
}

fn patch_system(
    net: &CurveNetwork,
    k: usize,
    w: &SurfaceWeights,
) -> Result<SurfaceSystem, StylingError> {
    net.surface_system(k, w)
}

/// `surface_smooth` and `surface_sharpen`.
pub fn apply_equilibrium(
    doc: &mut Document,
    op: &SurfaceEquilibrium,
    sharpen: bool,
) -> Result<OpOutcome, OpError> {
    let name = if sharpen {
        "surface_sharpen"
    } else {
        "surface_smooth"
    };
    let mut net = network_of(doc, op.id, name)?;
    let path = check_path(&op.path)?;
    let f_ok = if sharpen {
        op.f > 1.0 && op.f <= 2.0
    } else {
        op.f > 0.0 && op.f < 1.0
    };
    if !f_ok || !op.f.is_finite() {
        return Err(StylingError::BadParameter(
            "f must be in (0, 1) for the smoother and (1, 2] for the sharpener",
        )
        .into());
    }
    if !(op.wq_max.is_finite() && (1.0..=100.0).contains(&op.wq_max)) {
        return Err(StylingError::BadParameter("wq_max must be in [1, 100]").into());
    }
    let mut sys = patch_system(&net, op.patch, &op.weights)?;
    let (d, _wq) =
        sys.equilibrium_frames(&net.patches[op.patch].disp, op.f, path.len(), op.wq_max)?;
    let work = (d.len() * path.len()) as u64;
    net.patches[op.patch].disp = d;
    store(doc, op.id, net, work)
}

/// `surface_pull`.
pub fn apply_surface_pull(doc: &mut Document, op: &SurfacePull) -> Result<OpOutcome, OpError> {
    let mut net = network_of(doc, op.id, "surface_pull")?;
    let path = check_path(&op.path)?;
    if !((0.0..=1.0).contains(&op.u0) && (0.0..=1.0).contains(&op.v0)) {
        return Err(StylingError::BadParameter("u0 and v0 must be in [0, 1]").into());
    }
    let mut sys = patch_system(&net, op.patch, &op.weights)?;
    let base0 = net.patch_base_point(op.patch, op.u0, op.v0)?;
    let targets: Vec<DVec3> = path;
    let d = sys.pull(
        &net.patches[op.patch].disp,
        op.u0,
        op.v0,
        base0,
        op.wpp,
        &targets,
    )?;
    let work = (d.len() * targets.len()) as u64;
    net.patches[op.patch].disp = d;
    store(doc, op.id, net, work)
}
