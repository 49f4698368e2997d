//! Structure-aware propagation: after parts changed, their descendants
//! (breadth-first) are re-placed on their parents' new surfaces so every
//! attachment keeps holding.

use std::collections::{BTreeMap, VecDeque};

use glam::{DAffine3, DQuat, DVec3};

use super::junction::{open_ends_before, Junction};
use super::relations::same_plane;
use super::structure::{RelationKind, RELATION_TOLERANCE};
use super::{
    anchor_frame, anchor_frame_in_plane, children_of, mirror_plane, transform_gc, Anchor,
    AssemblyError, Attachment,
};
use crate::gc::{Gc, GcAssembly, GcError};
use crate::nurbs::NurbsSurface;

/// The descendants of `roots`, breadth-first, each once, without the
/// roots themselves.
pub fn descendants_bfs(asm: &GcAssembly, roots: &[usize]) -> Vec<usize> {
    let mut seen = vec![false; asm.parts.len()];
    for &r in roots {
        if let Some(s) = seen.get_mut(r) {
            *s = true;
        }
    }
    let mut queue: VecDeque<usize> = roots.iter().copied().collect();
    let mut out = Vec::new();
    while let Some(p) = queue.pop_front() {
        for c in children_of(asm, p) {
            if !seen[c] {
                seen[c] = true;
                out.push(c);
                queue.push_back(c);
            }
        }
    }
    out
}

/// The similarity about `pivot` taking direction `from` to `to`
/// (rotation by the shortest arc, uniform scale `|to| / |from|`).
pub(super) fn similarity_about(pivot: DVec3, from: DVec3, to: DVec3) -> DAffine3 {
    let (lf, lt) = (from.length(), to.length());
    if !(lf > 1e-300 && lt > 1e-300) {
        return DAffine3::IDENTITY;
    }
    let (a, b) = (from / lf, to / lt);
    // `DQuat::from_rotation_arc` returns the identity below about 3e-8
    // rad, which leaves a handle's end up to 1e-9 of its length off its
    // anchor; the half-angle form `(a x b, 1 + a . b)` is exact there.
    let d = a.dot(b);
    let q = if d > -0.5 {
        let c = a.cross(b);
        DQuat::from_xyzw(c.x, c.y, c.z, 1.0 + d).normalize()
    } else {
        DQuat::from_rotation_arc(a, b)
    };
    DAffine3::from_translation(pivot)
        * DAffine3::from_scale_rotation_translation(DVec3::splat(lt / lf), q, DVec3::ZERO)
        * DAffine3::from_translation(-pivot)
}

/// The part whose spine plane child `c` must stay in, when it has a
/// recorded coplanar relation: its parent if they are coplanar, else the
/// first coplanar part that is not still to be re-placed (`pending`).
fn coplanar_partner(asm: &GcAssembly, c: usize, p: usize, pending: &[bool]) -> Option<usize> {
    let rec = asm.relations.as_ref()?;
    let with = |j: usize| {
        let key = (c.min(j), c.max(j));
        rec.coplanar.contains(&key)
    };
    if with(p) {
        return Some(p);
    }
    (0..asm.parts.len()).find(|&j| j != c && !pending.get(j).copied().unwrap_or(false) && with(j))
}

/// A child's placement on its parent: the frames at its start (and a
/// handle's end) anchor on the parent's old and new surfaces, and the
/// anchors after the re-placement.
struct Placement {
    start: (DAffine3, DAffine3),
    end: Option<(DAffine3, DAffine3)>,
    attach: Attachment,
}

/// The frames of [`reattach_descendants`] at the child's anchors: the
/// plain anchor frames, or (`plane`: the old and new planes of a
/// coplanar partner) frames kept in the partner's plane
/// ([`anchor_frame_in_plane`]), the anchors moved to where their
/// iso-curves cross it.
fn placement(
    (old_parent, so): (&Gc, &NurbsSurface),
    (new_parent, sn): (&Gc, &NurbsSurface),
    att: Attachment,
    plane: Option<((DVec3, DVec3), (DVec3, DVec3))>,
) -> Result<Option<Placement>, AssemblyError> {
    let frames = |at: Anchor| -> Result<Option<(DAffine3, DAffine3, Anchor)>, AssemblyError> {
        let Some((po, pn)) = plane else {
            return Ok(Some((
                anchor_frame(old_parent, so, at)?,
                anchor_frame(new_parent, sn, at)?,
                at,
            )));
        };
        let offset = (so.point(at.u, at.v) - po.0).dot(po.1);
        let Some((_, f_old)) = anchor_frame_in_plane(old_parent, so, at, po, offset) else {
            return Ok(None);
        };
        let Some((moved, f_new)) = anchor_frame_in_plane(new_parent, sn, at, pn, offset) else {
            return Ok(None);
        };
        Ok(Some((f_old, f_new, moved)))
    };
    let Some((s_old, s_new, start)) = frames(att.start)? else {
        return Ok(None);
    };
    let (end, end_anchor) = match att.end {
        None => (None, None),
        Some(e) => match frames(e)? {
            None => return Ok(None),
            Some((e_old, e_new, moved)) => (Some((e_old, e_new)), Some(moved)),
        },
    };
    Ok(Some(Placement {
        start: (s_old, s_new),
        end,
        attach: Attachment {
            start,
            end: end_anchor,
        },
    }))
}

