//! Budgets of the SDF ops (issues 22 and 37): before an op resamples,
//! fuses, extracts or builds a component's SDF, it counts the work it is
//! about to do and the memory the volume will hold afterwards, estimates
//! from them the time it will take on this machine, and is refused at
//! once when either is over its limit: [`SdfError::OverBudget`] or
//! [`SdfError::TooSlow`], each stating the estimate and the limit. (A
//! chain of copies of a fused result, each doubling it, used to be refused
//! only after 47 s of work, when the grid was already over its memory.)
//!
//! **What is counted** ([`Work`]):
//! - the bricks of each operand's box, each classified near or far by a
//!   few lookups (resampling's far test);
//! - the bricks near each operand's surface, sampled densely, folded and
//!   extracted: the surface's area over a brick's face times
//!   [`BRICKS_PER_FACE_AREA`] (the band makes the bricks beside the
//!   surface dense too); the area is exact for meshes (library and user
//!   components, fused results) and the area of the box for analytic
//!   solids (a bound for the convex ones, near it for the torus);
//! - exact distance queries against a mesh and its triangles, for the
//!   SDF of a component made from an object or a result
//!   ([`super::mesh_sdf::component_sdf_at`]).
//!
//! **The time per unit** was measured on this machine (AMD EPYC, one
//! thread of two, `cargo run --release --example sdf_bench` and
//! `sdf::tests::budget`), with a margin, and checked by the tests against
//! measured runs: estimates must not be below the time measured near the
//! limit, nor far above it.

use super::SdfError;
use crate::budget::OverBudget;

/// No accepted SDF op should run longer than this on this machine
/// (issue 37).
pub const TIME_LIMIT_SECONDS: f64 = crate::budget::MAX_SECONDS;
/// Memory budget of a volume's dense bricks.
pub const MEMORY_BUDGET_BYTES: usize = 1 << 30;
/// Bytes of one dense brick.
pub const BRICK_BYTES: f64 = 512.0 * 4.0;
/// Dense bricks per brick face (`(8 step)²`) of surface area.
pub const BRICKS_PER_FACE_AREA: f64 = 2.5;

/// Seconds to classify one brick of an operand's box.
const SECONDS_PER_REGION_BRICK: f64 = 0.4e-6;
/// Seconds to sample, fold and extract one brick near a surface.
const SECONDS_PER_SURFACE_BRICK: f64 = 40e-6;
/// Seconds per exact distance query against a mesh.
const SECONDS_PER_QUERY: f64 = 1.5e-6;
/// Seconds per triangle to check a mesh and build its distance index.
const SECONDS_PER_TRIANGLE: f64 = 2e-6;

/// The work of one SDF op, counted before it runs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    /// Bricks of operand boxes to classify.
    pub region_bricks: f64,
    /// Bricks near the surfaces to sample, fold and extract.
    pub surface_bricks: f64,
    /// Dense bricks the volume will hold afterwards.
    pub held_bricks: f64,
    /// Exact distance queries against meshes.
    pub mesh_queries: f64,
    /// Triangles of meshes to check and index.
    pub mesh_triangles: f64,
}

impl Work {
    /// The estimated time on this machine, in seconds.
    pub fn seconds(&self) -> f64 {
        self.region_bricks * SECONDS_PER_REGION_BRICK
            + self.surface_bricks * SECONDS_PER_SURFACE_BRICK
            + self.mesh_queries * SECONDS_PER_QUERY
            + self.mesh_triangles * SECONDS_PER_TRIANGLE
    }

    /// The estimated memory of the volume's dense bricks afterwards.
    pub fn held_bytes(&self) -> f64 {
        self.held_bricks * BRICK_BYTES
    }

    /// `self` and `other` together.
    pub fn plus(&self, o: &Work) -> Work {
        Work {
            region_bricks: self.region_bricks + o.region_bricks,
            surface_bricks: self.surface_bricks + o.surface_bricks,
            held_bricks: self.held_bricks + o.held_bricks,
            mesh_queries: self.mesh_queries + o.mesh_queries,
            mesh_triangles: self.mesh_triangles + o.mesh_triangles,
        }
    }

    /// `Ok` when the memory and the time are within their limits; else
    /// the refusal, naming `what` (the op's work) and both numbers. A NaN
    /// count (an operand of infinite size) is over every limit.
    pub fn check(&self, what: &str) -> Result<(), SdfError> {
        let bytes = self.held_bytes();
        if bytes.is_nan() || bytes > MEMORY_BUDGET_BYTES as f64 {
            return Err(SdfError::OverBudget(grid_memory(
                mib_ceil(bytes),
                (MEMORY_BUDGET_BYTES >> 20) as u64,
            )));
        }
        let seconds = self.seconds();
        if seconds.is_nan() || seconds > TIME_LIMIT_SECONDS {
            return Err(SdfError::TooSlow {
                what: what.to_owned(),
                seconds,
                limit: TIME_LIMIT_SECONDS,
            });
        }
        Ok(())
    }
}

/// The grid would need `needed_mib` MiB, over `budget_mib`: refused as
/// the `step`'s (a larger step, or the operand scaled down, needs less).
pub fn grid_memory(needed_mib: u64, budget_mib: u64) -> OverBudget {
    OverBudget::new(
        "step",
        "the grid's memory in MiB (use a larger step or scale the operand down)",
        needed_mib as f64,
        budget_mib as f64,
    )
}

/// `bytes` in MiB, rounded up (so a need over the budget never reads as
/// equal to it); saturating for NaN and infinity.
pub fn mib_ceil(bytes: f64) -> u64 {
    if bytes.is_nan() {
        u64::MAX
    } else {
        (bytes / (1u64 << 20) as f64).ceil() as u64
    }
}

/// Dense bricks near a surface of `area` (model units²) at grid `step`.
pub fn surface_bricks(area: f64, step: f64) -> f64 {
    let face = 8.0 * step * 8.0 * step;
    BRICKS_PER_FACE_AREA * area / face
}

/// Distance queries of [`super::mesh_sdf::mesh_to_sdf_banded`] on a grid
/// of `samples` samples at `step` around a surface of `area`, computing
/// exact values within `band`: one per far block of 4³ and one per sample
/// of the blocks near the surface.
pub fn banded_queries(samples: f64, area: f64, step: f64, band: f64) -> f64 {
    // Blocks whose centre is within their radius plus the band of the
    // surface: a shell that thick on both sides, plus a block.
    let radius = 1.5 * 3f64.sqrt() * step;
    let shell = 2.0 * (radius + band) + 4.0 * step;
    samples / 64.0 + (area * shell / (step * step * step)).min(samples)
}
