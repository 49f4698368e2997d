//! Snapping a dragged object to the other objects of the document (issue
//! 19, "precision"): to their centres, to the axis lines through their
//! centres, and onto their surfaces. Per drag, after the grid and angle
//! snapping of [`crate::interact::palette::Snap`]; the result says what it snapped
//! to, so the readout can show it.
//!
//! Choices (what a user placing parts on a desk expects; Open Blocks and
//! Gravity Sketch snap in the same three ways):
//! - **Centre**: the dragged object's bounding-box centre within
//!   [`SNAP_TOLERANCE`] of another's goes onto it (concentric parts).
//! - **Surface**: the dragged object's lowest point (bounding-box bottom
//!   centre, model +Z is up) within the tolerance above or below another
//!   object's surface, found by a ray straight down through it, is set
//!   onto that surface (a shade resting on a stand, a knob on a lid).
//! - **Axis**: the centre within the tolerance of a line through another
//!   object's centre along a model axis goes onto that line (aligned
//!   parts).
//!
//! The first of these that applies wins, nearest object first among
//! equals. Only bounding boxes and one ray per other object are used, so
//! the cost per frame is one pass over the other objects' boxes plus a
//! ray per object whose box is under the dragged one.

use crate::doc::{Document, ObjectId};
use crate::math::DVec3;

use super::pick::{ray_mesh, Ray};

/// How close (model metres) a dragged object must come to snap.
pub const SNAP_TOLERANCE: f64 = 0.02;

/// What a drag snapped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SnapKind {
    /// The other object's centre.
    Centre,
    /// Its surface, under the dragged object.
    Surface,
    /// The line through its centre along model axis `0..3` (x, y, z).
    Axis(usize),
}

/// A snap: the translation to add and what it is to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectSnap {
    /// The object snapped to.
    pub to: ObjectId,
    /// How.
    pub kind: SnapKind,
    /// The translation that makes it so (model space).
    pub offset: DVec3,
}

impl ObjectSnap {
    /// For the readout: "centre of #3", "surface of #3", "x axis of #3".
    pub fn label(&self) -> String {
        match self.kind {
            SnapKind::Centre => format!("centre of #{}", self.to.0),
            SnapKind::Surface => format!("surface of #{}", self.to.0),
            SnapKind::Axis(a) => format!("{} axis of #{}", ["x", "y", "z"][a.min(2)], self.to.0),
        }
    }
}

