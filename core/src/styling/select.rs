//! Tool selection from the pointer pose (paper §6.1, Table 1).
//!
//! The reference point is the closest curve point to the pointer's tip;
//! `d` is the tip's distance to it, `α` the angle between the pointer's
//! direction and the curve tangent there (0°..180°).
//!
//! | | 60° ≤ α ≤ 120° | α ≤ 30° or α ≥ 150° |
//! |---|---|---|
//! | d < 2 cm | edit data point | attach new curve |
//! | 2 cm ≤ d ≤ 4 cm | sharpen segment | smooth segment |
//!
//! Anything else selects nothing. Model units are metres.
//!
//! Table 1 only concerns curves. For the surface tools (§4) and for
//! picking a loop to fill, [`nearest_patch_point`] and [`nearest_loop`]
//! find what the pointer is at; the tools decide what to do with it.

use crate::math::fm::DetMath as _;
use serde::{Deserialize, Serialize};

use crate::math::{DVec2, DVec3};

use super::curve::SplineCurve;
use super::network::{CurveNetwork, Piece};
use super::ngon::ngon_chart;
use super::polygon::NgonDomain;

/// A tool chosen by the pointer pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveTool {
    /// Pull the pointed curve point (the puller).
    EditDataPoint,
    /// Sharpen the segment.
    SharpenSegment,
    /// Start a new curve attached here.
    AttachNewCurve,
    /// Smooth the segment.
    SmoothSegment,
}

/// The selection and the geometry it was made from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Selection {
    /// The tool, if the pose selects one.
    pub tool: Option<CurveTool>,
    /// Parameter of the reference point.
    pub t: f64,
    /// Distance from the tip to the curve.
    pub distance: f64,
    /// Angle to the tangent, degrees in `[0, 180]`.
    pub angle_deg: f64,
}

/// Table 1 as a function of distance (metres) and angle (degrees).
pub fn table1(distance: f64, angle_deg: f64) -> Option<CurveTool> {
    let across = (60.0..=120.0).contains(&angle_deg);
    let along = (0.0..=30.0).contains(&angle_deg) || (150.0..=180.0).contains(&angle_deg);
    let near = (0.0..0.02).contains(&distance);
    let mid = (0.02..=0.04).contains(&distance);
    match (near, mid, across, along) {
        (true, _, true, _) => Some(CurveTool::EditDataPoint),
        (true, _, _, true) => Some(CurveTool::AttachNewCurve),
        (_, true, true, _) => Some(CurveTool::SharpenSegment),
        (_, true, _, true) => Some(CurveTool::SmoothSegment),
        _ => None,
    }
}

/// Selects a tool from the pointer tip and direction relative to `curve`.
/// A non-finite or zero direction selects nothing.
pub fn select_tool(curve: &SplineCurve, tip: DVec3, dir: DVec3) -> Selection {
    let (t, distance) = curve.closest(tip);
    let tangent = curve.derivs(t, 1)[1];
    let angle_deg = if dir.length() > 0.0 && tangent.length() > 0.0 && dir.is_finite() {
        let c = (dir.normalize().dot(tangent.normalize())).clamp(-1.0, 1.0);
        c.facos().to_degrees()
    } else {
        f64::NAN
    };
    let tool = if angle_deg.is_finite() && distance.is_finite() {
        table1(distance, angle_deg)
    } else {
        None
    };
    Selection {
        tool,
        t,
        distance,
        angle_deg,
    }
}

/// Table 1 over a whole network: the live curve nearest to the tip (ties
/// go to the lower index) and the selection against it. Distances are in
/// model units; `scale` (metres per model unit) converts them for Table 1,
/// whose bands are in metres. `None` when the network has no curve.
pub fn select_in_network(
    net: &CurveNetwork,
    tip: DVec3,
    dir: DVec3,
    scale: f64,
) -> Option<(usize, Selection)> {
    let mut best: Option<(usize, Selection)> = None;
    for (i, c) in net.curves.iter().enumerate() {
        let Some(c) = c else { continue };
        let s = select_tool(c, tip, dir);
        if best.is_none_or(|(_, b)| s.distance < b.distance) {
            best = Some((i, s));
        }
    }
    best.map(|(i, mut s)| {
        s.tool = if s.angle_deg.is_finite() && (s.distance * scale).is_finite() {
            table1(s.distance * scale, s.angle_deg)
        } else {
            None
        };
        (i, s)
    })
}

