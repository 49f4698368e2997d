//! Limits on the memory, work and time one sculpt op may ask for (issue
//! 22: nothing a user or a file sends may abort the host; issues 33 and
//! 37: no accepted sculpt op runs longer than [`MAX_SECONDS`] on this
//! machine, and a refusal comes at once, before the work).
//!
//! ## Size
//!
//! A frame refines the surface its brush reaches, and the band a warp
//! stretches, to edges of at most `max_len` (paper §5.3). Before any frame
//! runs, each frame's triangles are estimated from the parameters alone:
//!
//! - the reach: a ball of radius `R` (brush bound radius × pose scale +
//!   influence, model units). A surface that bounds a convex region inside
//!   the ball has at most the ball's area `4πR²`;
//! - the stretch: a warp that moves the reached region by `D` (drag: the
//!   sample-to-sample distance plus the rotation angle × `R`; explode:
//!   `h · |delta| · pressure`; whittle only contracts: 0) drags a band of
//!   about `2πR · D` behind it, and the slivers of the band refine like an
//!   area of `4πD²` (what an explode to radius `D` makes; measured on the
//!   issue 22 drag stroke of a unit sphere, `R` = 1.4, `max_len` = 0.07: a
//!   last sample 1, 3, 10 m away made 31 k, 100 k and 966 k triangles, and
//!   this estimate gives 57 k, 166 k and 1.3 M);
//! - bisected triangles with longest edge at most `max_len` average about
//!   half an equilateral triangle of that edge, `√3/8 · max_len²`.
//!
//! One frame's estimate above [`MAX_FRAME_TRIANGLES`] (1 M, about 150 MB of
//! half-edge mesh, grid and marks) is refused with
//! [`SculptError::OverBudget`], naming `max_edge_rel` when the reach
//! dominates and the sample (`samples[i].position`, or `warp.delta`) when
//! the stretch does. `max_edge_rel` 1e-4 asked for about 1e10 triangles in
//! one frame; the declared minimum of `max_edge_rel` in the op schema is
//! [`MIN_MAX_EDGE_REL`].
//!
//! ## Time
//!
//! The size limits alone let a 600-sample stroke of 800 k-triangle frames
//! through, which ran 368 s before the face limit stopped it (issue 37).
//! So every sculpt op is also estimated in seconds before it runs
//! ([`StrokeCost`], [`CreateCost`]) and refused with
//! [`SculptError::TooSlow`] past [`MAX_SECONDS`]. A stroke costs
//!
//! ```text
//! seconds = FACE·faces + GRID·samples + UNIT·Σ_frames units + FRAME·frames
//! ```
//!
//! - `faces`: the mesh the op copies, indexes, checks and hands back (and
//!   the document hashes);
//! - `samples`: the distance grid a mesh brush is sampled on;
//! - `units` of a frame: the vertices it looks at plus the triangles it
//!   refines. The vertices are those of the cells its reach meets: counted
//!   in the mesh as it is (the sculptor's vertex grid, [`VertexGrid::count_ball`]),
//!   so a reach over a part already finer than this stroke's edges is
//!   counted as it is, or the refined surface's (`1.5 ×` the reach's area
//!   over two triangles, the cells' share outside the ball), whichever is
//!   more; the triangles are the size estimate above.
//!
//! The constants are measured on this machine (AMD EPYC, 2 cores; the
//! release build, CPU seconds of both threads: an upper bound of the wall
//! time on an idle machine) by the calibration in `core/tests/timed/sculpt_time.rs`,
//! which also runs each op kind at the limit and compares.
//!
//! The estimate assumes the reached surface is not crumpled; a backstop
//! holds it to its word: the stroke counts the work it does (the vertices
//! its frames look at and the triangles they add, [`DONE_UNITS`] each, and
//! the triangles the crossing guard searches, [`GUARD_UNITS`] each: on a
//! surface crumpled under the brush that search is most of the time), and
//! once the count reaches what the time left after the fixed costs
//! allows, it stops with [`SculptError::TooSlow`]. Measured 2026-11-29:
//! drags that ran 7.6-20 s CPU before the guard was counted now stop at
//! 6.9-10.6 s CPU (4.5-6.5 s wall), with the document as it was.
//! The face limit backs the size the same way:
//! refinement stops once the stroke has added [`MAX_STROKE_NEW_TRIANGLES`]
//! faces or the mesh has [`MAX_TRIANGLES`], and the stroke fails with
//! [`SculptError::OverBudget`] naming the count where it stopped. Both
//! count, so replays fail the same way on any machine and thread count;
//! the op works on a copy, so the document is left as it was.

