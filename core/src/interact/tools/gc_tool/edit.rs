//! The edits of a picked element (paper §4 "Editing a generalized
//! cylinder"): what a FIST motion, an OPEN hold or a PINCH becomes.
//!
//! - A key point dragged by FIST bends the spine: the motion projected on
//!   the spine plane moves the key point (`gc_edit_part` bend, so the
//!   edit propagates to symmetric twins and children).
//! - A section dragged by FIST: the motion `d` is split at the picked
//!   point `P` into the radial part (from the section's centre through
//!   `P`, in the section plane), the normal part (the spine tangent) and
//!   the tangent part (around the section). The largest one decides the
//!   edit: radial resizes by `(ρ + d_r) / ρ` (`ρ = |P - centre|`), normal
//!   shifts the section along the spine by `d_n` of arc length (clamped
//!   between its neighbours), tangent twists by `d_t / ρ` radians.
//! - A part dragged by FIST moves rigidly (`gc_transform_part`); a child
//!   slides on its parent: the translation takes its anchor to the
//!   parent-surface point nearest the moved anchor.
//! - An OPEN hold deletes the section under the ray, or inserts one at the
//!   surface point under it.
//! - A PINCH on an end section sets the shape type: closed pinch closes
//!   that end, open pinch opens it, with shell thickness from the finger
//!   gap. Opening the free end of a solid child makes a tube (its start
//!   is buried in the parent).

use crate::assembly::{GcEditPart, GcTransformPart, PartEdit};
use crate::doc::{Edit, ObjectId, Op};
use crate::gc::{
    ClosedEnd, GcAssembly, GcDeleteSection, GcInsertSection, GcSetShape, PartId, SectionIndex,
    ShapeType,
};
use crate::math::DVec3;

use super::target::GeoCache;
use super::GcTarget;
use super::GcToolSettings;

/// The op a FIST drag of `target` by `d` (model space) becomes.
pub(super) fn drag_op(target: &GcTarget, d: DVec3, geo: &GeoCache) -> Option<Op> {
    if !d.is_finite() {
        return None;
    }
    match *target {
        GcTarget::KeyPoint {
            id,
            part,
            section,
            point,
        } => {
            let n = geo.assembly(id)?.parts.get(part)?.gc.spine.plane_normal;
            let to = point + d - n * d.dot(n);
            Some(Op::GcEditPart(Edit::new(
                id,
                GcEditPart {
                    part: PartId(part),
                    edit: PartEdit::Bend {
                        section: SectionIndex(section),
                        to,
                    },
                },
            )))
        }
        GcTarget::Section {
            id,
            part,
            section,
            point,
        } => section_drag(id, part, section, point, d, geo),
        GcTarget::Surface { id, part, .. } => move_part(id, part, d, geo),
        GcTarget::Empty { .. } => None,
    }
}

fn section_drag(
    id: ObjectId,
    part: usize,
    section: usize,
    point: DVec3,
    d: DVec3,
    geo: &GeoCache,
) -> Option<Op> {
    let gc = &geo.assembly(id)?.parts.get(part)?.gc;
    let f = geo.part(id, part)?.frames.get(section)?;
    let off = point - f.origin;
    let radial = off - f.tangent * off.dot(f.tangent);
    let rho = radial.length();
    let r = radial.try_normalize()?;
    let tang = f.tangent.cross(r);
    let (dr, dn, dt) = (d.dot(r), d.dot(f.tangent), d.dot(tang));
    let edit = if dr.abs() >= dn.abs() && dr.abs() >= dt.abs() {
        PartEdit::Resize {
            section: SectionIndex(section),
            factor: ((rho + dr) / rho).max(0.05),
        }
    } else if dn.abs() >= dt.abs() {
        let (a, b) = gc.spine.curve.domain();
        let k = gc.sections.len();
        let v = gc.sections[section].v;
        let speed = gc.spine.curve.derivatives(v, 1)[1].length().max(1e-9);
        let lo = if section == 0 {
            a
        } else {
            gc.sections[section - 1].v
        };
        let hi = if section + 1 == k {
            b
        } else {
            gc.sections[section + 1].v
        };
        let margin = 0.02 * (hi - lo);
        let lo = if section == 0 { lo } else { lo + margin };
        let hi = if section + 1 == k { hi } else { hi - margin };
        PartEdit::Shift {
            section: SectionIndex(section),
            v: (v + dn / speed).clamp(lo, hi),
        }
    } else {
        PartEdit::Twist {
            section: SectionIndex(section),
            angle: dt / rho,
        }
    };
    Some(Op::GcEditPart(Edit::new(
        id,
        GcEditPart {
            part: PartId(part),
            edit,
        },
    )))
}

