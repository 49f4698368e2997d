//! The assembly edits (`gc_add_child`, `gc_copy`, `gc_transform_part`,
//! `gc_edit_part`): plain values with every parameter explicit, and how
//! each changes a [`GcAssembly`]. The document applies them to a copy of
//! the assembly and stores it only when the whole change (propagation and
//! union included) succeeded.

use glam::{DAffine3, DQuat, DVec3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::junction::bury_part;
use super::structure::{end_radius, RelationKind};
use super::{
    anchor_frame, check_relations, descendants_bfs, ensure_recorded, mirror_gc, mirror_plane,
    project_to_surface, propagate_edit, reattach_descendants, record_new_part, reflect,
    symmetry_twins, transform_gc, Anchor, AssemblyError, Attachment,
};
use crate::gc::{
    build_gc, Gc, GcAssembly, GcError, GcPart, PartId, Resolution, SectionIndex, SectionSpec,
    ShapeType,
};
use crate::math::fm::DetMath as _;
use crate::nurbs::NurbsSurface;

fn default_tolerance() -> f64 {
    1e-4
}

fn default_shape() -> ShapeType {
    ShapeType::Solid
}

fn identity_rotation() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

fn check_part(asm: &GcAssembly, part: PartId) -> Result<(), AssemblyError> {
    let part = part.0;
    if part < asm.parts.len() {
        Ok(())
    } else {
        Err(GcError::BadPart {
            index: part,
            count: asm.parts.len(),
        }
        .into())
    }
}

fn positive(what: &'static str, x: f64) -> Result<(), AssemblyError> {
    if x.is_nan() || x.is_infinite() {
        Err(AssemblyError::NonFinite(what))
    } else if x > 0.0 {
        Ok(())
    } else {
        Err(AssemblyError::BadSize { what, value: x })
    }
}

fn rigid(translate: DVec3, rotate: [f64; 4]) -> Result<DAffine3, AssemblyError> {
    if !translate.is_finite() {
        return Err(AssemblyError::NonFinite("translate"));
    }
    if rotate.iter().any(|x| !x.is_finite()) {
        return Err(AssemblyError::NonFinite("rotate"));
    }
    let q = DQuat::from_array(rotate);
    let len = q.length();
    if !(len > 1e-12) {
        return Err(AssemblyError::ZeroRotation);
    }
    Ok(DAffine3::from_rotation_translation(q / len, translate))
}

/// Where a child's spine ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ChildEnd {
    /// The end is free (a spout, a leg).
    Free,
    /// The end lands on the parent too (a handle).
    Parent,
}

/// Create a child GC starting on part `parent`'s side surface at the
/// picked point `at`. Its spine is sketched in the plane through `at`
/// spanned by the surface normal `n` and the parent's spine tangent `t`
/// (made perpendicular to `n`): spine point `[a, b]` is `at + a n + b t`,
/// and the spine plane normal is `n x t`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcAddChild {
    /// The parent part.
    pub parent: PartId,
    /// The picked point, on the parent's side surface.
    #[schemars(with = "[f64; 3]", extend("x-unit" = "m"))]
    pub at: DVec3,
    /// How far `at` may be from the surface.
    #[serde(default = "default_tolerance")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub tolerance: f64,
    /// Spine points in the sketch plane's `(n, t)` coordinates about
    /// `at` (at least 2; the first may lie inside the parent).
    #[schemars(extend("x-unit" = "m"))]
    pub spine: Vec<[f64; 2]>,
    /// Whether the spine's end is free or lands on the parent.
    pub end: ChildEnd,
    /// For `end = parent`: how far the last spine point may be from the
    /// parent's surface (its projection there becomes the end anchor).
    #[serde(default = "default_tolerance")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub end_tolerance: f64,
    /// Key sections, `v` in `[0, 1]` along the spine (2 to 256: see
    /// `gc::budget`).
    #[schemars(length(min = 2, max = 256))]
    pub sections: Vec<SectionSpec>,
    /// Shape type.
    #[serde(default = "default_shape")]
    pub shape: ShapeType,
    /// Mesh resolution.
    #[serde(default)]
    pub resolution: Resolution,
}

