//! Where a hollow child meets its parent (issue 33): the open end of a
//! shell or container child (a spout's root, a hollow handle's ends)
//! stays inside its parent, so the channel it opens never leaks.
//!
//! A child is re-placed on its parent rigidly in its anchor frame
//! ([`super::reattach_descendants`]): its spine start keeps its anchor
//! coordinates. That keeps the spine start inside the parent, but not the
//! whole section: when the parent's surface curves away more sharply
//! around the anchor (the teapot body's widest section resized by 1.2),
//! the rim of a spout's first section comes out of the body, and the
//! spout's channel then opens to the outside beside the body (the
//! union's genus went from 2 to 4).
//!
//! So after each re-placement, the **rim** of each attached open end (its
//! key section's curve, sampled at [`RIM_SAMPLES`] points) is measured
//! against the parent's side surface: its *exposure* is the largest
//! signed distance of a rim point from the surface, positive outside
//! (closest points by Newton's method, walking around the rim from the
//! anchor). When the rim was inside before the edit and would now stand
//! out (or come within a quarter of the margin of it), the child is sunk
//! along the parent's inward normal at the anchor (projected into the
//! child's spine plane, so every plane relation holds) until its rim is
//! back inside by [`BURY_MARGIN`] of its radius (or as deep as it was, if
//! that was less). A part re-placed with its parent, slid or copied is
//! moved as a whole (a handle's end by turning the handle about its
//! start, its start about its end, as its ends are re-placed); a part
//! whose own shape was edited has only that end's key point moved (a
//! bend), so a bend's key point stays where the user put it. An end
//! that would need sinking deeper than [`MAX_SINK`] radii is refused:
//! [`AssemblyError::RelationBroken`] naming `connected`.
//!
//! Choices and why:
//! - Solid children are left as they are: a solid end that stands partly
//!   out of its parent shows its cap, but the union is still one closed
//!   solid with the same topology (a rail wider than the post it leaves
//!   is how the chair is made). Only an open end leaks.
//! - An end that already stood out before the edit (a user's own design)
//!   is not corrected: there is nothing to keep. An end the edit opens
//!   (`gc_set_shape` making a solid spout a shell) is kept inside: capped,
//!   it could stand out harmlessly; open, it would leak.
//! - The margin is in the child's units (5% of its rim radius), enough for
//!   the meshes' chords on both sides at the default resolutions.

use glam::{DAffine3, DVec3};

use super::propagate::similarity_about;
use super::structure::end_radius;
use super::{anchor_frame, project_near, project_to_surface, transform_gc, Anchor, AssemblyError};
use crate::gc::{ClosedEnd, Gc, GcAssembly, GcError, ShapeType};
use crate::nurbs::NurbsSurface;

/// Points a section's rim is measured at.
pub const RIM_SAMPLES: usize = 48;

/// How far inside its parent a re-placed open end is kept, in radii of
/// its section.
pub const BURY_MARGIN: f64 = 0.05;

/// The deepest an open end is sunk by one edit, in radii of its section.
pub const MAX_SINK: f64 = 1.0;

/// Sinking steps before an end is refused.
const SINK_STEPS: usize = 8;

/// True when the first (`first`) or last end of `gc` is open: both ends
/// of a shell, the end a container leaves open.
pub(super) fn open_end(gc: &Gc, first: bool) -> bool {
    match gc.shape {
        ShapeType::Solid => false,
        ShapeType::Shell { .. } => true,
        ShapeType::Container { closed_end, .. } => match closed_end {
            ClosedEnd::Start => !first,
            ClosedEnd::End => first,
        },
    }
}

/// The rim of `gc`'s first (`first`) or last key section, in world space.
fn rim(gc: &Gc, first: bool) -> Result<Vec<DVec3>, GcError> {
    let frames = gc.frames()?;
    let s = if first {
        gc.sections.first()
    } else {
        gc.sections.last()
    }
    .ok_or(GcError::TooFewSections { got: 0 })?;
    let c = s.world_curve(&frames.at(&gc.spine, s.v)?)?;
    Ok((0..RIM_SAMPLES)
        .map(|i| c.point(i as f64 / RIM_SAMPLES as f64))
        .collect())
}