fn move_part(id: ObjectId, part: usize, d: DVec3, geo: &GeoCache) -> Option<Op> {
    let asm = geo.assembly(id)?;
    let p = asm.parts.get(part)?;
    let translate = match (p.parent, p.attach) {
        (Some(parent), Some(att)) => {
            let surf = &geo.part(id, parent)?.surface;
            let anchor = surf.point(att.start.u, att.start.v);
            crate::assembly::project_to_surface(surf, anchor + d).point - anchor
        }
        _ => d,
    };
    Some(Op::GcTransformPart(Edit::new(
        id,
        GcTransformPart {
            part: PartId(part),
            translate,
            rotate: [0.0, 0.0, 0.0, 1.0],
            tolerance: 1e-3,
        },
    )))
}

/// The op an OPEN hold on `target` becomes.
pub(super) fn hold_op(target: &GcTarget) -> Option<Op> {
    match *target {
        GcTarget::Section {
            id, part, section, ..
        } => Some(Op::GcDeleteSection(Edit::new(
            id,
            GcDeleteSection {
                part: PartId(part),
                section: SectionIndex(section),
            },
        ))),
        GcTarget::Surface { id, part, v, .. } => Some(Op::GcInsertSection(Edit::new(
            id,
            GcInsertSection {
                part: PartId(part),
                v,
            },
        ))),
        _ => None,
    }
}

/// Which end a section is, if it is the first or last.
pub(super) fn end_of(asm: &GcAssembly, part: usize, section: usize) -> Option<ClosedEnd> {
    let k = asm.parts.get(part)?.gc.sections.len();
    if section == 0 {
        Some(ClosedEnd::Start)
    } else if section + 1 == k {
        Some(ClosedEnd::End)
    } else {
        None
    }
}

fn other(e: ClosedEnd) -> ClosedEnd {
    match e {
        ClosedEnd::Start => ClosedEnd::End,
        ClosedEnd::End => ClosedEnd::Start,
    }
}

/// The shape type after a pinch at end `end`: closed (`gap = None`) or
/// open with finger gap `gap` (metres). `child` says the part is a child,
/// whose start end is buried in its parent: opening a solid child's free
/// end makes a tube (shell), not a container, since a cap at the buried
/// start would seal the tube's inside off where it crosses a hollow
/// parent's wall (a void no printer can empty).
pub(super) fn pinch_shape(
    current: ShapeType,
    end: ClosedEnd,
    gap: Option<f64>,
    child: bool,
    s: &GcToolSettings,
) -> ShapeType {
    match gap {
        None => match current {
            ShapeType::Solid => ShapeType::Solid,
            ShapeType::Shell { thickness } => ShapeType::Container {
                thickness,
                closed_end: end,
            },
            ShapeType::Container { closed_end, .. } => {
                if closed_end == end {
                    current
                } else {
                    ShapeType::Solid
                }
            }
        },
        Some(g) => {
            let (lo, hi) = s.thickness_range;
            let thickness = (g * s.thickness_per_gap).clamp(lo, hi);
            match current {
                ShapeType::Solid if child && end == ClosedEnd::End => {
                    ShapeType::Shell { thickness }
                }
                ShapeType::Solid => ShapeType::Container {
                    thickness,
                    closed_end: other(end),
                },
                ShapeType::Shell { .. } => ShapeType::Shell { thickness },
                ShapeType::Container { closed_end, .. } => {
                    if closed_end == end {
                        ShapeType::Shell { thickness }
                    } else {
                        ShapeType::Container {
                            thickness,
                            closed_end,
                        }
                    }
                }
            }
        }
    }
}

/// The op setting `shape` on a part, if it changes anything.
pub(super) fn shape_op(
    id: ObjectId,
    part: usize,
    shape: ShapeType,
    asm: &GcAssembly,
) -> Option<Op> {
    (asm.parts.get(part)?.gc.shape != shape).then_some(Op::GcSetShape(Edit::new(
        id,
        GcSetShape {
            part: PartId(part),
            shape,
        },
    )))
}