/// Where an object `dragged`, whose moved bounding box is `(lo, hi)`
/// (model space), snaps among the other objects of `doc`, if anywhere.
pub fn snap_to_objects(
    doc: &Document,
    dragged: ObjectId,
    (lo, hi): (DVec3, DVec3),
) -> Option<ObjectSnap> {
    let tol = SNAP_TOLERANCE;
    let centre = (lo + hi) * 0.5;
    let others: Vec<(ObjectId, (DVec3, DVec3))> = doc
        .objects()
        .filter(|(id, _)| *id != dragged)
        .filter_map(|(id, o)| Some((id, o.mesh.bbox()?)))
        .collect();
    let nearest = |cands: &mut Vec<(f64, ObjectSnap)>| {
        cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.to.0.cmp(&b.1.to.0)));
        cands.first().map(|c| c.1)
    };
    // Centres.
    let mut cands: Vec<(f64, ObjectSnap)> = others
        .iter()
        .map(|(id, (l, h))| ((*l + *h) * 0.5 - centre, *id))
        .filter(|(d, _)| d.length() <= tol)
        .map(|(d, to)| {
            let snap = ObjectSnap {
                to,
                kind: SnapKind::Centre,
                offset: d,
            };
            (d.length(), snap)
        })
        .collect();
    if let Some(s) = nearest(&mut cands) {
        return Some(s);
    }
    // Surfaces under the dragged object's bottom centre.
    let bottom = DVec3::new(centre.x, centre.y, lo.z);
    let ray = Ray {
        origin: bottom + DVec3::Z * tol,
        dir: DVec3::NEG_Z,
    };
    let mut cands: Vec<(f64, ObjectSnap)> = others
        .iter()
        .filter(|(_, (l, h))| {
            (l.x..=h.x).contains(&bottom.x)
                && (l.y..=h.y).contains(&bottom.y)
                && h.z >= bottom.z - tol
                && l.z <= bottom.z + tol
        })
        .filter_map(|(id, _)| {
            let o = doc.get(*id).ok()?;
            let (t, _) = ray_mesh(&ray, &o.mesh, 2.0 * tol)?;
            let d = t - tol;
            let snap = ObjectSnap {
                to: *id,
                kind: SnapKind::Surface,
                offset: DVec3::NEG_Z * d,
            };
            Some((d.abs(), snap))
        })
        .collect();
    if let Some(s) = nearest(&mut cands) {
        return Some(s);
    }
    // Axis lines through the other centres.
    let mut cands: Vec<(f64, ObjectSnap)> = Vec::new();
    for (id, (l, h)) in &others {
        let c = (*l + *h) * 0.5;
        for axis in 0..3 {
            let mut d = c - centre;
            d[axis] = 0.0;
            if d.length() <= tol {
                let snap = ObjectSnap {
                    to: *id,
                    kind: SnapKind::Axis(axis),
                    offset: d,
                };
                cands.push((d.length(), snap));
            }
        }
    }
    nearest(&mut cands)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::doc::{AddSolid, Op, OpLog};
    use crate::math::Transform;
    use crate::solid::SolidShape;

    /// A log with a unit-ish box on the desk (top at z = 0.1) and a small
    /// sphere far away.
    fn desk() -> (OpLog, ObjectId, ObjectId) {
        let mut log = OpLog::new();
        let add = |log: &mut OpLog, shape, at: [f64; 3]| {
            log.apply(Op::AddSolid(AddSolid {
                shape,
                transform: Transform {
                    translate: at,
                    ..Transform::IDENTITY
                },
                segments: 32,
            }))
            .unwrap()
            .created
            .unwrap()
        };
        let slab = add(
            &mut log,
            SolidShape::Box {
                size: [0.4, 0.4, 0.1],
            },
            [0.0, 0.0, 0.05],
        );
        let ball = add(
            &mut log,
            SolidShape::Sphere { radius: 0.05 },
            [1.0, 0.0, 0.3],
        );
        (log, slab, ball)
    }

    fn bbox_at(c: DVec3, half: f64) -> (DVec3, DVec3) {
        (c - DVec3::splat(half), c + DVec3::splat(half))
    }

    #[test]
    fn a_part_dropped_near_a_surface_rests_on_it() {
        let (log, slab, ball) = desk();
        let doc = log.document();
        // A 10 cm cube, 1.5 cm above the slab's top (z = 0.1).
        let c = DVec3::new(0.05, -0.1, 0.1 + 0.05 + 0.015);
        let s = snap_to_objects(doc, ball, bbox_at(c, 0.05)).expect("snaps");
        assert_eq!((s.to, s.kind), (slab, SnapKind::Surface), "{s:?}");
        let bottom = c.z - 0.05 + s.offset.z;
        assert!((bottom - 0.1).abs() < 1e-9, "bottom at {bottom}");
        assert_eq!((s.offset.x, s.offset.y), (0.0, 0.0));
        // Sunk 1 cm into it: lifted out onto it.
        let s = snap_to_objects(doc, ball, bbox_at(c - DVec3::Z * 0.025, 0.05)).unwrap();
        assert!(
            (c.z - 0.025 - 0.05 + s.offset.z - 0.1).abs() < 1e-9,
            "{s:?}"
        );
        // Too high: nothing (the ball is far away).
        assert_eq!(
            snap_to_objects(doc, ball, bbox_at(c + DVec3::Z * 0.03, 0.05)),
            None
        );
        assert_eq!(s.label(), format!("surface of #{}", slab.0));
    }

    #[test]
    fn centres_win_over_surfaces_and_axes_align() {
        let (log, slab, ball) = desk();
        let doc = log.document();
        // Near the ball's centre: onto it, exactly.
        let ball_c = DVec3::new(1.0, 0.0, 0.3);
        let near = ball_c + DVec3::new(0.01, -0.005, 0.008);
        let s = snap_to_objects(doc, slab, bbox_at(near, 0.02)).unwrap();
        assert_eq!((s.to, s.kind), (ball, SnapKind::Centre));
        assert!((near + s.offset - ball_c).length() < 1e-12);
        // 30 cm along x from it, 1 cm off the line: onto the x axis line.
        let off = ball_c + DVec3::new(-0.3, 0.01, -0.012);
        let s = snap_to_objects(doc, slab, bbox_at(off, 0.02)).unwrap();
        assert_eq!((s.to, s.kind), (ball, SnapKind::Axis(0)), "{s:?}");
        let on = off + s.offset;
        assert!((on.y - ball_c.y).abs() < 1e-12 && (on.z - ball_c.z).abs() < 1e-12);
        assert!((on.x - off.x).abs() < 1e-12, "moves only across the line");
        assert_eq!(s.label(), format!("x axis of #{}", ball.0));
        // Far from everything: no snap.
        assert_eq!(
            snap_to_objects(doc, slab, bbox_at(DVec3::new(0.5, 0.7, 0.9), 0.02)),
            None
        );
    }
}
