//! Structure-aware editing (§3.3): the relations an assembly records, the
//! one propagation path every GC edit goes through, and the check that
//! every recorded relation still holds after an edit.
//!
//! The paper identifies the relations "by analyzing the assembly
//! procedure", so they are recorded when a part is added (`gc_add_child`,
//! `gc_copy`), in [`RecordedRelations`], and never re-detected afterwards:
//! a pair recorded as symmetric stays a pair however many edits follow,
//! and rounding can no longer make it drop out of a 1e-9 detection.
//! Assemblies saved before relations were recorded (the field is absent,
//! `None`) get them detected once from their geometry on their first
//! assembly op ([`ensure_recorded`]).
//!
//! What is recorded for a new part `k`:
//! - **coplanar** with its parent and with each sibling whose spine lies in
//!   the same plane;
//! - **concentric** with its parent when both spines are straight and on
//!   one line;
//! - **symmetric** with each sibling it mirrors about the parent's spine
//!   plane; never with a part it coincides with (a part in its parent's
//!   spine plane is its own mirror image), and never with the part it was
//!   copied from unless the copy was asked to be mirrored.
//!
//! Connectivity is the parent link itself plus the [`Attachment`]: a
//! child's spine starts within its start section's radius of its anchor
//! point on the parent (and a handle's end within its end radius), plus
//! how deep a junction may have sunk an open end ([`super::junction`]).
//!
//! Propagation ([`propagate_edit`]): the edit is applied to the part, the
//! mirrored edit to its recorded twins, the edited parts whose spine start
//! (or a handle's end) moved are re-anchored by projecting it on the parent
//! (the relation "connected" fails when it left the parent), the
//! descendants are re-placed breadth-first ([`reattach_descendants`]), and
//! then every recorded relation is checked ([`check_relations`]); an edit
//! that breaks one fails with [`AssemblyError::RelationBroken`] naming it,
//! and the document keeps its state.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::junction::bury_part;
use super::relations::{coincident, is_mirror, on_one_line, same_plane};
use super::{
    flip_profile, mirror_plane, project_to_surface, reattach_descendants, reflect, AssemblyError,
    Attachment, GcEditPart, PartEdit,
};
use crate::gc::{self, Gc, GcAssembly, GcEdit, GcError, PartId, RecordedRelations};
use crate::nurbs::euclidean;

/// A relation of §3.3, as an error names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RelationKind {
    /// A child touches its parent.
    Connected,
    /// Two spines in one plane.
    Coplanar,
    /// Two straight spines on one line.
    Concentric,
    /// Two siblings mirrored about their parent's spine plane.
    Symmetric,
}

impl std::fmt::Display for RelationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Connected => "connected",
            Self::Coplanar => "coplanar",
            Self::Concentric => "concentric",
            Self::Symmetric => "symmetric",
        })
    }
}

/// Relative tolerance (of a part's size) the relations are kept to.
pub const RELATION_TOLERANCE: f64 = 1e-9;

