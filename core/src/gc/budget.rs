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
//! The profiles are summed into the skin's cost as they are fitted
//! ([`Cost::add`]), so a GC whose first profiles already ask for too much
//! is refused before the rest are fitted (64 sections of distinct
//! 4,096-point loops were fitted for 17 s before the refusal).
//!
//! ## Time
//!
//! Those limits bound one GC; an assembly's union grows with every part,
//! and an edit re-unites the nodes of the union tree over the parts it
//! changed ([`crate::mesh::union_tree_nodes`]). A child
//! added to a container at 724 × 724 (2 M triangles, accepted) took 10 s;
//! the chair's nine parts at 256 × 256, 11 s (issue 37: no accepted op may
//! run longer than 10 s). So every GC op is also estimated in seconds
//! before it is evaluated ([`edit_seconds`], from the parameters alone:
//! each part's triangles from its grid) and refused past [`MAX_SECONDS`]
//! with [`GcError::OverBudget`]. The estimate follows what
//! [`crate::assembly::union_mesh_cached`] does when the document's last
//! evaluation is cached (as it is in a session, a replay and a load,
//! which replays the history op by op):
//!
//! ```text
//! seconds = MESH·(triangles meshed: changed parts and their cavities)
//!         + DIFFERENCE·Σ_{re-trimmed parts} (part + the cavities that may cut it)
//!         + IMPORT·Σ_{re-imported parts} part
//!         + UNION·Σ_{tree nodes united again} (the parts under the node)
//!         + RESULT·(the result's triangles)
//! ```
//!
//! A part is re-trimmed and re-imported when it changed, and a node is
//! united again when a part under it was re-trimmed or the tree before
//! the op (over the parts before it) had no such node. (The union imports
//! a changed part's whole group again, the other members from their kept
//! trims: a chair leg's edit imports six parts. The estimate charges the
//! changed part's import and the union of every node over it, which is
//! at least the group's import: the root spans every part, at the same
//! seconds per triangle.) The seconds are
//! CPU seconds: the two halves of a node are united at once, so on two
//! cores the wall time can be less. The union imports parts whose boxes
//! are disjoint together, without a boolean
//! ([`crate::mesh::disjoint_groups`]);
//! the boxes are not known before meshing, so the estimate is the tree's
//! over single parts. When a part is added or removed, the nodes over
//! part 0 are counted as well: the part may join or leave the first
//! group, and the grouped tree then re-unites that group's path to the
//! root. An edit that moves a part into or out of a group re-unites the
//! path of every group it changes, which can be more booleans than the
//! one path the estimate counts (up to the tree's depth, each nearly the
//! whole union): a gap the calibration's margin (below) covers on the
//! examples but does not bound.
//!
//! A changed hollow part may cut any other part, so its edit re-trims
//! and re-unites them all; any hollow part is assumed to cut every other
//! (the bounding boxes that decide it are not known before meshing). The
//! constants are CPU seconds of the release build on this machine (AMD
//! EPYC, 2 cores), from `calibrate` in `core/tests/timed/gc_time.rs`, rounded
//! up. With the grouped union tree (2026-11-30) the estimate is 1.5-3.9
//! times the measured CPU time of every edit over 0.3 s on the mug, the
//! teapot, the chair and the rack at 128 to 724 segments (a boolean the
//! groups save is still counted). That test runs an edit at the limit and
//! checks it finishes within it.
//!
//! The estimate counts on the cache holding the tree that the state
//! before the op was evaluated with ([`crate::assembly::UnionCache`]
//! keeps the last evaluation whatever its size). After an undo to a
//! checkpoint, which restores a state without evaluating it, an edit of
//! an assembly whose tree is over the cache's budget (about half a
//! million triangles) may find it gone and unite every part: up to the
//! whole union's time, which this estimate does not bound. The tree
//! (issue 37) keeps that bounded for long assemblies: the left fold it
//! replaced (Manifold's batch union) cost the square of the parts, about
//! 8 s for thirty default-resolution parts; the tree costs `n log n`.
//!
//! Each resolution axis stays declared as 4..=4096 in the op schema (a
//! long cable wants many rings and few points around); the product is what
//! the grid limit checks, with [`GcError::OverBudget`] naming the
//! parameter, the estimate and the limit. [`crate::gc::Gc::validate`] runs
//! these checks, so every op that builds or edits a GC (and every GC read
//! from a USD file, a trace or a shared session) is held to them.