impl GcAddChild {
    /// Adds the child part to `asm`.
    pub fn apply_to(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        let part = self.build(asm)?;
        ensure_recorded(asm);
        asm.parts.push(part);
        record_new_part(asm, asm.parts.len() - 1, None);
        Ok(())
    }

    /// The child part this op adds to `asm`.
    pub fn build(&self, asm: &GcAssembly) -> Result<GcPart, AssemblyError> {
        check_part(asm, self.parent)?;
        if !self.at.is_finite() {
            return Err(AssemblyError::NonFinite("picked point"));
        }
        positive("tolerance", self.tolerance)?;
        positive("end tolerance", self.end_tolerance)?;
        if self.spine.len() < 2 {
            return Err(AssemblyError::TooFewSpinePoints(self.spine.len()));
        }
        if self.spine.iter().flatten().any(|x| !x.is_finite()) {
            return Err(AssemblyError::NonFinite("spine"));
        }
        let parent = &asm.parts[self.parent.0].gc;
        let surf = parent.surface()?;
        let proj = project_to_surface(&surf, self.at);
        if !(proj.distance <= self.tolerance) {
            return Err(AssemblyError::OffSurface {
                distance: proj.distance,
                tolerance: self.tolerance,
            });
        }
        let frame = anchor_frame(parent, &surf, proj.anchor)?;
        let points: Vec<DVec3> = self
            .spine
            .iter()
            .map(|p| frame.transform_point3(DVec3::new(p[0], p[1], 0.0)))
            .collect();
        let gc = build_gc(
            &points,
            frame.matrix3.z_axis,
            &self.sections,
            self.shape,
            self.resolution,
        )?;
        let end = match self.end {
            ChildEnd::Free => None,
            ChildEnd::Parent => {
                let last = gc.spine.curve.point(gc.spine.curve.domain().1);
                let pe = project_to_surface(&surf, last);
                if !(pe.distance <= self.end_tolerance) {
                    return Err(AssemblyError::EndOffSurface {
                        distance: pe.distance,
                        tolerance: self.end_tolerance,
                    });
                }
                Some(pe.anchor)
            }
        };
        Ok(GcPart {
            gc,
            parent: Some(self.parent.0),
            attach: Some(Attachment {
                start: proj.anchor,
                end,
            }),
        })
    }
}

/// Copy part `part` with its descendants (an instance): mirrored about
/// its parent's spine plane when `mirror` (a root about its own), then
/// rotated by `rotate` and moved by `translate`. The copy keeps the
/// parent; its anchor is re-found by projecting the moved anchor point on
/// the parent's surface, which must be within `tolerance`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcCopy {
    /// The part to copy.
    pub part: PartId,
    /// Mirror about the parent's spine plane first.
    #[serde(default)]
    pub mirror: bool,
    /// Translation applied after the mirror and rotation.
    #[serde(default)]
    #[schemars(with = "[f64; 3]", extend("x-unit" = "m"))]
    pub translate: DVec3,
    /// Rotation quaternion `[x, y, z, w]` (normalized here).
    #[serde(default = "identity_rotation")]
    pub rotate: [f64; 4],
    /// How far a moved anchor may be from its parent's surface.
    #[serde(default = "default_tolerance")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub tolerance: f64,
}

fn reanchor(
    old_parent: &Gc,
    new_parent: &Gc,
    anchor: Anchor,
    map: &dyn Fn(DVec3) -> DVec3,
    tolerance: f64,
) -> Result<Anchor, AssemblyError> {
    let p = map(old_parent.surface()?.point(anchor.u, anchor.v));
    project_within(&new_parent.surface()?, p, tolerance)
}

fn reanchor_attachment(
    att: Attachment,
    old_parent: &Gc,
    new_parent: &Gc,
    map: &dyn Fn(DVec3) -> DVec3,
    tolerance: f64,
) -> Result<Attachment, AssemblyError> {
    Ok(Attachment {
        start: reanchor(old_parent, new_parent, att.start, map, tolerance)?,
        end: match att.end {
            Some(e) => Some(reanchor(old_parent, new_parent, e, map, tolerance)?),
            None => None,
        },
    })
}

