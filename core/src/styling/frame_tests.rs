//! The modeling frame (paper §5.4): strokes drawn in a moving frame, the
//! frame held by a hand, curves and patches carried by it.

use super::curve::{fit_curve, FitMode};
use super::frame::{mirror_in_frame, project_to_drawing_plane, stroke_in_frame, ModelingFrame};
use super::ngon_tests::{boundary_gap, prism};
use super::surface::SurfaceWeights;
use super::StylingError;
use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};
use crate::mesh::validate;

fn frame(t: f64) -> ModelingFrame {
    ModelingFrame::new(
        DVec3::new(0.2 * t, 1.0 - 0.1 * t, -0.3),
        DQuat::from_euler(glam::EulerRot::XYZ, 0.3 + t, -0.7 * t, 1.1 * t),
    )
}

#[test]
fn a_stroke_drawn_on_a_moving_frame_is_recovered_in_it() {
    // The off hand turns the frame while the stylus draws a circle on it:
    // the world samples are the circle carried by the frame of each instant.
    let count = 60;
    let local: Vec<DVec3> = (0..count)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / count as f64 * 0.9;
            DVec3::new(0.1 * a.fcos(), 0.1 * a.fsin(), 0.0)
        })
        .collect();
    let frames: Vec<ModelingFrame> = (0..count).map(|i| frame(i as f64 / 60.0)).collect();
    let world: Vec<[f64; 3]> = local
        .iter()
        .zip(&frames)
        .map(|(p, f)| f.affine().unwrap().transform_point3(*p).to_array())
        .collect();
    let back = stroke_in_frame(&world, &frames).unwrap();
    for (b, l) in back.iter().zip(&local) {
        assert!(DVec3::from_array(*b).distance(*l) < 1e-12);
    }
    // The world stroke itself is no circle (the frame turned by ~60°);
    // the curve fitted in the frame is.
    let c = fit_curve(&back, FitMode::Interpolate, None).unwrap();
    let (a, b) = c.domain();
    for i in 0..=50 {
        let p = c.point(a + (b - a) * i as f64 / 50.0);
        assert!(p.z.abs() < 1e-12 && (p.length() - 0.1).abs() < 2e-4, "{p}");
    }
    // One frame for the whole stroke works too; a count mismatch does not.
    let one = stroke_in_frame(&world, &frames[..1]).unwrap();
    assert_eq!(one.len(), count);
    assert!(matches!(
        stroke_in_frame(&world, &frames[..2]),
        Err(StylingError::BadParameter(_))
    ));
}

#[test]
fn a_held_frame_follows_the_hand_rigidly() {
    let held = frame(0.2);
    let grab = frame(0.5);
    let motion = ModelingFrame::new(DVec3::new(0.05, -0.02, 0.1), DQuat::from_rotation_y(0.4));
    // The hand moves by `motion` (in model space).
    let hand_now = {
        let m = motion.affine().unwrap() * grab.affine().unwrap();
        let (_, q, t) = m.to_scale_rotation_translation();
        ModelingFrame::new(t, q)
    };
    let now = ModelingFrame::follow(&held, &grab, &hand_now).unwrap();
    let p = DVec3::new(0.03, 0.01, -0.02);
    let before = held.affine().unwrap().transform_point3(p);
    let after = now.affine().unwrap().transform_point3(p);
    let want = motion.affine().unwrap().transform_point3(before);
    assert!(after.distance(want) < 1e-12, "{after} vs {want}");
    // Not moving the hand leaves the frame where it was.
    let still = ModelingFrame::follow(&held, &grab, &grab).unwrap();
    let q = still.affine().unwrap().transform_point3(p);
    assert!(q.distance(before) < 1e-12);
}

