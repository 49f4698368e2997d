//! Mirrored strokes (issue 19's mirror plane): a `sculpt_stroke` with a
//! `mirror` plane moves a second brush along the path's mirror image, so a
//! stroke on one side of a symmetric model shapes both sides alike.

use glam::{DQuat, DVec3};

use super::tests::{assert_undo_redo_replay, create_op, sample, settings};
use super::warp::Warp;
use super::{BrushShape, SculptStroke};
use crate::doc::{Edit, LogError, ObjectId, Op, OpError, OpLog};
use crate::math::MirrorPlane;
use crate::mesh::{validate, TriMesh, ValidationSettings};

/// The mirror plane z = 0 through the sphere's centre: the base sphere is
/// symmetric across it, so the mirrored result must be too, point by point.
/// (That a frame's mirror image is `M·o·P`, which matters for planes
/// oblique to the brush, is checked in `math::mirror`.)
fn plane() -> MirrorPlane {
    MirrorPlane::new(DVec3::ZERO, DVec3::Z).unwrap()
}

fn normal() -> DVec3 {
    DVec3::from_array(plane().normal)
}

/// A twisting pull outwards on the sphere's side the plane's normal points
/// to, with a box brush (not round: its frame's mirror image matters),
/// optionally mirrored.
fn pull(mirror: Option<MirrorPlane>) -> Op {
    let mirror = mirror.map(Box::new);
    let n = normal();
    let side = n.any_orthonormal_vector();
    Op::SculptStroke(Edit::new(
        ObjectId(1),
        SculptStroke {
            settings: settings(
                BrushShape::Box {
                    half_extents: [0.12, 0.2, 0.08],
                },
                0.25,
                Warp::Drag,
            ),
            samples: (0..8)
                .map(|i| {
                    let t = i as f64 / 7.0;
                    let q = DQuat::from_rotation_z(0.6 * t) * DQuat::from_rotation_x(0.3);
                    let at = n * (0.95 + 0.3 * t) + side * (0.2 + 0.1 * t);
                    sample(at.to_array(), q, 1.0)
                })
                .collect(),
            mirror,
        },
    ))
}

fn mesh_after(ops: &[Op]) -> TriMesh {
    let mut log = OpLog::new();
    log.apply(create_op(0.1)).unwrap();
    for op in ops {
        log.apply(op.clone()).unwrap();
    }
    (*log.document().get(ObjectId(1)).unwrap().mesh).clone()
}

/// How far the surface reaches along the normal and against it.
fn reach(m: &TriMesh) -> (f64, f64) {
    let n = normal();
    m.positions
        .iter()
        .map(|p| DVec3::from_array(*p).dot(n))
        .fold((f64::NEG_INFINITY, f64::NEG_INFINITY), |(a, b), d| {
            (a.max(d), b.max(-d))
        })
}

#[test]
fn a_mirrored_stroke_shapes_both_sides_alike() {
    let base = mesh_after(&[]);
    let one = mesh_after(&[pull(None)]);
    let both = mesh_after(&[pull(Some(plane()))]);
    for m in [&one, &both] {
        let r = validate(m, &ValidationSettings::default());
        assert!(r.is_closed_manifold(), "{}", r.problems());
    }
    // The plain stroke pulls one side out and leaves the other a sphere;
    // the mirrored one pulls both out as far.
    let (out, back) = reach(&one);
    assert!(out > 1.15, "pulled out to {out}");
    assert!(back < 1.01, "the other side reaches {back}");
    let (out2, back2) = reach(&both);
    println!("single stroke reaches {out:.4} / {back:.4}, mirrored {out2:.4} / {back2:.4}");
    assert!((out2 - out).abs() < 1e-3 && (back2 - out).abs() < 1e-3);
    // Point by point: every moved vertex's mirror image is on the surface
    // too (the two brushes refine their sides in different orders, so
    // the vertices may differ, not the surface).
    let surface = crate::sdf::mesh_sdf::MeshDistance::new(&both, DVec3::ZERO).unwrap();
    let moved: Vec<DVec3> = both
        .positions
        .iter()
        .map(|p| DVec3::from_array(*p))
        .filter(|p| p.length() > 1.01)
        .collect();
    assert!(moved.len() > 40, "{} moved vertices", moved.len());
    let far = moved
        .iter()
        .map(|p| surface.signed_distance(plane().point(*p)).abs())
        .fold(0.0, f64::max);
    println!(
        "{} moved vertices, farthest mirror image {far:.2e} off the surface",
        moved.len()
    );
    assert!(
        far < 2e-3,
        "a moved vertex's mirror image is {far} off the surface"
    );
    // Twice the single stroke's added volume.
    let v0 = base.signed_volume();
    let (d1, d2) = (one.signed_volume() - v0, both.signed_volume() - v0);
    println!("added volume: single {d1:.5}, mirrored {d2:.5}");
    assert!(d1 > 0.005);
    assert!(
        (d2 / d1 - 2.0).abs() < 0.05,
        "mirrored adds {d2}, single {d1}"
    );
}

#[test]
fn a_mirrored_stroke_undoes_and_replays_bit_identically() {
    let mut log = OpLog::new();
    log.apply(create_op(0.12)).unwrap();
    let op = pull(Some(plane()));
    let text = serde_json::to_string(&op).unwrap();
    assert!(text.contains("\"mirror\""), "{text}");
    // Without a plane the op's JSON is what it was before mirrors.
    assert!(!serde_json::to_string(&pull(None))
        .unwrap()
        .contains("mirror"));
    assert_undo_redo_replay(&mut log, &[op]);
}

#[test]
fn a_bad_mirror_plane_is_a_typed_error_and_changes_nothing() {
    let mut log = OpLog::new();
    log.apply(create_op(0.2)).unwrap();
    let before = log.document().content_hash();
    for plane in [
        MirrorPlane {
            point: [0.0; 3],
            normal: [0.0; 3],
        },
        MirrorPlane {
            point: [f64::NAN, 0.0, 0.0],
            normal: [1.0, 0.0, 0.0],
        },
    ] {
        let err = log.apply(pull(Some(plane))).unwrap_err();
        assert!(matches!(&err, LogError::Op(OpError::Sculpt(_))), "{err:?}");
        assert!(err.to_string().contains("mirror plane"), "{err}");
        assert_eq!(log.document().content_hash(), before);
    }
}