/// `old_child` re-placed by `pl`: it follows the frame at its start
/// anchor, and a handle is then rotated and scaled about its start so its
/// end follows the frame at its end anchor.
fn place(old_child: &Gc, pl: &Placement) -> Gc {
    let m = pl.start.1 * pl.start.0.inverse();
    let mut gc = transform_gc(old_child, &m);
    if let Some((e_old, e_new)) = pl.end {
        let (a, b) = old_child.spine.curve.domain();
        let end_old = old_child.spine.curve.point(b);
        let local = e_old.inverse().transform_point3(end_old);
        let target = e_new.transform_point3(local);
        let start = gc.spine.curve.point(a);
        let e_r = m.transform_point3(end_old);
        let s = similarity_about(start, e_r - start, target - start);
        gc = transform_gc(&gc, &s);
    }
    gc
}

/// Re-places the descendants of `changed` in `new` (whose parts before
/// the change are `old`, same indices): each child follows the frame at
/// its start anchor from the parent's old surface to its new one, and a
/// handle is then rotated and scaled about its start so that its end
/// follows its end anchor. Children without an anchor are left alone.
///
/// Two corrections keep the recorded relations and the union's topology
/// where a rigid re-placement would not:
/// - a child recorded coplanar with its parent is placed by frames kept
///   in the parent's spine plane ([`anchor_frame_in_plane`]): a section
///   replaced by another profile kind, or twisted, re-parameterizes the
///   parent's surface, so a fixed `(u, v)` moves off the plane and the
///   normal there turns out of it. A child coplanar with a part already
///   in place (a sibling) is placed so when the plain placement would
///   leave that plane. Either is refused as `coplanar` only when its
///   anchor's iso-curve no longer reaches the plane;
/// - an open end (a spout's root) whose rim would come out of the parent
///   is sunk back in (`assembly::junction`).
pub fn reattach_descendants(
    old: &GcAssembly,
    new: &mut GcAssembly,
    changed: &[usize],
) -> Result<(), AssemblyError> {
    let mut old_surf: BTreeMap<usize, NurbsSurface> = BTreeMap::new();
    let mut new_surf: BTreeMap<usize, NurbsSurface> = BTreeMap::new();
    let order = descendants_bfs(new, changed);
    let mut pending = vec![false; new.parts.len()];
    for &c in &order {
        pending[c] = true;
    }
    for c in order {
        pending[c] = false;
        let (Some(p), Some(att)) = (new.parts[c].parent, new.parts[c].attach) else {
            continue;
        };
        let count = old.parts.len();
        let old_parent = &old
            .parts
            .get(p)
            .ok_or(GcError::BadPart { index: p, count })?
            .gc;
        let old_child = &old
            .parts
            .get(c)
            .ok_or(GcError::BadPart { index: c, count })?
            .gc;
        if let std::collections::btree_map::Entry::Vacant(e) = old_surf.entry(p) {
            e.insert(old_parent.surface()?);
        }
        // The parent may itself have just been re-placed: always rebuild.
        new_surf.insert(p, new.parts[p].gc.surface()?);
        let (so, sn) = (&old_surf[&p], &new_surf[&p]);
        let new_parent = &new.parts[p].gc;
        let partner = coplanar_partner(new, c, p, &pending);
        let in_plane = |j: usize| -> Result<(Gc, Attachment), AssemblyError> {
            let planes = (
                mirror_plane(&old.parts[j].gc),
                mirror_plane(&new.parts[j].gc),
            );
            let kept = placement((old_parent, so), (new_parent, sn), att, Some(planes))?.ok_or(
                AssemblyError::RelationBroken {
                    relation: RelationKind::Coplanar,
                    parts: (c.min(j), c.max(j)),
                },
            )?;
            Ok((place(old_child, &kept), kept.attach))
        };
        let (gc, attach) = match partner {
            // In its parent's plane: always placed by frames kept there.
            Some(j) if j == p => in_plane(j)?,
            _ => {
                let pl = placement((old_parent, so), (new_parent, sn), att, None)?.ok_or(
                    AssemblyError::DegenerateAnchor {
                        u: att.start.u,
                        v: att.start.v,
                    },
                )?;
                let gc = place(old_child, &pl);
                match partner {
                    // In a sibling's plane: kept there when the plain
                    // placement would leave it. As `check_relations` reads
                    // the pair: the smaller index's plane.
                    Some(j)
                        if !(if j < c {
                            same_plane(&new.parts[j].gc, &gc, RELATION_TOLERANCE)
                        } else {
                            same_plane(&gc, &new.parts[j].gc, RELATION_TOLERANCE)
                        }) =>
                    {
                        in_plane(j)?
                    }
                    _ => (gc, att),
                }
            }
        };
        let before = open_ends_before(so, old_child, attach.start, attach.end)?;
        let junction = Junction {
            child: c,
            parent: p,
            parent_gc: new_parent,
            surf: sn,
            by_key_point: false,
        };
        let gc = junction.bury(gc, &before, attach.end.is_some())?;
        gc.validate()?;
        new.parts[c].gc = gc;
        new.parts[c].attach = Some(attach);
    }
    Ok(())
}
