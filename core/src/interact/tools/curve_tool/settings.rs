//! [`CurveToolSettings`]: what the curve tool can be tuned by (tip offset,
//! thresholds, the smoother's, sharpener's and puller's parameters).

use crate::styling::curve::FitMode;
use crate::styling::surface::SurfaceWeights;
use crate::styling::tools::{PullParams, SharpenLimits, SmoothParams};
use crate::styling::AttractParams;

use crate::interact::input::Hand;

/// Settings of the curve tool. Lengths are metres in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveToolSettings {
    /// The hand holding the pen.
    pub dominant: Hand,
    /// Pen tip distance along the aim from the aim pose.
    pub tip_offset: f64,
    /// Length of the drawn ray.
    pub reach: f64,
    /// Seconds a stroke survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Smallest spacing of drawn samples (closer ones are skipped).
    pub min_spacing: f64,
    /// How drawn samples become a curve.
    pub fit: FitMode,
    /// Arc-length resampling of drawn samples before fitting.
    pub resample: Option<f64>,
    /// Closest approach under which a new curve joins an existing one.
    pub snap_tol: f64,
    /// Mesh samples per patch side of a new network.
    pub resolution: u32,
    /// Surface-tool control points per patch side of a new network.
    pub surface_n: u32,
    /// Smoother weights.
    pub smooth: SmoothParams,
    /// Sharpener weights.
    pub sharpen: SmoothParams,
    /// Where the sharpener stops.
    pub sharpen_limits: SharpenLimits,
    /// Puller weights.
    pub pull: PullParams,
    /// Attractor weights (`curve_attract`).
    pub attract: AttractParams,
    /// Surface tools' internal energy weights.
    pub surface: SurfaceWeights,
    /// Surface smoother's factor on `w_q` per frame, in (0, 1).
    pub surface_smooth_f: f64,
    /// Surface sharpener's factor on `w_q` per frame, in (1, 2], and its cap.
    pub surface_sharpen: (f64, f64),
    /// How far from the pen tip the surface smoother and sharpener act
    /// (the gaussian radius of their weight on the patch), metres in the
    /// model.
    pub surface_radius: f64,
    /// The most the surface smoother and sharpener move any point of the
    /// patch in one frame (metres in the model): 1 s held changes a
    /// patch by at most this times the frame rate.
    pub surface_max_step: f64,
    /// Surface puller's attractor weight.
    pub surface_wpp: f64,
}

impl Default for CurveToolSettings {
    fn default() -> Self {
        Self {
            dominant: Hand::Right,
            tip_offset: 0.0,
            reach: 5.0,
            grace: 0.25,
            min_spacing: 0.003,
            fit: FitMode::Approximate { tol: 0.001 },
            resample: Some(0.01),
            snap_tol: 0.02,
            resolution: 24,
            surface_n: 8,
            smooth: SmoothParams {
                wb: 1e-6,
                ws: 0.0,
                wp0: 1.0,
                wp1: 0.0,
                wp2: 0.0,
                alpha: 20.0,
            },
            sharpen: SmoothParams {
                wb: 2e-6,
                ws: 0.0,
                wp0: 1.0,
                wp1: 0.0,
                wp2: 3e-6,
                alpha: 30.0,
            },
            sharpen_limits: SharpenLimits {
                max_step: 0.004,
                max_growth: 4.0,
            },
            pull: PullParams {
                wpp: 200.0,
                wp0: 1.0,
                wp1: 0.001,
            },
            // 3% of the way per frame: about 2/3 of the way in a 0.5 s
            // hold at 72 Hz, so the user sees it move and can stop.
            attract: AttractParams {
                weight: 0.03,
                wp0: 1.0,
                wp1: 0.0,
                alpha: 20.0,
                keep_ends: false,
            },
            // The values of the styled fixtures (tests/data/lampshade.jsonl).
            surface: SurfaceWeights { wb: 1.0, ws: 0.0 },
            // Both act within about 5 cm of the pen and move the patch at
            // most 0.25 mm a frame: 1.8 cm in a held second at 72 Hz, 3 cm
            // at 120 Hz (issue 33: 1.2 per frame up to 4 times took a
            // 4.7 cm bump to 18.4 cm in one second, and stronger settings
            // made it overhang). Where the pen is, the smoother takes the
            // patch 0.95 of the way to its minimal shape in a second at
            // 72 Hz, the sharpener away from it by up to 3 times.
            surface_smooth_f: 0.96,
            surface_sharpen: (1.03, 3.0),
            surface_radius: 0.05,
            surface_max_step: 0.000_25,
            surface_wpp: 2000.0,
        }
    }
}
