//! Strokes that edit an existing assembly (paper 1 §3.3, §4 Figure 12):
//! a child sketched from a part's surface ([`child_from_stroke`]) and a
//! part's spine replaced by a stroke ([`replace_spine_from_stroke`]).
//!
//! Both follow the headset's GC tool (`interact::gc_tool::create`) so a
//! mouse sketch and a hand sketch give the same kind of part:
//! - a child starts where the stroke starts, projected onto the nearest
//!   part's side surface; its spine lies in the plane through that point
//!   spanned by the surface normal `n` and the parent's spine tangent `t`,
//!   in the `(n, t)` coordinates `gc_add_child` takes, sunk into the parent
//!   by 0.6 of the section radius so the union is one solid; a stroke that
//!   ends within `land_distance` of the parent makes a handle (both ends
//!   on the parent), else a spout;
//! - a replacing spine is projected into the part's spine plane and moved
//!   to start where the old spine started, so the part stays attached
//!   (a stroke drawn on a plane elsewhere would otherwise move the part
//!   into, and out of sight inside, its parent).
//!
//! Unlike the headset tool, the key sections come from [`section_params`]
//! (as many as the curve needs), not a fixed count.

use glam::{DVec2, DVec3};

use super::sections::{section_params, spine_points, SectionPlan, SectionSettings};
use super::{SketchError, SketchPlane};
use crate::assembly::{anchor_frame, project_to_surface};
use crate::gc::{fit_spine, GcAssembly};

/// How deep (in section radii) a child's spine starts inside its parent.
pub const SINK: f64 = 0.6;

/// Settings of [`child_from_stroke`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChildSettings {
    /// The stroke must start this close to a part's side surface.
    pub start_tolerance: f64,
    /// A stroke ending this close to the parent makes a handle.
    pub land_distance: f64,
    /// Section placement and stroke fitting.
    pub sections: SectionSettings,
}

impl Default for ChildSettings {
    fn default() -> Self {
        Self {
            start_tolerance: 0.01,
            land_distance: 0.012,
            sections: SectionSettings::default(),
        }
    }
}

/// Where a child's spine ends, as asked by the user.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndChoice {
    /// A handle when the stroke ends within `land_distance` of the parent.
    Auto,
    /// Always free (a spout).
    Free,
    /// Always on the parent (a handle); refused when the stroke ends
    /// farther than `land_distance` from it.
    Parent,
}

/// A child part sketched from a part's surface: the values of a
/// `gc_add_child` op.
#[derive(Clone, Debug, PartialEq)]
pub struct ChildSketch {
    /// The parent part.
    pub parent: usize,
    /// The start point, on the parent's side surface.
    pub at: DVec3,
    /// Spine points in the `(n, t)` coordinates about `at`.
    pub spine: Vec<[f64; 2]>,
    /// True when the spine ends on the parent (a handle).
    pub lands: bool,
    /// For a handle: how far the spine's end may be from the parent.
    pub end_tolerance: f64,
    /// The key sections' parameters on the child's spine.
    pub plan: SectionPlan,
}

/// The child part a stroke makes on `asm` with sections reaching `radius`
/// from its spine. The stroke must start on a part's side surface.
pub fn child_from_stroke(
    asm: &GcAssembly,
    stroke: &[DVec3],
    radius: f64,
    end: EndChoice,
    settings: &ChildSettings,
) -> Result<ChildSketch, SketchError> {
    if let Some(i) = stroke.iter().position(|p| !p.is_finite()) {
        return Err(SketchError::NonFinite(i));
    }
    let first = *stroke
        .first()
        .ok_or(SketchError::TooFewPoints { got: 0, need: 2 })?;
    let mut best = None;
    for (i, part) in asm.parts.iter().enumerate() {
        let surf = part.gc.surface()?;
        let proj = project_to_surface(&surf, first);
        if best
            .as_ref()
            .is_none_or(|(_, _, p): &(_, _, crate::assembly::Projection)| {
                proj.distance < p.distance
            })
        {
            best = Some((i, surf, proj));
        }
    }
    let (parent, surf, proj) = best.ok_or(SketchError::TooFewPoints { got: 0, need: 1 })?;
    if !(proj.distance <= settings.start_tolerance) {
        return Err(SketchError::OffPart {
            which: "starts",
            distance: proj.distance,
            tolerance: settings.start_tolerance,
            hint: "start the stroke on the part the child grows from",
        });
    }
    let frame = anchor_frame(&asm.parts[parent].gc, &surf, proj.anchor)?;
    let (n, t, normal) = (
        frame.matrix3.x_axis,
        frame.matrix3.y_axis,
        frame.matrix3.z_axis,
    );
    let o = frame.translation;
    let plane = SketchPlane::new(o, normal, n)?;
    let (simplified, _) = spine_points(stroke, &plane, settings.sections.stroke_tolerance)?;
    let start = plane.project(*simplified.first().ok_or(SketchError::ZeroLength)?);
    let depth = SINK * radius;
    let local: Vec<DVec2> = simplified
        .iter()
        .map(|p| plane.project(*p) - start)
        .collect();
    // `plane.x` is `n` and `plane.y` is `normal x n = t`.
    let spine: Vec<[f64; 2]> = local.iter().map(|q| [q.x - depth, q.y]).collect();
    let to_world = |q: [f64; 2]| o + n * q[0] + t * q[1];
    let last = *local.last().ok_or(SketchError::ZeroLength)?;
    let end_raw = to_world([last.x, last.y]);
    let raw_distance = project_to_surface(&surf, end_raw).distance;
    let lands = match end {
        EndChoice::Free => false,
        EndChoice::Auto => raw_distance < settings.land_distance,
        EndChoice::Parent => {
            if !(raw_distance < settings.land_distance) {
                return Err(SketchError::OffPart {
                    which: "ends",
                    distance: raw_distance,
                    tolerance: settings.land_distance,
                    hint: "end a handle's stroke on the part it started from",
                });
            }
            true
        }
    };
    let sunk_end = to_world([last.x - depth, last.y]);
    let end_tolerance = (project_to_surface(&surf, sunk_end).distance * 1.25).max(1e-4);
    let world: Vec<DVec3> = spine.iter().map(|q| to_world(*q)).collect();
    let child_spine = fit_spine(&world, normal)?;
    let plan = section_params(&child_spine, radius, &settings.sections)?;
    Ok(ChildSketch {
        parent,
        at: o,
        spine,
        lands,
        end_tolerance,
        plan,
    })
}