#[test]
fn curves_and_patches_drawn_in_a_frame_move_with_it() {
    // A hexagonal prism with a wavy cap, the cap pulled into a bump and a
    // side smoothed: its curves, patches and mesh are carried exactly.
    let mut net = prism(6, 0.1, 0.12, 0.015, 8);
    net.fill_all().unwrap();
    let w = SurfaceWeights { wb: 1.0, ws: 0.0 };
    let cap = net
        .patches
        .iter()
        .position(|p| p.pieces.len() == 6)
        .unwrap();
    for k in [0, cap] {
        let mut sys = net.surface_system(k, &w).unwrap();
        let base0 = net.patch_base_point(k, 0.5, 0.5).unwrap();
        let target = net.patch_point(k, 0.5, 0.5) + DVec3::new(0.0, 0.01, 0.02);
        let d0 = net.patches[k].disp.clone();
        net.patches[k].disp = sys.pull(&d0, 0.5, 0.5, base0, 1e4, &[target]).unwrap();
    }
    let (from, to) = (frame(0.1), frame(0.8));
    let m = from.motion_to(&to).unwrap();
    let moved = net.carried(&from, &to).unwrap();
    for k in 0..net.patches.len() {
        for (u, v) in [(0.5, 0.5), (0.3, 0.6), (0.7, 0.25)] {
            let want = m.transform_point3(net.patch_point(k, u, v));
            let got = moved.patch_point(k, u, v);
            assert!(got.distance(want) < 1e-12, "patch {k}: {got} vs {want}");
        }
    }
    for c in 0..net.curves.len() {
        let (a, b) = net.curve(c).unwrap().domain();
        let t = 0.37 * a + 0.63 * b;
        let want = m.transform_point3(net.curve(c).unwrap().point(t));
        assert!(moved.curve(c).unwrap().point(t).distance(want) < 1e-12);
    }
    assert!(moved.junction_gap() < 1e-9);
    assert!(boundary_gap(&moved) < 1e-9);
    let (m0, m1) = (net.mesh(), moved.mesh());
    assert_eq!(m0.triangles, m1.triangles);
    for (p, q) in m0.positions.iter().zip(&m1.positions) {
        let want = m.transform_point3(DVec3::from_array(*p));
        assert!(DVec3::from_array(*q).distance(want) < 1e-12);
    }
    let r = validate(&m1, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    assert!((m1.signed_volume() - m0.signed_volume()).abs() < 1e-12);
    // Carrying back restores the network to rounding.
    let back = moved.carried(&to, &from).unwrap();
    let d = back
        .patch_point(cap, 0.5, 0.5)
        .distance(net.patch_point(cap, 0.5, 0.5));
    assert!(d < 1e-12);
}

#[test]
fn drawing_plane_and_symmetry_plane() {
    let f = frame(0.3);
    let a = f.affine().unwrap();
    let inv = a.inverse();
    let s: Vec<[f64; 3]> = (0..20)
        .map(|i| {
            let t = i as f64 / 19.0;
            a.transform_point3(DVec3::new(0.2 * t, 0.05 * (6.0 * t).fsin(), 0.03 * t))
                .to_array()
        })
        .collect();
    let flat = project_to_drawing_plane(&s, &f).unwrap();
    for (p, q) in flat.iter().zip(&s) {
        let (lp, lq) = (
            inv.transform_point3(DVec3::from_array(*p)),
            inv.transform_point3(DVec3::from_array(*q)),
        );
        assert!(lp.z.abs() < 1e-12);
        assert!((lp.x - lq.x).abs() < 1e-12 && (lp.y - lq.y).abs() < 1e-12);
    }
    let mirrored = mirror_in_frame(&s, &f).unwrap();
    let twice = mirror_in_frame(&mirrored, &f).unwrap();
    for ((p, q), r) in mirrored.iter().zip(&s).zip(&twice) {
        let (lp, lq) = (
            inv.transform_point3(DVec3::from_array(*p)),
            inv.transform_point3(DVec3::from_array(*q)),
        );
        assert!((lp.x + lq.x).abs() < 1e-12 && (lp.y - lq.y).abs() < 1e-12);
        assert!(DVec3::from_array(*r).distance(DVec3::from_array(*q)) < 1e-12);
    }
    // Bad frames are typed errors.
    let zero = ModelingFrame {
        origin: [0.0; 3],
        rotation: [0.0; 4],
    };
    assert!(matches!(
        zero.validate(),
        Err(StylingError::BadParameter(_))
    ));
    let nan = ModelingFrame {
        origin: [f64::NAN, 0.0, 0.0],
        ..ModelingFrame::WORLD
    };
    assert_eq!(
        nan.validate(),
        Err(StylingError::NonFinite("modeling frame"))
    );
    assert!(project_to_drawing_plane(&s, &zero).is_err());
}

mod op {
    //! The `curve_draw_in_frame` op: through the log, replayed, undone.

    use super::*;
    use crate::doc::{
        parse_script, LogError, ObjectId, ObjectKind, Op, OpError, OpLog, ScriptCommand,
    };
    use crate::styling::{CurveDrawInFrame, CurveNetwork};

    fn network(log: &OpLog) -> (CurveNetwork, crate::math::Transform) {
        let o = log.document().get(ObjectId(1)).unwrap();
        match &o.kind {
            ObjectKind::CurveNetwork(n) => (n.clone(), o.placement),
            _ => unreachable!(),
        }
    }

    /// An arc drawn in local coordinates, and the model-space samples the
    /// hand produced while the frame moved (`frame(t)` at each sample).
    fn held_arc(count: usize) -> (Vec<DVec3>, Vec<[f64; 3]>, Vec<ModelingFrame>) {
        let local: Vec<DVec3> = (0..count)
            .map(|i| {
                let a = 2.0 * i as f64 / count as f64;
                DVec3::new(0.05 + 0.1 * a.fcos(), 0.1 * a.fsin(), 0.02 * a)
            })
            .collect();
        let frames: Vec<ModelingFrame> =
            (0..count).map(|i| frame(i as f64 / count as f64)).collect();
        let world = local
            .iter()
            .zip(&frames)
            .map(|(p, f)| f.affine().unwrap().transform_point3(*p).to_array())
            .collect();
        (local, world, frames)
    }

    fn draw(world: &[[f64; 3]], frames: &[ModelingFrame], plane: bool, mirror: bool) -> Op {
        Op::CurveDrawInFrame(CurveDrawInFrame {
            id: ObjectId(1),
            samples: world.to_vec(),
            frames: frames.to_vec(),
            onto_plane: plane,
            mirror,
            fit: FitMode::Interpolate,
            resample: None,
            snap_tol: 1e-3,
        })
    }

    fn new_log() -> OpLog {
        let mut log = OpLog::new();
        log.apply(
            serde_json::from_str(r#"{"op":"curve_network_create","resolution":8,"surface_n":6}"#)
                .unwrap(),
        )
        .unwrap();
        log
    }

    #[test]
    fn a_stroke_on_the_held_frame_lands_in_it_and_the_network_moves_with_it() {
        let mut log = new_log();
        let (local, world, frames) = held_arc(40);
        let before = log.document().content_hash();
        log.apply(draw(&world, &frames, false, false)).unwrap();
        let (net, placement) = network(&log);
        // The network's curve is the arc as drawn on the frame, expressed
        // where the frame held the network at the stroke's start (F_0).
        let f0 = frames[0].affine().unwrap();
        let want: Vec<[f64; 3]> = local
            .iter()
            .map(|p| f0.transform_point3(*p).to_array())
            .collect();
        let fit = fit_curve(&want, FitMode::Interpolate, None).unwrap();
        let got = net.curve(0).unwrap();
        assert_eq!(got.ctrl.len(), fit.ctrl.len());
        for (a, b) in got.ctrl.iter().zip(&fit.ctrl) {
            assert!(DVec3::from_array(*a).distance(DVec3::from_array(*b)) < 1e-12);
        }
        // The network moved with the frame: placed now, its last drawn
        // point is exactly under the pen's last sample, and its first is
        // where the frame carried the first sample.
        let p = placement.to_affine().unwrap();
        let last = p.transform_point3(DVec3::from_array(want[39]));
        assert!(
            last.distance(DVec3::from_array(world[39])) < 1e-12,
            "{last}"
        );
        let motion = frames[0].motion_to(&frames[39]).unwrap();
        let first = p.transform_point3(DVec3::from_array(want[0]));
        assert!(first.distance(motion.transform_point3(DVec3::from_array(world[0]))) < 1e-12);
        assert!(placement != crate::math::Transform::IDENTITY);
        // Replayed: the same bits. Undone: the document before the op.
        let hash = log.document().content_hash();
        let replayed = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
        assert_eq!(replayed.document().content_hash(), hash);
        assert_eq!(network(&replayed).1, placement);
        log.undo().unwrap();
        assert_eq!(log.document().content_hash(), before);
        assert_eq!(network(&log).1, crate::math::Transform::IDENTITY);
        log.redo().unwrap();
        assert_eq!(log.document().content_hash(), hash);
        // The op is one `.jsonl` line and back.
        let line = serde_json::to_string(&log.ops()[1]).unwrap();
        let back = parse_script(&line).unwrap();
        assert_eq!(back[0].command, ScriptCommand::Op(log.ops()[1].clone()));
    }

    #[test]
    fn a_fixed_frame_keeps_the_placement_and_plane_and_mirror_hold() {
        let mut log = new_log();
        // The network was moved before: strokes land in its own frame.
        log.apply(serde_json::from_str(r#"{"op":"set_transform","id":1,"transform":{"translate":[0.1,0.2,0.3],"rotate":[0,0,0.3826834323650898,0.9238795325112867],"scale":[2,2,2]}}"#).unwrap())
            .unwrap();
        let (_, p0) = network(&log);
        let f = frame(0.4);
        // A stroke off the drawing plane, on the +x side of the symmetry
        // plane.
        let world: Vec<[f64; 3]> = (0..30)
            .map(|i| {
                let a = 2.0 * i as f64 / 30.0;
                let l = DVec3::new(
                    0.25 + 0.1 * a.fcos(),
                    0.1 * a.fsin(),
                    0.01 * (i as f64).fsin(),
                );
                f.affine().unwrap().transform_point3(l).to_array()
            })
            .collect();
        log.apply(draw(&world, &[f], true, true)).unwrap();
        let (net, p1) = network(&log);
        assert_eq!(p1, p0, "a frame fixed in place does not move the network");
        assert_eq!(
            net.curves.iter().flatten().count(),
            2,
            "the stroke and its mirror"
        );
        let to_frame = f.affine().unwrap().inverse() * p0.to_affine().unwrap();
        let a = net.curve(0).unwrap();
        let b = net.curve(1).unwrap();
        for (ca, cb) in a.ctrl.iter().zip(&b.ctrl) {
            let la = to_frame.transform_point3(DVec3::from_array(*ca));
            let lb = to_frame.transform_point3(DVec3::from_array(*cb));
            // On the drawing plane, and mirrored across the symmetry plane.
            assert!(la.z.abs() < 1e-12 && lb.z.abs() < 1e-12, "{la} {lb}");
            assert!((la.x + lb.x).abs() < 1e-12 && (la.y - lb.y).abs() < 1e-12);
            assert!(la.x > 0.1, "the stroke sits on the +x side: {la}");
        }
        // Placed, the curve is the model-space stroke projected on the
        // frame's plane.
        let placed = p0.to_affine().unwrap();
        let proj = project_to_drawing_plane(&world, &f).unwrap();
        let fit = fit_curve(&proj, FitMode::Interpolate, None).unwrap();
        for (ca, cf) in a.ctrl.iter().zip(&fit.ctrl) {
            let m = placed.transform_point3(DVec3::from_array(*ca));
            assert!(m.distance(DVec3::from_array(*cf)) < 1e-9, "{m}");
        }
    }

    #[test]
    fn bad_frames_are_typed_errors_that_change_nothing() {
        let mut log = new_log();
        let (_, world, frames) = held_arc(20);
        let hash = log.document().content_hash();
        let cases = [
            (draw(&world, &frames[..3], false, false), "one per sample"),
            (draw(&world, &[], false, false), "one per sample"),
            (
                draw(
                    &world,
                    &[ModelingFrame {
                        origin: [0.0; 3],
                        rotation: [0.0; 4],
                    }],
                    false,
                    false,
                ),
                "zero quaternion",
            ),
        ];
        for (op, says) in cases {
            let e = log.apply(op).unwrap_err();
            assert!(
                matches!(&e, LogError::Op(OpError::Styling(StylingError::BadParameter(m))) if m.contains(says)),
                "{e}"
            );
            assert_eq!(log.document().content_hash(), hash);
        }
        // Not a network: typed.
        log.apply(
            serde_json::from_str(r#"{"op":"add_solid","shape":{"kind":"sphere","radius":0.1}}"#)
                .unwrap(),
        )
        .unwrap();
        let mut op = draw(&world, &frames, false, false);
        if let Op::CurveDrawInFrame(d) = &mut op {
            d.id = ObjectId(2);
        }
        assert!(
            matches!(
                log.apply(op).unwrap_err(),
                LogError::Op(OpError::WrongKind { .. })
            ),
            "wrong kind"
        );
    }
}