impl GcCopy {
    /// Applies the op to `asm`: the subtree is copied (mirrored about the
    /// parent's spine plane when asked), then the copy is moved by
    /// `rotate` and `translate` the way [`GcTransformPart`] moves a part:
    /// a child slides over its parent to where it was dropped and turns
    /// with the surface normal there. The copy is recorded as its
    /// source's twin only when it was mirrored (and does not lie on it).
    /// A refusal naming a relation of the copy names the part it copies
    /// (the copy does not exist).
    pub fn apply_to(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        check_part(asm, self.part)?;
        let base = asm.parts.len();
        let mut subtree = vec![self.part.0];
        subtree.extend(descendants_bfs(asm, &[self.part.0]));
        self.copy_into(asm).map_err(|e| match e {
            AssemblyError::RelationBroken { relation, parts } => {
                let source = |i: usize| i.checked_sub(base).map_or(i, |k| subtree[k]);
                let (a, b) = (source(parts.0), source(parts.1));
                let parts = if relation == RelationKind::Connected {
                    (a, b)
                } else {
                    (a.min(b), a.max(b))
                };
                AssemblyError::RelationBroken { relation, parts }
            }
            other => other,
        })
    }

    fn copy_into(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        let part = self.part.0;
        positive("tolerance", self.tolerance)?;
        let r = rigid(self.translate, self.rotate)?;
        ensure_recorded(asm);
        let parent = asm.parts[part].parent;
        let (o, n) = mirror_plane(&asm.parts[parent.unwrap_or(part)].gc);
        let mirror = self.mirror;
        let map = move |p: DVec3| if mirror { reflect(p, o, n) } else { p };
        let mut subtree = vec![part];
        subtree.extend(descendants_bfs(asm, &[part]));
        let base = asm.parts.len();
        let new_index = |i: usize| subtree.iter().position(|&s| s == i).map(|k| base + k);
        for &i in &subtree {
            let src = asm.parts[i].clone();
            let gc = if mirror {
                mirror_gc(&src.gc, o, n)
            } else {
                src.gc.clone()
            };
            gc.validate()?;
            let new_parent = src.parent.map(|p| new_index(p).unwrap_or(p));
            let attach = match (src.parent, new_parent, src.attach) {
                (Some(p), Some(np), Some(att)) if mirror => {
                    let (old_pg, new_pg) = (&asm.parts[p].gc, &asm.parts[np].gc);
                    Some(reanchor_attachment(
                        att,
                        old_pg,
                        new_pg,
                        &map,
                        self.tolerance,
                    )?)
                }
                (Some(_), Some(_), Some(att)) => Some(att),
                _ => None,
            };
            asm.parts.push(GcPart {
                gc,
                parent: new_parent,
                attach,
            });
        }
        // Now move the copy as a transform would (its descendants follow).
        let placed = asm.clone();
        let (gc, attach) = slide(&placed, base, &r, self.tolerance)?;
        asm.parts[base].gc = gc;
        asm.parts[base].attach = attach;
        bury_part(&placed, asm, base, false)?;
        reattach_descendants(&placed, asm, &[base])?;
        for (k, &i) in subtree.iter().enumerate() {
            let source = (k == 0).then_some((i, mirror));
            record_new_part(asm, base + k, source);
        }
        check_relations(asm)
    }
}