use crate::mesh::union_tree_nodes;
use crate::nurbs::NurbsCurve;

use super::{Gc, GcAssembly, GcError, Resolution, ShapeType};
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

/// The skin work and mesh grid of one GC, summed profile by profile.
#[derive(Clone, Debug)]
pub struct Cost {
    sections: usize,
    res: Resolution,
    knots: Vec<f64>,
    degree: usize,
}

impl Cost {
    /// The cost of a GC of `sections` key sections at `res`, before any
    /// profile is added (checks the section count).
    pub fn new(sections: usize, res: Resolution) -> Result<Self, GcError> {
        check_sections(sections)?;
        Ok(Self {
            sections,
            res,
            knots: Vec::new(),
            degree: 1,
        })
    }

    /// Adds one section's (local) profile curve; refuses as soon as the
    /// profiles added so far ask for more skinning work than the limit.
    pub fn add(&mut self, profile: &NurbsCurve) -> Result<(), GcError> {
        self.knots.extend(profile.knots.iter().copied());
        self.knots.sort_by(f64::total_cmp);
        self.knots.dedup();
        self.degree = self.degree.max(profile.degree);
        let columns = self.knots.len() as f64 * (self.degree + 1) as f64;
        let kk = (self.sections + 2) as f64;
        let flops = columns * kk * kk * kk / 3.0;
        if flops.is_nan() || flops > MAX_SKIN_FLOPS {
            return Err(over(
                "sections",
                "the skinning work (control columns × (sections + 2)³ / 3 flops)",
                flops,
                MAX_SKIN_FLOPS,
            ));
        }
        Ok(())
    }

    /// Checks the mesh grid once every profile is added, and gives the
    /// grid points of one wall.
    pub fn finish(&self) -> Result<f64, GcError> {
        let rings = f64::from(self.res.v) + self.sections as f64 + 1.0;
        let around = f64::from(self.res.u) + self.knots.len() as f64;
        let points = rings * around;
        if points.is_nan() || points > MAX_GRID_POINTS {
            return Err(over(
                "resolution",
                "the mesh grid points ((resolution.v + sections) × (resolution.u + profile knots))",
                points,
                MAX_GRID_POINTS,
            ));
        }
        Ok(points)
    }
}

pub use crate::budget::MAX_SECONDS;
/// Seconds per triangle of a part or cavity meshed.
pub const MESH_SECONDS: f64 = 0.2e-6;
/// Seconds per triangle of a part trimmed and of the cavities cutting it
/// (both imported, one difference).
pub const DIFFERENCE_SECONDS: f64 = 3.0e-6;
/// Seconds per triangle of a part imported as a union operand.
pub const IMPORT_SECONDS: f64 = 2.0e-6;
/// Seconds per triangle of each operand of one union step.
pub const UNION_SECONDS: f64 = 2.0e-6;
/// Seconds per triangle of the result (export from Manifold, sliver
/// check, placement, the document's hash and fold check).
pub const RESULT_SECONDS: f64 = 0.15e-6;

/// One part's estimated triangles: its walls' and, for a hollow part,
/// its cavity's (two per grid point; a shell or container has two walls,
/// its cavity the inner one).
fn triangles(gc: &Gc) -> Result<(f64, f64), GcError> {
    let mut cost = Cost::new(gc.sections.len(), gc.resolution)?;
    for s in &gc.sections {
        cost.add(&s.profile.curve()?)?;
    }
    let wall = 2.0 * cost.finish()?;
    Ok(match gc.shape {
        ShapeType::Solid => (wall, 0.0),
        ShapeType::Shell { .. } | ShapeType::Container { .. } => (2.0 * wall, wall),
    })
}

