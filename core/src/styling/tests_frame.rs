//! The modeling frame (paper §5.4): strokes drawn in a moving frame, the
//! frame held by a hand, curves and patches carried by it.

use super::curve::{fit_curve, FitMode};
use super::frame::{mirror_in_frame, project_to_drawing_plane, stroke_in_frame, ModelingFrame};
use super::surface::SurfaceWeights;
use super::tests_ngon::{boundary_gap, prism};
use super::StylingError;
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
            DVec3::new(0.1 * a.cos(), 0.1 * a.sin(), 0.0)
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
            a.transform_point3(DVec3::new(0.2 * t, 0.05 * (6.0 * t).sin(), 0.03 * t))
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