/// Part `i` of `asm` moved by `m`. A root moves rigidly. A child slides:
/// its anchor point moves by `m` and is projected back on the parent
/// (within `tolerance`), the part follows the anchor frame `(n, t, n x t)`
/// from the old anchor to the new one (so it re-orients with the surface
/// normal and keeps its bearing to the parent's spine), and spins about
/// the normal by the turn `m`'s rotation gives it ([`own_turn`]); a
/// handle's end then lands on its own slid anchor (rotated and scaled
/// about its start, as in [`reattach_descendants`]).
///
/// The rest of `m`'s rotation is not applied to the part a second time:
/// it already moved the anchor, and the frame carries the part with it
/// (a handle turned half a turn about a mug's axis is the turned handle,
/// not turned twice into the body).
fn slide(
    asm: &GcAssembly,
    i: usize,
    m: &DAffine3,
    tolerance: f64,
) -> Result<(Gc, Option<Attachment>), AssemblyError> {
    let src = &asm.parts[i];
    let (Some(p), Some(att)) = (src.parent, src.attach) else {
        return Ok((transform_gc(&src.gc, m), src.attach));
    };
    let pg = &asm.parts[p].gc;
    let surf = pg.surface()?;
    let p0 = surf.point(att.start.u, att.start.v);
    let start = project_within(&surf, m.transform_point3(p0), tolerance)?;
    let f_old = anchor_frame(pg, &surf, att.start)?;
    let f_new = anchor_frame(pg, &surf, start)?;
    let axis = pg.spine.curve.derivatives(att.start.v, 1)[1];
    let motion = f_new * own_turn(&f_old, axis, m) * f_old.inverse();
    let mut gc = transform_gc(&src.gc, &motion);
    let end = match att.end {
        None => None,
        Some(e) => {
            let (a, b) = src.gc.spine.curve.domain();
            let e_old = src.gc.spine.curve.point(b);
            let pe = surf.point(e.u, e.v);
            let proj = project_to_surface(&surf, m.transform_point3(pe));
            if !(proj.distance <= end_radius(&src.gc, false)) {
                return Err(AssemblyError::RelationBroken {
                    relation: RelationKind::Connected,
                    parts: (i, p),
                });
            }
            let local = anchor_frame(pg, &surf, e)?
                .inverse()
                .transform_point3(e_old);
            let target = anchor_frame(pg, &surf, proj.anchor)?.transform_point3(local);
            let s = gc.spine.curve.point(a);
            let e_r = motion.transform_point3(e_old);
            let sim = super::propagate::similarity_about(s, e_r - s, target - s);
            gc = transform_gc(&gc, &sim);
            Some(proj.anchor)
        }
    };
    gc.validate()?;
    Ok((gc, Some(Attachment { start, end })))
}

/// The turn about the surface normal that `m`'s rotation gives a child
/// anchored at frame `f_old` (whose `t` is the parent's spine tangent
/// `axis` made perpendicular to the normal), as a rotation about the
/// frame's x axis: the angle, about the turned normal, from the spine
/// tangent made perpendicular to the turned normal to the turned `t`.
///
/// It reads the part's bearing to the parent's spine after `m` as the
/// frame reads it everywhere, so (issue 33):
/// - no rotation is no turn, whatever the slide;
/// - a spin by `phi` about the normal is a turn by `phi`, whatever the
///   slide;
/// - a turn about a straight spine leaves the spine tangent where it was
///   and is no turn (the frame's own move carries the part: on a body of
///   revolution that is the turned part, not turned twice);
/// - it is continuous in `m` (a spin of 1e-9 is a turn of 1e-9), except
///   where `m` turns the normal onto the spine tangent, which leaves no
///   bearing to read: there it counts as no turn.
///
/// It used to be the twist of `f_newᵀ m f_old`: that is the least
/// rotation back onto the new normal, which differs from following the
/// frames by the frames' own turn about the normal between the two
/// anchors (first order in the slide on a bulged body), so the smallest
/// spin jumped the part by that turn, where no rotation at all took none.
/// No trigonometry: the rotation is built from the cosine and sine (same
/// bits everywhere).
fn own_turn(f_old: &DAffine3, axis: DVec3, m: &DAffine3) -> DAffine3 {
    // No rotation is exactly no turn (rounding of fᵀf would leave ~1e-16).
    if m.matrix3 == glam::DMat3::IDENTITY {
        return DAffine3::IDENTITY;
    }
    let to_local = f_old.matrix3.transpose();
    let turned = to_local * m.matrix3 * f_old.matrix3;
    let (n, t) = (turned.x_axis, turned.y_axis);
    let a = to_local * axis;
    let reference = a - n * n.dot(a);
    let (c, s) = (reference.dot(t), reference.cross(t).dot(n));
    let len = c.fhypot(s);
    if !(len > 1e-12 * a.length()) {
        return DAffine3::IDENTITY;
    }
    let (c, s) = (c / len, s / len);
    DAffine3::from_mat3(glam::DMat3::from_cols(
        DVec3::X,
        DVec3::new(0.0, c, s),
        DVec3::new(0.0, -s, c),
    ))
}

