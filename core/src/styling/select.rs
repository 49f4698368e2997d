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

use serde::{Deserialize, Serialize};

use crate::math::DVec3;

use super::curve::SplineCurve;

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
        c.acos().to_degrees()
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
    net: &super::network::CurveNetwork,
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
