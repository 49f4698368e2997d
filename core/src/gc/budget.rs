//! Limits on the memory and work one generalized cylinder may ask for
//! (issue 22: nothing a user or a file sends may abort the host or run for
//! minutes).
//!
//! A GC's cost is fixed by its parameters before anything is allocated:
//!
//! - **key sections** `k`: the skin ([`crate::nurbs::skin`], natural cubic
//!   in `v`) solves a dense `(k + 2)²` system once per column of control
//!   points, `(k + 2)³ / 3` flops each. 20,000 sections asked for 3 GB and
//!   minutes, 1e6 for 8 TB. A drawn GC has a handful of key sections; 256
//!   is far beyond any we have seen and costs milliseconds per column.
//! - **skin work**: columns × `(k + 2)³ / 3`, where the columns are the
//!   control points of the compatible sections, at most
//!   `(distinct knots of all profiles) × (max degree + 1)` (knot union and
//!   degree elevation, §10.3). Limit [`MAX_SKIN_FLOPS`], about a second.
//! - **mesh grid**: rings × points per ring of the sampled side surface.
//!   The rings are at most `resolution.v + k` (every section parameter is a
//!   sample), the points at most `resolution.u + ` the distinct knots (every
//!   knot is a sample). A shell or container has two walls. Each grid point
//!   costs about 150 bytes through sampling, meshing, validation and the
//!   assembly's union; [`MAX_GRID_POINTS`] (1 Mi, about 2 M triangles a
//!   wall, far past what a printer resolves on a hand-sized part) keeps
//!   one GC under about 400 MB and its export under a minute. The accepted
//!   4096 × 4096 resolution (16.8 M points a wall) aborted with an
//!   allocation failure; a first limit of 4 Mi still let 2000 × 2000
//!   through, which took over 60 s and 4.9 GB to export (abuse sweep).
//!
//! Each resolution axis stays declared as 4..=4096 in the op schema (a
//! long cable wants many rings and few points around); the product is what
//! the grid limit checks, with [`GcError::OverBudget`] naming the
//! parameter, the estimate and the limit. [`crate::gc::Gc::validate`] runs
//! these checks, so every op that builds or edits a GC (and every GC read
//! from a USD file, a trace or a shared session) is held to them.

use crate::nurbs::NurbsCurve;

use super::{GcError, Resolution};
use crate::budget::OverBudget;

/// Most key sections one GC may have (see the module doc).
pub const MAX_SECTIONS: usize = 256;
/// Most flops the skin's `v` solves may take (about a second).
pub const MAX_SKIN_FLOPS: f64 = 2e9;
/// Most side-surface grid points one wall of a GC may have.
pub const MAX_GRID_POINTS: f64 = (1u64 << 20) as f64;

fn over(parameter: &'static str, what: &'static str, estimate: f64, limit: f64) -> GcError {
    OverBudget::new(parameter, what, estimate, limit).into()
}

/// Checks the section count alone (before any profile is built).
pub fn check_sections(count: usize) -> Result<(), GcError> {
    if count > MAX_SECTIONS {
        return Err(over(
            "sections",
            "the number of key sections",
            count as f64,
            MAX_SECTIONS as f64,
        ));
    }
    Ok(())
}

/// Checks the skin work and the mesh grid of a GC whose sections have
/// the (local) profile curves `profiles` at resolution `res`.
pub fn check_cost(profiles: &[NurbsCurve], res: Resolution) -> Result<(), GcError> {
    let k = profiles.len();
    check_sections(k)?;
    let mut knots: Vec<f64> = profiles
        .iter()
        .flat_map(|c| c.knots.iter().copied())
        .collect();
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    let degree = profiles.iter().map(|c| c.degree).max().unwrap_or(1);
    let distinct = knots.len() as f64;
    let columns = distinct * (degree + 1) as f64;
    let kk = (k + 2) as f64;
    let flops = columns * kk * kk * kk / 3.0;
    if flops.is_nan() || flops > MAX_SKIN_FLOPS {
        return Err(over(
            "sections",
            "the skinning work (control columns × (sections + 2)³ / 3 flops)",
            flops,
            MAX_SKIN_FLOPS,
        ));
    }
    let rings = f64::from(res.v) + k as f64 + 1.0;
    let around = f64::from(res.u) + distinct;
    let points = rings * around;
    if points.is_nan() || points > MAX_GRID_POINTS {
        return Err(over(
            "resolution",
            "the mesh grid points ((resolution.v + sections) × (resolution.u + profile knots))",
            points,
            MAX_GRID_POINTS,
        ));
    }
    Ok(())
}
