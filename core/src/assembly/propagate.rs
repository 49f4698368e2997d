//! Structure-aware propagation: after parts changed, their descendants
//! (breadth-first) are re-placed on their parents' new surfaces so every
//! attachment keeps holding.

use std::collections::{BTreeMap, VecDeque};

use glam::{DAffine3, DQuat, DVec3};

use super::{anchor_frame, children_of, transform_gc, AssemblyError};
use crate::gc::{GcAssembly, GcError};
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

/// Re-places the descendants of `changed` in `new` (whose parts before
/// the change are `old`, same indices): each child follows the frame at
/// its start anchor from the parent's old surface to its new one, and a
/// handle is then rotated and scaled about its start so that its end
/// follows its end anchor. Children without an anchor are left alone.
pub fn reattach_descendants(
    old: &GcAssembly,
    new: &mut GcAssembly,
    changed: &[usize],
) -> Result<(), AssemblyError> {
    let mut old_surf: BTreeMap<usize, NurbsSurface> = BTreeMap::new();
    let mut new_surf: BTreeMap<usize, NurbsSurface> = BTreeMap::new();
    for c in descendants_bfs(new, changed) {
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
        let f_old = anchor_frame(old_parent, so, att.start)?;
        let f_new = anchor_frame(new_parent, sn, att.start)?;
        let m = f_new * f_old.inverse();
        let mut gc = transform_gc(old_child, &m);
        if let Some(end) = att.end {
            let (a, b) = old_child.spine.curve.domain();
            let e_old = old_child.spine.curve.point(b);
            let local = anchor_frame(old_parent, so, end)?
                .inverse()
                .transform_point3(e_old);
            let target = anchor_frame(new_parent, sn, end)?.transform_point3(local);
            let start = gc.spine.curve.point(a);
            let e_r = m.transform_point3(e_old);
            let s = similarity_about(start, e_r - start, target - start);
            gc = transform_gc(&gc, &s);
        }
        gc.validate()?;
        new.parts[c].gc = gc;
    }
    Ok(())
}