use std::f64::consts::PI;

use glam::DVec3;

use super::brush::{BrushExtent, BrushPose};
use super::grid::VertexGrid;
use super::stroke::StrokeSettings;
use super::warp::Warp;
use super::SculptError;

/// Smallest `max_edge_rel` a stroke may ask for (declared in the schema).
pub const MIN_MAX_EDGE_REL: f64 = 1e-3;
/// Most triangles one frame may be estimated to refine.
pub const MAX_FRAME_TRIANGLES: f64 = 1e6;
/// Most faces a sculpt mesh may reach during a stroke (the hard limit).
pub const MAX_TRIANGLES: usize = 12_000_000;
/// Most faces one stroke may add (the hard limit).
pub const MAX_STROKE_NEW_TRIANGLES: usize = 4_000_000;

pub use crate::budget::MAX_SECONDS;
/// Seconds per face of the mesh a stroke works on (copy, vertex grid,
/// triangle mesh out, the document's hash of it).
pub const FACE_SECONDS: f64 = 0.6e-6;
/// Seconds per sample of a mesh brush's distance grid.
pub const GRID_SECONDS: f64 = 1.5e-6;
/// Seconds per unit of frame work (a vertex looked at, a triangle
/// refined).
pub const UNIT_SECONDS: f64 = 0.35e-6;
/// Units of estimated work one unit the backstop counts (a vertex a
/// frame looked at, or half an edge split) stands for: the estimate
/// over-counts the vertices a frame looks at, the count does not, so a
/// counted unit costs more (0.46-0.79 µs CPU measured, 2026-11-29).
pub const DONE_UNITS: f64 = 2.0;
/// Units of estimated work per triangle the crossing guard searches. It
/// builds a bounding-volume tree over the triangles near the frame's
/// moves and tests the pairs that overlap, in frames the fold guard
/// pulled back: a surface crumpled under the brush costs this every
/// frame, which the estimate from the parameters cannot see, so the
/// backstop counts it (2.3-4.5 µs CPU per triangle measured by
/// `calibrate`, 2026-11-29: a drag estimated at 2.9 s ran 7.6 s, one
/// estimated at 7.7 s ran 17.4 s).
pub const GUARD_UNITS: f64 = 11.0;
/// Seconds per frame, whatever it reaches.
pub const FRAME_SECONDS: f64 = 20e-6;
/// Seconds per vertex of a base mesh `sculpt_create` builds (mesh,
/// half-edge structure and its checks, the document's mesh and hash).
pub const CREATE_VERTEX_SECONDS: f64 = 4.8e-6;
/// The cells a reach meets hold about this many times the vertices of the
/// ball (the ball's share of the cube of cells around it is π/6, the
/// cells that the sphere crosses bring part of it back).
const CELL_FILL: f64 = 1.5;

/// The face count past which a stroke starting with `faces` stops.
pub fn face_limit(faces: usize) -> usize {
    MAX_TRIANGLES.min(faces.saturating_add(MAX_STROKE_NEW_TRIANGLES))
}

/// Area of the average refined triangle at edge `max_len`: half an
/// equilateral triangle.
fn triangle_area(max_len: f64) -> f64 {
    3f64.sqrt() / 8.0 * max_len * max_len
}

fn over(field: String, what: &'static str, estimate: f64, limit: f64) -> SculptError {
    crate::budget::OverBudget::new(field, what, estimate, limit).into()
}

/// What a stroke is estimated to cost before it runs (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StrokeCost {
    /// Faces of the mesh the stroke works on.
    pub faces: f64,
    /// Samples of the mesh brush's distance grid (0 for other brushes).
    pub grid_samples: f64,
    /// Units of frame work, summed over every path's frames.
    pub units: f64,
    /// Frames, summed over every path.
    pub frames: f64,
    /// The triangles the frames refine, summed (part of `units`).
    pub triangles: f64,
    /// The path and frame with the most units: the sample to name.
    pub heaviest: (usize, usize),
}

impl StrokeCost {
    /// The seconds the stroke is estimated to take on this machine.
    pub fn seconds(&self) -> f64 {
        self.fixed_seconds() + UNIT_SECONDS * self.units + FRAME_SECONDS * self.frames
    }