/// A point of a patch the pointer is near: what the surface tools (paper
/// §4) act on when the pointer is at a surface rather than a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchPoint {
    /// The patch index.
    pub patch: usize,
    /// Its parameters (as in [`CurveNetwork::patch_point`]; in `[0, 1]²`).
    pub u: f64,
    /// See `u`.
    pub v: f64,
    /// The point.
    pub point: DVec3,
    /// Distance from the tip to it (model units).
    pub distance: f64,
}

/// Samples per chart side of the coarse search in [`nearest_patch_point`].
const PATCH_SAMPLES: usize = 8;

/// The patch point nearest to `tip` over every patch of `net` (ties go to
/// the lower patch index), or `None` when the network has no patch.
///
/// A picking query, not an exact projection: each patch's domain is
/// sampled coarsely (the unit square for 3- and 4-sided patches, each of
/// the n quad charts of an n-sided one, [`ngon_chart`]) and the best
/// sample is refined twice on a grid a quarter as wide around it, so the
/// result is within a small fraction of a patch of the true nearest point
/// (enough to choose where the puller grabs) at about 200 evaluations per
/// 4-sided patch. The domain point is always inside the patch's domain.
pub fn nearest_patch_point(net: &CurveNetwork, tip: DVec3) -> Option<PatchPoint> {
    let mut best: Option<PatchPoint> = None;
    for (k, patch) in net.patches.iter().enumerate() {
        let sides = patch.pieces.len();
        let dom = (sides > 4).then(|| NgonDomain::regular(sides));
        let charts = if sides > 4 { sides } else { 1 };
        let at = |q: usize, a: f64, b: f64| -> (DVec2, DVec3) {
            let uv = match &dom {
                Some(d) => ngon_chart(d, q, a, b),
                None => DVec2::new(a, b),
            };
            (uv, net.patch_point(k, uv.x, uv.y))
        };
        let mut here: Option<(f64, usize, f64, f64)> = None;
        let consider = |q: usize, a: f64, b: f64, here: &mut Option<(f64, usize, f64, f64)>| {
            let (_, p) = at(q, a, b);
            let d = p.distance(tip);
            if d.is_finite() && here.is_none_or(|h| d < h.0) {
                *here = Some((d, q, a, b));
            }
        };
        let n = PATCH_SAMPLES;
        for q in 0..charts {
            for i in 0..=n {
                for j in 0..=n {
                    consider(q, i as f64 / n as f64, j as f64 / n as f64, &mut here);
                }
            }
        }
        let mut width = 1.0 / n as f64;
        for _ in 0..2 {
            let Some((_, q, a0, b0)) = here else { break };
            for i in -2..=2 {
                for j in -2..=2 {
                    let a = (a0 + i as f64 * width / 2.0).clamp(0.0, 1.0);
                    let b = (b0 + j as f64 * width / 2.0).clamp(0.0, 1.0);
                    consider(q, a, b, &mut here);
                }
            }
            width /= 4.0;
        }
        let Some((d, q, a, b)) = here else { continue };
        if best.is_none_or(|b| d < b.distance) {
            let (uv, point) = at(q, a, b);
            best = Some(PatchPoint {
                patch: k,
                u: uv.x.clamp(0.0, 1.0),
                v: uv.y.clamp(0.0, 1.0),
                point,
                distance: d,
            });
        }
    }
    best
}

/// The loop of `loops` whose corners' centroid is nearest to `tip` (ties
/// go to the earlier loop): the loop a pointer picks to fill.
pub fn nearest_loop<'a>(
    net: &CurveNetwork,
    loops: &'a [Vec<Piece>],
    tip: DVec3,
) -> Option<&'a Vec<Piece>> {
    let centroid = |l: &Vec<Piece>| {
        l.iter().map(|p| net.node_point(p.from)).sum::<DVec3>() / l.len().max(1) as f64
    };
    loops
        .iter()
        .filter(|l| !l.is_empty())
        .map(|l| (centroid(l).distance(tip), l))
        .filter(|(d, _)| d.is_finite())
        .fold(
            None,
            |best: Option<(f64, &Vec<Piece>)>, (d, l)| match best {
                Some((bd, _)) if bd <= d => best,
                _ => Some((d, l)),
            },
        )
        .map(|(_, l)| l)
}