/// How far the rim stands out of the side surface `surf`: the largest
/// signed distance of a rim point from it (positive outside). A point
/// whose closest surface point is on the surface's end rim lies beyond
/// the parent's end and counts as outside by its distance.
fn exposure(surf: &NurbsSurface, rim: &[DVec3]) -> f64 {
    let (_, (v0, v1)) = surf.domain();
    let mut at: Option<Anchor> = None;
    let mut worst = f64::NEG_INFINITY;
    for p in rim {
        let pr = match at {
            None => project_to_surface(surf, *p),
            Some(seed) => project_near(surf, *p, seed),
        };
        at = Some(pr.anchor);
        let Anchor { u, v } = pr.anchor;
        let signed = if v <= v0 || v >= v1 {
            pr.distance
        } else {
            let d = surf.derivatives(u, v, 1);
            match d[1][0].cross(d[0][1]).try_normalize() {
                Some(n) => (*p - pr.point).dot(n),
                None => pr.distance,
            }
        };
        worst = worst.max(signed);
    }
    worst
}

/// Where an attached end of a child sits: which end, its anchor on the
/// parent, and how far its rim stood out before the edit.
#[derive(Clone, Copy, Debug)]
struct End {
    first: bool,
    anchor: Anchor,
    before: f64,
}

/// The parts a junction check needs: the child and parent indices (for
/// the refusal), the parent after the edit and its side surface, and the
/// child's ends.
pub(super) struct Junction<'a> {
    /// The child's index.
    pub child: usize,
    /// The parent's index.
    pub parent: usize,
    /// The parent after the edit.
    pub parent_gc: &'a Gc,
    /// Its side surface.
    pub surf: &'a NurbsSurface,
    /// Sink by moving the end's key point (a bend: the rest of the spine
    /// stays where the user put it; for a part's own edits) rather than
    /// the whole part (a part re-placed with its parent).
    pub by_key_point: bool,
}

/// Exposure of each attached open end of `old_child` on its parent's
/// side surface `old_surf` before the edit (`None`: nothing to keep).
pub(super) fn open_ends_before(
    old_surf: &NurbsSurface,
    old_child: &Gc,
    start: Anchor,
    end: Option<Anchor>,
) -> Result<Vec<(bool, Anchor, f64)>, GcError> {
    let mut out = Vec::new();
    for (first, anchor) in [(true, Some(start)), (false, end)] {
        let Some(anchor) = anchor else { continue };
        if !open_end(old_child, first) {
            continue;
        }
        out.push((first, anchor, exposure(old_surf, &rim(old_child, first)?)));
    }
    Ok(out)
}