    /// The part that does not depend on the frames.
    pub fn fixed_seconds(&self) -> f64 {
        FACE_SECONDS * self.faces + GRID_SECONDS * self.grid_samples
    }

    /// The units of frame work the stroke may do before the backstop
    /// stops it: what the time left after the fixed costs allows.
    pub fn unit_limit(&self) -> f64 {
        ((MAX_SECONDS - self.fixed_seconds() - FRAME_SECONDS * self.frames) / UNIT_SECONDS).max(0.0)
    }

    /// [`SculptError::TooSlow`] when the estimate is over [`MAX_SECONDS`],
    /// naming what dominates: the samples (`samples`, the frames), the
    /// mesh brush (`settings.brush.step`) or the mesh (`id`).
    pub fn check(&self) -> Result<(), SculptError> {
        let seconds = self.seconds();
        if seconds.is_finite() && seconds <= MAX_SECONDS {
            return Ok(());
        }
        let terms = [
            (
                UNIT_SECONDS * self.units + FRAME_SECONDS * self.frames,
                "samples",
            ),
            (GRID_SECONDS * self.grid_samples, "settings.brush.step"),
            (FACE_SECONDS * self.faces, "id"),
        ];
        let field = terms
            .iter()
            .fold(terms[0], |a, b| if b.0 > a.0 { *b } else { a })
            .1;
        let field = if field == "samples" && self.frames <= 2.0 {
            "settings.max_edge_rel".to_string()
        } else {
            field.to_string()
        };
        Err(SculptError::TooSlow {
            field,
            what: "the stroke",
            seconds,
            limit: MAX_SECONDS,
            detail: format!(
                "{:.0} frames looking at or refining {:.3e} vertices and triangles, a mesh of {:.0} triangles, a brush grid of {:.0} samples",
                self.frames, self.units, self.faces, self.grid_samples
            ),
        })
    }
}

/// What `sculpt_create` is estimated to cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CreateCost {
    /// Vertices of the base mesh.
    pub vertices: f64,
}

impl CreateCost {
    /// The seconds the op is estimated to take on this machine.
    pub fn seconds(&self) -> f64 {
        CREATE_VERTEX_SECONDS * self.vertices
    }

    /// [`SculptError::TooSlow`] past [`MAX_SECONDS`], naming `field`.
    pub fn check(&self, field: &str) -> Result<(), SculptError> {
        let seconds = self.seconds();
        if seconds.is_finite() && seconds <= MAX_SECONDS {
            return Ok(());
        }
        Err(SculptError::TooSlow {
            field: field.to_string(),
            what: "the base mesh",
            seconds,
            limit: MAX_SECONDS,
            detail: format!("{:.0} vertices", self.vertices),
        })
    }
}

/// Checks a stroke's frames (model-space `poses` with pressures, model
/// scale `scale`, `settings` with the brush already resolved) against the
/// frame size budget and the time budget before anything is refined (see
/// the module doc). Without the mesh, the time counts the frames only.
pub fn check_stroke(
    settings: &StrokeSettings,
    scale: f64,
    poses: &[(BrushPose, f64)],
) -> Result<(), SculptError> {
    check_strokes(settings, scale, &[poses])
}

/// [`check_stroke`] for brushes moving together (a stroke and its mirror
/// image).
pub fn check_strokes(
    settings: &StrokeSettings,
    scale: f64,
    paths: &[&[(BrushPose, f64)]],
) -> Result<(), SculptError> {
    estimate_strokes(settings, settings.brush.extent(), scale, paths, None)?.check()
}

/// The cost of brushes moving together along `paths` (a stroke and its
/// mirror image), with the density of the mesh as it is from `grid`
/// when given; an error when one frame is over the frame budget. The
/// caller adds the mesh's faces and the brush grid's samples.
pub fn estimate_strokes(
    settings: &StrokeSettings,
    extent: BrushExtent,
    scale: f64,
    paths: &[&[(BrushPose, f64)]],
    grid: Option<&VertexGrid>,
) -> Result<StrokeCost, SculptError> {
    let mut cost = StrokeCost::default();
    let mut heaviest = 0.0;
    for (k, poses) in paths.iter().enumerate() {
        path_cost(
            settings,
            extent,
            scale,
            poses,
            grid,
            k,
            &mut cost,
            &mut heaviest,
        )?;
    }
    Ok(cost)
}

