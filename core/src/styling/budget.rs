//! Limits on the memory and work a styling operation may ask for (issue
//! 22: nothing a user or a file sends may abort the host).
//!
//! Every styling input that sizes an allocation or a loop is checked
//! against a [`Budget`] before the work starts, and refused with
//! [`StylingError::OverBudget`] naming the parameter, the estimate and the
//! limit:
//!
//! - **extent**: every sample and pointer position within `max_extent` of
//!   the origin (model units, metres). Far samples are what made strokes
//!   ask for terabytes once resampled; a model this big is a unit error.
//! - **fit points**: the points a curve is fitted through (after arc-length
//!   resampling, estimated as `length / spacing + 1` before anything is
//!   allocated). Global interpolation and approximation (`core::nurbs`)
//!   solve dense systems, `8 n²` bytes and `n³ / 3` flops: 2,048 points is
//!   32 MiB and well under a second; a tracked stroke at 90 Hz is 900
//!   samples in 10 s.
//! - **tool work**: frames × unknowns of a held curve or surface tool (each
//!   frame is a sparse solve, linear in the unknowns).
//! - **tool time**: a held curve tool re-assembles the curve's energy and
//!   refactors it every frame, measured at 3.5-5.3 µs of CPU per frame and
//!   unknown in the release build on this machine (AMD EPYC, 2026-11-30:
//!   a 2,048-point curve's smoother held for 800 frames took 18.9 s, for
//!   8,000 frames 176 s; 500 points for 1,000 frames 5.3 s; 200 points
//!   for 3,518 frames 11.2 s; a still pointer is no cheaper). The tool-work limit alone let that 176 s
//!   through (issue 37: no accepted op may run longer than 10 s), so a
//!   held curve tool is also estimated in seconds
//!   ([`CURVE_TOOL_SECONDS`] per frame and unknown) and refused past
//!   [`MAX_SECONDS`]. A headset's curve of 100 points held for 10 s at
//!   90 Hz is 0.27 M frame-unknowns, estimated 1.6 s. (Where the time goes:
//!   47% adding the energy's outer products into the matrix, 11% basis
//!   derivatives: every frame re-assembles the energy over the whole
//!   curve, though the pointer's weight reaches only a window of it. A
//!   slot lookup by offset instead of binary search was tried and changed
//!   nothing. Assembling only the window the weight changes is issue 37's
//!   open work.) The surface tools cost far
//!   less per unit (a patch's 5,000 frames: 0.2 s) and keep the work
//!   limit.
//! - **loop search**: paths the automatic loop search may extend.
//!
//! The defaults are sized for a headset (a few hundred MiB and about a
//! second of work per op at most); [`Budget::default`] is what the ops
//! use until the document carries a configurable budget.

use serde::{Deserialize, Serialize};

use crate::math::DVec3;

use super::StylingError;

/// Limits on what one styling operation may ask for (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Budget {
    /// Largest distance of any sample or pointer position from the origin
    /// (model units).
    pub max_extent: f64,
    /// Most points one curve may be fitted through (after resampling).
    pub max_fit_points: usize,
    /// Most frames × unknowns one held tool application may solve.
    pub max_tool_work: u64,
    /// Most partial loops the automatic loop search may extend.
    pub max_loop_search: u64,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            max_extent: 1e4,
            max_fit_points: 2048,
            max_tool_work: 50_000_000,
            max_loop_search: 2_000_000,
        }
    }
}

pub use crate::budget::MAX_SECONDS;
/// CPU seconds per frame and unknown of a held curve tool (see the
/// module doc; measured 3.5-5.3 µs, with a margin).
pub const CURVE_TOOL_SECONDS: f64 = 6e-6;

fn over(parameter: &'static str, what: &'static str, estimate: f64, limit: f64) -> StylingError {
    crate::budget::OverBudget::new(parameter, what, estimate, limit).into()
}

impl Budget {
    /// Checks a held curve tool: its work ([`Self::check_tool_work`]) and
    /// its estimated seconds on this machine.
    pub fn check_curve_tool(
        &self,
        parameter: &'static str,
        frames: usize,
        unknowns: usize,
    ) -> Result<(), StylingError> {
        self.check_tool_work(parameter, frames, unknowns)?;
        let seconds = frames as f64 * unknowns as f64 * CURVE_TOOL_SECONDS;
        if !(seconds <= MAX_SECONDS) {
            return Err(over(
                parameter,
                "the seconds the held tool would take on this machine (frames × unknowns × CURVE_TOOL_SECONDS)",
                seconds,
                MAX_SECONDS,
            ));
        }
        Ok(())
    }

    /// Checks that every point lies within `max_extent` of the origin.
    pub fn check_extent(&self, parameter: &'static str, pts: &[DVec3]) -> Result<(), StylingError> {
        let far = pts.iter().map(|p| p.length()).fold(0.0, f64::max);
        if far.is_nan() || far > self.max_extent {
            return Err(over(
                parameter,
                "the farthest point's distance from the origin",
                far,
                self.max_extent,
            ));
        }
        Ok(())
    }

    /// Checks a count of points a curve would be fitted through.
    pub fn check_fit_points(
        &self,
        parameter: &'static str,
        estimate: f64,
    ) -> Result<(), StylingError> {
        if !(estimate <= self.max_fit_points as f64) {
            return Err(over(
                parameter,
                "the number of points to fit",
                estimate,
                self.max_fit_points as f64,
            ));
        }
        Ok(())
    }

    /// Checks the work of a held tool: `frames` solves of `unknowns`.
    pub fn check_tool_work(
        &self,
        parameter: &'static str,
        frames: usize,
        unknowns: usize,
    ) -> Result<(), StylingError> {
        let work = frames as f64 * unknowns as f64;
        if !(work <= self.max_tool_work as f64) {
            return Err(over(
                parameter,
                "frames × unknowns",
                work,
                self.max_tool_work as f64,
            ));
        }
        Ok(())
    }
}