/// The seconds `after`'s evaluation is estimated to take on this machine
/// when `before` (the assembly the op edited; `None` for a new one) was
/// evaluated last (see the module doc).
pub fn edit_seconds(before: Option<&GcAssembly>, after: &GcAssembly) -> Result<f64, GcError> {
    let sizes: Vec<(f64, f64)> = after
        .parts
        .iter()
        .map(|p| triangles(&p.gc))
        .collect::<Result<_, _>>()?;
    let changed: Vec<bool> = (0..after.parts.len())
        .map(|i| before.and_then(|b| b.parts.get(i)).map(|p| &p.gc) != Some(&after.parts[i].gc))
        .collect();
    let hollow = |i: usize| sizes[i].1 > 0.0;
    let total: f64 = sizes.iter().map(|s| s.0).sum();
    let mut seconds = RESULT_SECONDS * total;
    for (i, &(t, c)) in sizes.iter().enumerate() {
        if changed[i] {
            seconds += MESH_SECONDS * (t + c);
        }
    }
    if after.parts.len() < 2 {
        return Ok(seconds);
    }
    // The parts whose trimmed mesh may differ: a changed hollow part
    // re-trims every part; a one-part assembly before cached no union.
    let was_hollow = |i: usize| {
        before
            .and_then(|b| b.parts.get(i))
            .is_some_and(|p| !matches!(p.gc.shape, ShapeType::Solid))
    };
    let any_hollow_changed = (0..sizes.len()).any(|i| changed[i] && (hollow(i) || was_hollow(i)))
        || before.is_some_and(|b| (sizes.len()..b.parts.len()).any(was_hollow));
    let before_nodes: std::collections::HashSet<(usize, usize)> = match before {
        Some(b) if b.parts.len() >= 2 => union_tree_nodes(b.parts.len()).into_iter().collect(),
        _ => Default::default(),
    };
    let retrimmed = |i: usize| changed[i] || any_hollow_changed || before_nodes.is_empty();
    let cavities: f64 = sizes.iter().map(|s| s.1).sum();
    for (i, &(t, c)) in sizes.iter().enumerate() {
        let cutting = cavities - c;
        if retrimmed(i) && cutting > 0.0 {
            seconds += DIFFERENCE_SECONDS * (t + cutting);
        }
    }
    // The union tree's nodes that are not found whole: those over a
    // re-trimmed part, and those the tree before did not have.
    let mut under = vec![0.0; sizes.len() + 1];
    for (i, s) in sizes.iter().enumerate() {
        under[i + 1] = under[i] + s.0;
    }
    // A part added or removed may join or leave the first group: the
    // nodes over part 0 (the tree's left spine) are counted too.
    let regroup = before.is_some_and(|b| b.parts.len() != sizes.len());
    for (lo, hi) in union_tree_nodes(sizes.len()) {
        let kept = before_nodes.contains(&(lo, hi)) && !(lo..hi).any(retrimmed);
        if kept && !(regroup && lo == 0) {
            continue;
        }
        seconds += if hi - lo == 1 {
            IMPORT_SECONDS * sizes[lo].0
        } else {
            UNION_SECONDS * (under[hi] - under[lo])
        };
    }
    Ok(seconds)
}

/// [`GcError::OverBudget`] when [`edit_seconds`] is over [`MAX_SECONDS`].
pub fn check_edit(before: Option<&GcAssembly>, after: &GcAssembly) -> Result<(), GcError> {
    let seconds = edit_seconds(before, after)?;
    if !(seconds <= MAX_SECONDS) {
        return Err(over(
            "parts",
            "the seconds to mesh and unite the parts this op changes, on this machine (lower their resolution or split the assembly)",
            seconds,
            MAX_SECONDS,
        ));
    }
    Ok(())
}
