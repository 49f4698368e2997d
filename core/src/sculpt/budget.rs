//! Limits on the memory and work one sculpt stroke may ask for (issue 22:
//! nothing a user or a file sends may abort the host or run for minutes).
//!
//! A frame refines the surface its brush reaches, and the band a warp
//! stretches, to edges of at most `max_len` (paper §5.3). Before any frame
//! runs, [`check_stroke`] estimates each frame's triangles from the
//! parameters alone:
//!
//! - the reach: a ball of radius `R` (brush bound radius × pose scale +
//!   influence, model units). A surface that bounds a convex region inside
//!   the ball has at most the ball's area `4πR²`;
//! - the stretch: a warp that moves the reached region by `D` (drag: the
//!   sample-to-sample distance plus the rotation angle × `R`; explode:
//!   `h · |delta| · pressure`; whittle only contracts: 0) drags a band of
//!   about `2πR · D` behind it, and the slivers of the band refine like an
//!   area of `4πD²` (what an explode to radius `D` makes; measured on the
//!   issue's drag stroke of a unit sphere, `R` = 1.4, `max_len` = 0.07: a
//!   last sample 1, 3, 10 m away made 31 k, 100 k and 966 k triangles, and
//!   this estimate gives 57 k, 166 k and 1.3 M);
//! - bisected triangles with longest edge at most `max_len` average about
//!   half an equilateral triangle of that edge, `√3/8 · max_len²`.
//!
//! One frame's estimate above [`MAX_FRAME_TRIANGLES`] (1 M, about 150 MB of
//! half-edge mesh, grid and marks, a few seconds of splitting) is refused
//! with [`SculptError::OverBudget`], naming `max_edge_rel` when the reach
//! dominates and the sample (`samples[i].position`, or `warp.delta`) when
//! the stretch does. The sum over frames (each frame visits what it
//! reaches) is held to [`MAX_STROKE_WORK`]. `max_edge_rel` 1e-4 asked for
//! about 1e10 triangles in one frame (GBs and minutes before this check);
//! the declared minimum of `max_edge_rel` in the op schema is
//! [`MIN_MAX_EDGE_REL`] (a frame of a brush whose influence equals its size
//! then estimates 1.2 M triangles).
//!
//! The estimate assumes the reached surface is not crumpled; a hard limit
//! backs it: the sculptor stops refining once the stroke has added
//! [`MAX_STROKE_NEW_TRIANGLES`] faces or the mesh has [`MAX_TRIANGLES`]
//! (the base-mesh limit's 8 M plus room for strokes), and the stroke fails
//! with the same error, leaving the document as it was (the op works on a
//! copy). The limit is a face count, so replays fail the same way on any
//! machine and thread count. (Before this check, the 100 m sample reached
//! 12 M triangles in 47 s; the estimate refuses it at once.)

use std::f64::consts::PI;

use super::brush::BrushPose;
use super::stroke::StrokeSettings;
use super::warp::Warp;
use super::SculptError;

/// Smallest `max_edge_rel` a stroke may ask for (declared in the schema).
pub const MIN_MAX_EDGE_REL: f64 = 1e-3;
/// Most triangles one frame may be estimated to refine.
pub const MAX_FRAME_TRIANGLES: f64 = 1e6;
/// Most estimated triangles summed over a stroke's frames.
pub const MAX_STROKE_WORK: f64 = 5e8;
/// Most faces a sculpt mesh may reach during a stroke (the hard limit).
pub const MAX_TRIANGLES: usize = 12_000_000;
/// Most faces one stroke may add (the hard limit).
pub const MAX_STROKE_NEW_TRIANGLES: usize = 4_000_000;

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
    SculptError::OverBudget {
        field,
        what,
        estimate,
        limit,
    }
}

/// Checks a stroke's frames (model-space `poses` with pressures, model
/// scale `scale`, `settings` with the brush already resolved) against the
/// budget before anything is refined (see the module doc).
pub fn check_stroke(
    settings: &StrokeSettings,
    scale: f64,
    poses: &[(BrushPose, f64)],
) -> Result<(), SculptError> {
    check_strokes(settings, scale, &[poses])
}

/// [`check_stroke`] for brushes moving together (a stroke and its mirror
/// image): every frame of every path within the frame budget, their sum
/// within the stroke's.
pub fn check_strokes(
    settings: &StrokeSettings,
    scale: f64,
    paths: &[&[(BrushPose, f64)]],
) -> Result<(), SculptError> {
    let mut total = 0.0;
    for poses in paths {
        total += path_work(settings, scale, poses)?;
    }
    if total.is_nan() || total > MAX_STROKE_WORK {
        return Err(over(
            "samples".into(),
            "the triangles the stroke's frames refine, summed",
            total,
            MAX_STROKE_WORK,
        ));
    }
    Ok(())
}

/// The triangles one path's frames refine, summed; an error when one
/// frame is over the frame budget.
fn path_work(
    settings: &StrokeSettings,
    scale: f64,
    poses: &[(BrushPose, f64)],
) -> Result<f64, SculptError> {
    let size = settings.brush_size() / scale;
    let max_len = settings.max_edge_rel * size;
    let h = settings.influence / scale;
    let tri = triangle_area(max_len);
    let bound = settings.brush.bound_radius();
    let mut total = 0.0;
    let mut prev: Option<&BrushPose> = None;
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
        total += frame;
    }
    Ok(total)
}

/// The error of a stroke stopped by the hard face limit.
pub fn too_many_faces(faces: usize, limit: usize) -> SculptError {
    over(
        "max_edge_rel".into(),
        "the sculpt mesh's triangles during the stroke",
        faces as f64,
        limit as f64,
    )
}