/// Adds path `k`'s frames to `cost`; an error when one frame is over the
/// frame budget.
#[allow(clippy::too_many_arguments)]
fn path_cost(
    settings: &StrokeSettings,
    extent: BrushExtent,
    scale: f64,
    poses: &[(BrushPose, f64)],
    grid: Option<&VertexGrid>,
    k: usize,
    cost: &mut StrokeCost,
    heaviest: &mut f64,
) -> Result<(), SculptError> {
    let size = extent.size * settings.brush_scale / scale;
    let max_len = settings.max_edge_rel * size;
    let h = settings.influence / scale;
    let tri = triangle_area(max_len);
    let bound = extent.bound;
    let mut prev: Option<&BrushPose> = None;
    // The mesh's own count, re-read only when the reach moved by a
    // quarter of itself (dense samples of a slow stroke share it).
    let mut counted: Option<(DVec3, f64, f64)> = None;
    for (i, (pose, pressure)) in poses.iter().enumerate() {
        let from = prev.unwrap_or(pose);
        prev = Some(pose);
        let eval = if settings.warp == Warp::Drag {
            from
        } else {
            pose
        };
        let reach = bound * eval.scale + h;
        let stretch = match settings.warp {
            Warp::Drag => {
                let turn = (pose.rotation * from.rotation.inverse())
                    .normalize()
                    .to_axis_angle()
                    .1
                    .abs();
                (pose.position - from.position).length() + turn * reach
            }
            Warp::Explode { delta } => h * delta.abs() * pressure,
            Warp::Whittle => 0.0,
        };
        let reached = 4.0 * PI * reach * reach / tri;
        let stretched = (2.0 * PI * reach * stretch + 4.0 * PI * stretch * stretch) / tri;
        let frame = reached + stretched;
        if frame.is_nan() || frame > MAX_FRAME_TRIANGLES {
            let field = if reached.is_nan() || reached > MAX_FRAME_TRIANGLES / 2.0 {
                "max_edge_rel".to_string()
            } else if matches!(settings.warp, Warp::Explode { .. }) {
                "warp.delta".to_string()
            } else {
                format!("samples[{i}].position")
            };
            return Err(over(
                field,
                "the triangles one frame refines (reach and stretched band / max edge²)",
                frame,
                MAX_FRAME_TRIANGLES,
            ));
        }
        let existing = match grid {
            Some(g) => {
                let c = eval.position;
                match counted {
                    Some((at, r, n)) if at.distance(c) <= 0.25 * r && r == reach => n,
                    _ => {
                        let n = g.count_ball(c, reach) as f64;
                        counted = Some((c, reach, n));
                        n
                    }
                }
            }
            None => 0.0,
        };
        let units = existing.max(CELL_FILL * reached / 2.0) + frame;
        if units > *heaviest {
            *heaviest = units;
            cost.heaviest = (k, i);
        }
        cost.units += units;
        cost.triangles += frame;
        cost.frames += 1.0;
    }
    Ok(())
}

/// The units of work a frame did, as the backstop counts them (see
/// [`DONE_UNITS`], [`GUARD_UNITS`]).
pub fn frame_units(s: &super::sculptor::FrameStats) -> f64 {
    DONE_UNITS * (s.visited + 2 * s.splits) as f64 + GUARD_UNITS * s.guard_faces as f64
}

/// The error of a stroke stopped by the hard face limit: the mesh had
/// `faces` (more than `limit`) where it stopped.
pub fn too_many_faces(faces: usize, limit: usize) -> SculptError {
    over(
        "settings.max_edge_rel".into(),
        "the sculpt mesh's triangles where the stroke stopped refining",
        faces as f64,
        limit as f64,
    )
}

/// The error of a stroke stopped by the backstop: it had done `units` of
/// frame work, the time `cost` allowed `limit`.
pub fn too_much_work(cost: &StrokeCost, units: f64, frames: usize) -> SculptError {
    SculptError::TooSlow {
        field: "samples".into(),
        what: "the stroke (stopped by the work it did, more than estimated)",
        seconds: cost.fixed_seconds() + UNIT_SECONDS * units + FRAME_SECONDS * frames as f64,
        limit: MAX_SECONDS,
        detail: format!(
            "after {frames} frames it had looked at or refined {units:.3e} vertices and triangles, of {:.3e} estimated for all {:.0}",
            cost.units, cost.frames
        ),
    }
}