fn pair(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// True when parts `a` and `b` are siblings mirrored about their parent's
/// spine plane (and not one part lying on the other).
pub(super) fn mirrored_siblings(asm: &GcAssembly, a: usize, b: usize, rel: f64) -> bool {
    let (Some(pa), Some(pb)) = (asm.parts[a].parent, asm.parts[b].parent) else {
        return false;
    };
    if pa != pb || a == b {
        return false;
    }
    let (o, n) = mirror_plane(&asm.parts[pa].gc);
    let (ga, gb) = (&asm.parts[a].gc, &asm.parts[b].gc);
    is_mirror(ga, gb, o, n, rel) && !coincident(ga, gb, rel)
}

/// The relations of part `k` with the parts before it, as recorded when
/// `k` is added; `source` is the part it was copied from and whether the
/// copy was mirrored.
fn relations_of_new_part(
    asm: &GcAssembly,
    k: usize,
    source: Option<(usize, bool)>,
) -> RecordedRelations {
    let mut out = RecordedRelations::default();
    let Some(parent) = asm.parts[k].parent else {
        return out;
    };
    let gk = &asm.parts[k].gc;
    let pg = &asm.parts[parent].gc;
    if same_plane(pg, gk, RELATION_TOLERANCE) {
        out.coplanar.push(pair(parent, k));
    }
    if on_one_line(pg, gk, RELATION_TOLERANCE) {
        out.concentric.push(pair(parent, k));
    }
    for j in 0..k {
        if asm.parts[j].parent != Some(parent) {
            continue;
        }
        let gj = &asm.parts[j].gc;
        if same_plane(gj, gk, RELATION_TOLERANCE) {
            out.coplanar.push(pair(j, k));
        }
        let from_source_unmirrored = matches!(source, Some((s, false)) if s == j);
        if !from_source_unmirrored && mirrored_siblings(asm, j, k, RELATION_TOLERANCE) {
            out.symmetric.push(pair(j, k));
        }
    }
    out
}

/// Records the relations of an assembly saved before relations were
/// recorded, detected once from its geometry (as if its parts had been
/// added one by one); does nothing when they are recorded or when there
/// is only one part.
pub fn ensure_recorded(asm: &mut GcAssembly) {
    // A single part has no relations (and keeps its serialized form).
    if asm.relations.is_some() || asm.parts.len() < 2 {
        return;
    }
    let mut all = RecordedRelations::default();
    for k in 0..asm.parts.len() {
        let r = relations_of_new_part(asm, k, None);
        all.symmetric.extend(r.symmetric);
        all.coplanar.extend(r.coplanar);
        all.concentric.extend(r.concentric);
    }
    asm.relations = Some(all);
}

/// Records the relations of the part just added at index `k` (see the
/// module doc); `source` is the copied part and whether it was mirrored.
pub fn record_new_part(asm: &mut GcAssembly, k: usize, source: Option<(usize, bool)>) {
    let r = relations_of_new_part(asm, k, source);
    let rec = asm.relations.get_or_insert_with(Default::default);
    rec.symmetric.extend(r.symmetric);
    rec.coplanar.extend(r.coplanar);
    rec.concentric.extend(r.concentric);
}

/// Radius of `gc`'s first (`first`) or last section: the largest distance
/// of its profile's control points from the spine, times its scale.
pub(super) fn end_radius(gc: &Gc, first: bool) -> f64 {
    let s = if first {
        gc.sections.first()
    } else {
        gc.sections.last()
    };
    s.and_then(|s| {
        s.profile.curve().ok().map(|c| {
            c.control
                .iter()
                .map(|h| euclidean(*h).truncate().length())
                .fold(0.0, f64::max)
                * s.scale
        })
    })
    .unwrap_or(0.0)
}

/// How far `gc`'s first (`first`) or last spine end may be from its
/// anchor on the parent: its section's radius, plus the deepest a
/// junction sinks an open end in one edit ([`super::MAX_SINK`] radii).
pub(super) fn attach_reach(gc: &Gc, first: bool) -> f64 {
    end_radius(gc, first) * (1.0 + super::MAX_SINK)
}

fn spine_ends(gc: &Gc) -> (DVec3, DVec3) {
    let (a, b) = gc.spine.curve.domain();
    (gc.spine.curve.point(a), gc.spine.curve.point(b))
}

fn broken(relation: RelationKind, a: usize, b: usize) -> AssemblyError {
    let parts = if relation == RelationKind::Connected {
        (a, b)
    } else {
        pair(a, b)
    };
    AssemblyError::RelationBroken { relation, parts }
}

/// Checks every relation recorded in `asm` (and every child's connection
/// to its parent) to [`RELATION_TOLERANCE`] of the parts' sizes.
pub fn check_relations(asm: &GcAssembly) -> Result<(), AssemblyError> {
    let mut surfaces = std::collections::BTreeMap::new();
    for (c, part) in asm.parts.iter().enumerate() {
        let (Some(p), Some(att)) = (part.parent, part.attach) else {
            continue;
        };
        let parent = asm.parts.get(p).ok_or(GcError::BadPart {
            index: p,
            count: asm.parts.len(),
        })?;
        if let std::collections::btree_map::Entry::Vacant(e) = surfaces.entry(p) {
            e.insert(parent.gc.surface()?);
        }
        let surf = &surfaces[&p];
        let (s, e) = spine_ends(&part.gc);
        let (_, (v0, v1)) = surf.domain();
        // An anchor past the end of the parent's surface (a shifted or
        // deleted end section) has left the parent.
        let near = |at: super::Anchor, q: DVec3, r: f64| {
            at.v >= v0
                && at.v <= v1
                && surf.point(at.u, at.v).distance(q) <= r * (1.0 + 1e-9) + 1e-12
        };
        if !near(att.start, s, attach_reach(&part.gc, true)) {
            return Err(broken(RelationKind::Connected, c, p));
        }
        if let Some(end) = att.end {
            if !near(end, e, attach_reach(&part.gc, false)) {
                return Err(broken(RelationKind::Connected, c, p));
            }
        }
    }
    let Some(rec) = &asm.relations else {
        return Ok(());
    };
    let gc = |i: usize| -> Result<&Gc, AssemblyError> {
        asm.parts.get(i).map(|p| &p.gc).ok_or_else(|| {
            GcError::BadPart {
                index: i,
                count: asm.parts.len(),
            }
            .into()
        })
    };
    for &(a, b) in &rec.coplanar {
        if !same_plane(gc(a)?, gc(b)?, RELATION_TOLERANCE) {
            return Err(broken(RelationKind::Coplanar, a, b));
        }
    }
    for &(a, b) in &rec.concentric {
        if !on_one_line(gc(a)?, gc(b)?, RELATION_TOLERANCE) {
            return Err(broken(RelationKind::Concentric, a, b));
        }
    }
    for &(a, b) in &rec.symmetric {
        gc(a)?;
        gc(b)?;
        let parent = asm.parts[a].parent;
        let ok = parent.is_some()
            && parent == asm.parts[b].parent
            && parent.is_some_and(|p| {
                let (o, n) = mirror_plane(&asm.parts[p].gc);
                is_mirror(&asm.parts[a].gc, &asm.parts[b].gc, o, n, RELATION_TOLERANCE)
            });
        if !ok {
            return Err(broken(RelationKind::Symmetric, a, b));
        }
    }
    Ok(())
}

/// An edit of one part that can be seen in a mirror: how its twins get it.
pub trait MirrorEdit: GcEdit {
    /// The same edit on the mirror image about the plane through `o` with
    /// unit normal `n`.
    fn mirrored(&self, o: DVec3, n: DVec3) -> Self;
}

fn reflect_dir(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

macro_rules! mirror_unchanged {
    ($($ty:ty),*) => {$(
        impl MirrorEdit for $ty {
            fn mirrored(&self, _: DVec3, _: DVec3) -> Self {
                self.clone()
            }
        }
    )*};
}

mirror_unchanged!(
    gc::GcResize,
    gc::GcShift,
    gc::GcDeleteSection,
    gc::GcInsertSection,
    gc::GcSetShape,
    gc::GcSetResolution
);

impl MirrorEdit for gc::GcBend {
    fn mirrored(&self, o: DVec3, n: DVec3) -> Self {
        Self {
            to: reflect(self.to, o, n),
            ..self.clone()
        }
    }
}

impl MirrorEdit for gc::GcTwist {
    fn mirrored(&self, _: DVec3, _: DVec3) -> Self {
        Self {
            angle: -self.angle,
            ..self.clone()
        }
    }
}

impl MirrorEdit for gc::GcReplaceSpine {
    fn mirrored(&self, o: DVec3, n: DVec3) -> Self {
        Self {
            points: self.points.iter().map(|p| reflect(*p, o, n)).collect(),
            plane_normal: reflect_dir(self.plane_normal, n),
            ..self.clone()
        }
    }
}

impl MirrorEdit for gc::GcReplaceSection {
    fn mirrored(&self, _: DVec3, _: DVec3) -> Self {
        Self {
            profile: flip_profile(&self.profile),
            twist: -self.twist,
            ..self.clone()
        }
    }
}

impl GcEdit for GcEditPart {
    fn part(&self) -> PartId {
        self.part
    }
    fn edit(&self, gc: &mut Gc) -> Result<(), GcError> {
        match self.edit {
            PartEdit::Bend { section, to } => gc.bend(section.0, to),
            PartEdit::Resize { section, factor } => gc.resize(section.0, factor),
            PartEdit::Shift { section, v } => gc.shift(section.0, v),
            PartEdit::Twist { section, angle } => gc.twist(section.0, angle),
        }
    }
}

impl MirrorEdit for GcEditPart {
    fn mirrored(&self, o: DVec3, n: DVec3) -> Self {
        let edit = match self.edit {
            PartEdit::Bend { section, to } => PartEdit::Bend {
                section,
                to: reflect(to, o, n),
            },
            PartEdit::Twist { section, angle } => PartEdit::Twist {
                section,
                angle: -angle,
            },
            ref other => other.clone(),
        };
        Self {
            part: self.part,
            edit,
        }
    }
}

/// Re-anchors part `i` after its own spine changed: a start (or a
/// handle's end) that moved is projected on the parent's surface and must
/// stay within its section's radius of it.
fn reanchor_own(old: &GcAssembly, asm: &mut GcAssembly, i: usize) -> Result<(), AssemblyError> {
    let (Some(p), Some(att)) = (asm.parts[i].parent, asm.parts[i].attach) else {
        return Ok(());
    };
    let (s0, e0) = spine_ends(&old.parts[i].gc);
    let (s1, e1) = spine_ends(&asm.parts[i].gc);
    if s0 == s1 && e0 == e1 {
        return Ok(());
    }
    let surf = asm.parts[p].gc.surface()?;
    let gc = &asm.parts[i].gc;
    let place = |at: super::Anchor, q0: DVec3, q1: DVec3, r: f64| {
        if q0 == q1 {
            return Ok(at);
        }
        let pr = project_to_surface(&surf, q1);
        if pr.distance <= r {
            Ok(pr.anchor)
        } else {
            Err(broken(RelationKind::Connected, i, p))
        }
    };
    let start = place(att.start, s0, s1, attach_reach(gc, true))?;
    let end = match att.end {
        Some(e) => Some(place(e, e0, e1, attach_reach(gc, false))?),
        None => None,
    };
    asm.parts[i].attach = Some(Attachment { start, end });
    Ok(())
}

/// Applies `edit` structure-aware (see the module doc): to its part, the
/// mirrored edit to the part's recorded twins, then re-anchors, re-places
/// the descendants breadth-first and checks every recorded relation.
pub fn propagate_edit<E: MirrorEdit>(asm: &mut GcAssembly, edit: &E) -> Result<(), AssemblyError> {
    let part = edit.part().0;
    if part >= asm.parts.len() {
        return Err(GcError::BadPart {
            index: part,
            count: asm.parts.len(),
        }
        .into());
    }
    ensure_recorded(asm);
    let old = asm.clone();
    let twins = asm
        .relations
        .as_ref()
        .map(|r| r.twins_of(part))
        .unwrap_or_default();
    edit.edit(&mut asm.parts[part].gc)?;
    if let Some(p) = old.parts[part].parent {
        let (o, n) = mirror_plane(&old.parts[p].gc);
        let m = edit.mirrored(o, n);
        for &t in &twins {
            m.edit(&mut asm.parts[t].gc)?;
        }
    }
    let mut roots = vec![part];
    roots.extend(twins);
    for &r in &roots {
        reanchor_own(&old, asm, r)?;
        bury_part(&old, asm, r, true)?;
    }
    reattach_descendants(&old, asm, &roots)?;
    check_relations(asm)
}

/// Release a recorded relation between two parts, so that later edits may
/// break it (the user's way to ask for it): after a [`RelationBroken`]
/// refusal, the host offers this op and the edit again. Connectivity is
/// the parent link and cannot be released.
///
/// [`RelationBroken`]: AssemblyError::RelationBroken
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcRelease {
    /// One part.
    pub part: PartId,
    /// The other part.
    pub other: PartId,
    /// The relation to release (`coplanar`, `concentric` or `symmetric`).
    pub relation: RelationKind,
}

impl GcRelease {
    /// Applies the op to `asm`; a relation that is not recorded is an
    /// error naming it.
    pub fn apply_to(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        let count = asm.parts.len();
        for p in [self.part.0, self.other.0] {
            if p >= count {
                return Err(GcError::BadPart { index: p, count }.into());
            }
        }
        ensure_recorded(asm);
        let key = pair(self.part.0, self.other.0);
        let not_recorded = AssemblyError::NotRecorded {
            relation: self.relation,
            parts: key,
        };
        let rec = asm.relations.get_or_insert_with(Default::default);
        let list = match self.relation {
            RelationKind::Connected => return Err(not_recorded),
            RelationKind::Coplanar => &mut rec.coplanar,
            RelationKind::Concentric => &mut rec.concentric,
            RelationKind::Symmetric => &mut rec.symmetric,
        };
        let before = list.len();
        list.retain(|&q| q != key);
        if list.len() == before {
            return Err(not_recorded);
        }
        Ok(())
    }
}