/// The anchor of `p` on `surf`, refused as off the surface when `p` is
/// farther from it than `tolerance`.
fn project_within(surf: &NurbsSurface, p: DVec3, tolerance: f64) -> Result<Anchor, AssemblyError> {
    let proj = project_to_surface(surf, p);
    if !(proj.distance <= tolerance) {
        return Err(AssemblyError::OffSurface {
            distance: proj.distance,
            tolerance,
        });
    }
    Ok(proj.anchor)
}

/// Move part `part` rigidly (rotation `rotate`, then `translate`); its
/// symmetry twins get the mirrored motion and every descendant follows.
/// A part with a parent must stay on it: its moved anchor point is
/// projected on the parent's surface and must be within `tolerance`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcTransformPart {
    /// The part to move.
    pub part: PartId,
    /// Translation.
    #[serde(default)]
    #[schemars(with = "[f64; 3]", extend("x-unit" = "m"))]
    pub translate: DVec3,
    /// Rotation quaternion `[x, y, z, w]` (normalized here).
    #[serde(default = "identity_rotation")]
    pub rotate: [f64; 4],
    /// How far a moved anchor may be from its parent's surface.
    #[serde(default = "default_tolerance")]
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub tolerance: f64,
}

impl GcTransformPart {
    /// Applies the op to `asm`: the part slides (a child over its parent,
    /// re-oriented with the surface normal), its recorded
    /// twins get the mirrored motion, the descendants follow, and every
    /// recorded relation is checked.
    pub fn apply_to(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        check_part(asm, self.part)?;
        let part = self.part.0;
        positive("tolerance", self.tolerance)?;
        let r = rigid(self.translate, self.rotate)?;
        ensure_recorded(asm);
        let old = asm.clone();
        let twins = symmetry_twins(&old, part);
        let mut moved = vec![(part, r)];
        if let Some(p) = old.parts[part].parent {
            let (o, n) = mirror_plane(&old.parts[p].gc);
            let m = DAffine3::from_translation(o)
                * DAffine3::from_mat3(glam::DMat3::IDENTITY - 2.0 * outer(n))
                * DAffine3::from_translation(-o);
            let mr = m * r * m;
            moved.extend(twins.iter().map(|&t| (t, mr)));
        }
        for &(i, m) in &moved {
            let (gc, attach) = slide(&old, i, &m, self.tolerance)?;
            asm.parts[i].gc = gc;
            asm.parts[i].attach = attach;
            bury_part(&old, asm, i, false)?;
        }
        let roots: Vec<usize> = moved.iter().map(|(i, _)| *i).collect();
        reattach_descendants(&old, asm, &roots)?;
        check_relations(asm)
    }
}

fn outer(n: DVec3) -> glam::DMat3 {
    glam::DMat3::from_cols(n * n.x, n * n.y, n * n.z)
}

/// A §3.2 edit of one part, as [`GcEditPart`] propagates it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "edit", rename_all = "snake_case", deny_unknown_fields)]
pub enum PartEdit {
    /// Move key point `section` to `to` (in the spine plane).
    Bend {
        /// Section index.
        section: SectionIndex,
        /// New key point.
        #[schemars(with = "[f64; 3]", extend("x-unit" = "m"))]
        to: DVec3,
    },
    /// Scale section `section` by `factor`.
    Resize {
        /// Section index.
        section: SectionIndex,
        /// Factor (> 0).
        factor: f64,
    },
    /// Move section `section` to spine parameter `v`.
    Shift {
        /// Section index.
        section: SectionIndex,
        /// New parameter.
        v: f64,
    },
    /// Twist interior section `section` by `angle` radians.
    Twist {
        /// Section index.
        section: SectionIndex,
        /// Angle.
        angle: f64,
    },
}

/// Structure-aware edit: `edit` is applied to part `part`, mirrored to
/// its symmetry twins (same parent, mirrored about the parent's spine
/// plane), and then every descendant of the edited parts is re-placed on
/// its parent's new surface, breadth-first.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GcEditPart {
    /// The part edited.
    pub part: PartId,
    /// The edit.
    pub edit: PartEdit,
}

impl GcEditPart {
    /// Applies the op to `asm` ([`propagate_edit`]).
    pub fn apply_to(&self, asm: &mut GcAssembly) -> Result<(), AssemblyError> {
        check_part(asm, self.part)?;
        propagate_edit(asm, self)
    }
}