impl Junction<'_> {
    /// `gc` (the child placed on the parent after the edit) sunk where an
    /// open end's rim would stand out (see the module doc); `before` is
    /// [`open_ends_before`] with the anchors after the edit.
    /// `handle` is true when both ends are attached.
    pub fn bury(
        &self,
        mut gc: Gc,
        before: &[(bool, Anchor, f64)],
        handle: bool,
    ) -> Result<Gc, AssemblyError> {
        let ends: Vec<End> = before
            .iter()
            .filter(|(first, _, e)| open_end(&gc, *first) && *e <= 0.0)
            .map(|&(first, anchor, before)| End {
                first,
                anchor,
                before,
            })
            .collect();
        if ends.is_empty() {
            return Ok(gc);
        }
        // Two passes: sinking one end of a handle turns it about the
        // other, which moves that end's rim a little.
        for _ in 0..2 {
            for end in &ends {
                gc = self.sink_end(gc, end, handle)?;
            }
        }
        Ok(gc)
    }

    fn sink_end(&self, mut gc: Gc, end: &End, handle: bool) -> Result<Gc, AssemblyError> {
        let r = end_radius(&gc, end.first);
        let margin = BURY_MARGIN * r;
        let target = end.before.max(-margin);
        let mut e = exposure(self.surf, &rim(&gc, end.first)?);
        if e <= target + 0.25 * margin {
            return Ok(gc);
        }
        let dir = self.sink_direction(&gc, end.anchor)?;
        let mut depth = 0.0;
        for _ in 0..SINK_STEPS {
            if e <= target {
                return Ok(gc);
            }
            let step = e - target + 0.05 * margin;
            depth += step;
            if !(depth <= MAX_SINK * r) {
                break;
            }
            gc = if self.by_key_point {
                let i = if end.first { 0 } else { gc.sections.len() - 1 };
                let mut bent = gc.clone();
                let key = bent.key_points()[i];
                bent.bend(i, key + dir * step)?;
                bent
            } else {
                moved_end(&gc, end.first, handle, dir * step)
            };
            gc.validate()?;
            e = exposure(self.surf, &rim(&gc, end.first)?);
        }
        if e <= target + 0.25 * margin {
            Ok(gc)
        } else {
            Err(self.broken())
        }
    }

    /// The parent's inward normal at `anchor`, in the child's spine plane.
    fn sink_direction(&self, gc: &Gc, anchor: Anchor) -> Result<DVec3, AssemblyError> {
        let n = anchor_frame(self.parent_gc, self.surf, anchor)?
            .matrix3
            .x_axis;
        let pn = gc.spine.plane_normal.normalize();
        Ok(-(n - pn * n.dot(pn)).try_normalize().unwrap_or(n))
    }

    fn broken(&self) -> AssemblyError {
        AssemblyError::RelationBroken {
            relation: super::RelationKind::Connected,
            parts: (self.child, self.parent),
        }
    }
}

/// `gc` with its first (`first`) or last spine end moved by `w`: the
/// whole part for a free-ended child, else the part turned and scaled
/// about its other end (a handle keeps that end where it is).
fn moved_end(gc: &Gc, first: bool, handle: bool, w: DVec3) -> Gc {
    let (a, b) = gc.spine.curve.domain();
    let (s, e) = (gc.spine.curve.point(a), gc.spine.curve.point(b));
    let m = match (handle, first) {
        (false, _) => DAffine3::from_translation(w),
        (true, true) => similarity_about(e, s - e, s + w - e),
        (true, false) => similarity_about(s, e - s, e + w - s),
    };
    transform_gc(gc, &m)
}

/// Sinks part `i` of `asm` (a child whose own placement just changed:
/// edited, slid, copied) where an open end's rim would come out of its
/// parent; `old` holds the assembly before the change (the same parent,
/// part `i` as it was). `by_key_point`: see [`Junction::by_key_point`].
pub(super) fn bury_part(
    old: &GcAssembly,
    asm: &mut GcAssembly,
    i: usize,
    by_key_point: bool,
) -> Result<(), AssemblyError> {
    let (Some(p), Some(att)) = (asm.parts[i].parent, asm.parts[i].attach) else {
        return Ok(());
    };
    let count = old.parts.len();
    let (Some(old_parent), Some(old_child)) = (old.parts.get(p), old.parts.get(i)) else {
        return Err(GcError::BadPart { index: i, count }.into());
    };
    if !open_end(&asm.parts[i].gc, true) && !open_end(&asm.parts[i].gc, false) {
        return Ok(());
    }
    let mut before =
        open_ends_before(&old_parent.gc.surface()?, &old_child.gc, att.start, att.end)?;
    // An end this edit opened (a solid spout made a shell): its rim may
    // have stood out harmlessly while it was capped; now it would leak, so
    // it is kept inside like any open end.
    for (first, anchor) in [(true, Some(att.start)), (false, att.end)] {
        let Some(anchor) = anchor else { continue };
        if open_end(&asm.parts[i].gc, first) && !open_end(&old_child.gc, first) {
            before.push((first, anchor, f64::NEG_INFINITY));
        }
    }
    let surf = asm.parts[p].gc.surface()?;
    let junction = Junction {
        child: i,
        parent: p,
        parent_gc: &asm.parts[p].gc,
        surf: &surf,
        by_key_point,
    };
    let gc = junction.bury(asm.parts[i].gc.clone(), &before, att.end.is_some())?;
    asm.parts[i].gc = gc;
    Ok(())
}