/// A part's spine replaced by a stroke: the values of a `gc_replace_spine`
/// op, and where sections must first be inserted so that the new spine
/// gets as many as it needs.
#[derive(Clone, Debug, PartialEq)]
pub struct SpineReplacement {
    /// New spine points (in the part's spine plane, starting where the old
    /// spine started).
    pub points: Vec<DVec3>,
    /// The part's spine plane normal.
    pub plane_normal: DVec3,
    /// Parameters on the *current* spine at which to insert key sections
    /// before replacing it (increasing; none coincide with an existing
    /// section), so that after the replacement the sections sit where
    /// [`section_params`] wants them on the new spine.
    pub insert_at: Vec<f64>,
    /// The placement of sections on the new spine.
    pub plan: SectionPlan,
}

/// How part `part` of `asm` gets the spine `stroke` describes.
pub fn replace_spine_from_stroke(
    asm: &GcAssembly,
    part: usize,
    stroke: &[DVec3],
    settings: &SectionSettings,
) -> Result<SpineReplacement, SketchError> {
    let gc = &asm
        .parts
        .get(part)
        .ok_or(crate::gc::GcError::BadPart {
            index: part,
            count: asm.parts.len(),
        })?
        .gc;
    let normal = gc.spine.plane_normal;
    let (a0, b0) = gc.spine.curve.domain();
    let old_start = gc.spine.curve.point(a0);
    let tangent = gc.spine.curve.derivatives(a0, 1)[1];
    let plane = SketchPlane::new(old_start, normal, tangent)?;
    let (simplified, _) = spine_points(stroke, &plane, settings.stroke_tolerance)?;
    let first = *simplified.first().ok_or(SketchError::ZeroLength)?;
    let shift = old_start - first;
    let points: Vec<DVec3> = simplified.iter().map(|p| *p + shift).collect();
    let spine = fit_spine(&points, normal)?;
    let radius = gc
        .sections
        .iter()
        .map(|s| s.scale.abs() * profile_radius(&s.profile))
        .fold(0.0, f64::max);
    let plan = section_params(&spine, radius, settings)?;
    // `Gc::replace_spine` maps the sections' parameters affinely from
    // [v_first, v_last] onto the new domain [a, b].
    let (a, b) = spine.curve.domain();
    let k = gc.sections.len();
    let (v0, v1) = (gc.sections[0].v, gc.sections[k - 1].v);
    let existing: Vec<f64> = gc.sections.iter().map(|s| s.v).collect();
    let eps = 1e-9 * (b0 - a0).abs().max(1.0);
    let insert_at = plan.params[1..plan.params.len() - 1]
        .iter()
        .map(|p| v0 + (p - a) / (b - a) * (v1 - v0))
        .filter(|v| existing.iter().all(|e| (e - v).abs() > eps))
        .collect();
    Ok(SpineReplacement {
        points,
        plane_normal: normal,
        insert_at,
        plan,
    })
}

/// Largest distance of a profile's outline from its centre.
pub fn profile_radius(p: &crate::gc::Profile) -> f64 {
    p.curve().map_or(0.0, |c| {
        (0..128)
            .map(|i| c.point(i as f64 / 128.0).truncate().length())
            .fold(0.0, f64::max)
    })
}
