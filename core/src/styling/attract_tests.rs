//! Attractors at real weights (issue 18): each frame moves the curve the
//! predicted fraction of the way to its point, line, plane or curve.

use super::attract::{AttractParams, Attractor, Target};
use super::curve::{fit_curve, FitMode, SplineCurve};
use super::net_tests::edge_samples;
use super::network::CurveNetwork;
use super::tests::wavy_samples;
use super::tools::CurveSession;
use super::StylingError;
use crate::math::fm::DetMath as _;
use crate::math::DVec3;

fn wavy() -> SplineCurve {
    fit_curve(&wavy_samples(40, 0.0), FitMode::Interpolate, None).unwrap()
}

/// Uniform weights, free ends, no tangent term: the exact case.
fn uniform(weight: f64) -> AttractParams {
    AttractParams {
        weight,
        wp0: 1.0,
        wp1: 0.0,
        alpha: 0.0,
        keep_ends: false,
    }
}

fn params(c: &SplineCurve, count: usize) -> Vec<f64> {
    let (a, b) = c.domain();
    (0..count)
        .map(|i| a + (b - a) * i as f64 / (count - 1) as f64)
        .collect()
}

/// Runs `frames` frames and checks that every point's distance to the
/// target shrank by exactly `(1 - c)^frames`, moving along `m (y - r)`.
fn check_exact(target: Target, frames: usize) -> SplineCurve {
    let c0 = wavy();
    let p = uniform(3.0);
    let mut s = CurveSession::new(c0.clone()).unwrap();
    s.attract(&p, &target, 0.0, frames).unwrap();
    assert_eq!(s.refactor_count(), 1, "one factorization for every frame");
    let keep = (1.0 - p.step_fraction()).fpowi(frames as i32);
    assert!((keep - 0.25f64.fpowi(frames as i32)).abs() < 1e-15);
    let mut worst: f64 = 0.0;
    for t in params(&c0, 200) {
        let before = target.distance(c0.point(t));
        let after = target.distance(s.curve.point(t));
        worst = worst.max((after - keep * before).abs());
    }
    assert!(
        worst < 1e-9,
        "{target:?}: distance off the prediction by {worst}"
    );
    s.curve
}

#[test]
fn plane_line_point_and_straight_curve_pull_by_the_predicted_fraction() {
    let n = DVec3::new(0.3, 0.2, 1.0).normalize();
    let a = DVec3::new(0.0, 0.0, 0.01);
    let c0 = wavy();
    let c = check_exact(Target::Plane(a, n), 3);
    // Points move along the plane's normal only.
    for t in params(&c0, 50) {
        let d = c.point(t) - c0.point(t);
        assert!((d - n * d.dot(n)).length() < 1e-12);
    }
    let dir = DVec3::new(1.0, 0.2, 0.0).normalize();
    let c = check_exact(Target::Line(DVec3::new(0.1, 0.0, 0.0), dir), 2);
    for t in params(&c0, 50) {
        assert!((c.point(t) - c0.point(t)).dot(dir).abs() < 1e-12);
    }
    check_exact(Target::Point(DVec3::new(0.15, 0.1, -0.05)), 4);
    // A straight curve: its nearest points are an affine image of the
    // reference, so the frame is exact too.
    let line: Vec<[f64; 3]> = (0..10)
        .map(|i| {
            let s = i as f64 / 9.0;
            [-0.1 + 0.5 * s, 0.05 + 0.02 * s, 0.03]
        })
        .collect();
    let straight = fit_curve(&line, FitMode::Interpolate, None).unwrap();
    check_exact(Target::Curve(&straight), 3);
}

#[test]
fn a_curved_attractor_draws_the_curve_onto_itself() {
    let c0 = wavy();
    let arc: Vec<[f64; 3]> = (0..30)
        .map(|i| {
            let s = i as f64 / 29.0;
            [-0.05 + 0.4 * s, 0.08 * (3.0 * s).fsin(), 0.04]
        })
        .collect();
    let y = fit_curve(&arc, FitMode::Interpolate, None).unwrap();
    let target = Target::Curve(&y);
    let worst = |c: &SplineCurve| {
        params(c, 100)
            .into_iter()
            .map(|t| target.distance(c.point(t)))
            .fold(0.0, f64::max)
    };
    let d0 = worst(&c0);
    let mut s = CurveSession::new(c0.clone()).unwrap();
    let mut prev = d0;
    for _ in 0..8 {
        s.attract(&uniform(3.0), &target, 0.0, 1).unwrap();
        let d = worst(&s.curve);
        assert!(d < 0.5 * prev, "frame moved {prev} -> {d}");
        prev = d;
    }
    assert!(prev < 1e-3 * d0, "after 8 frames {prev} of {d0}");
}

#[test]
fn a_local_attractor_pulls_around_the_pointer_only() {
    let c0 = wavy();
    let (a, b) = c0.domain();
    let t0 = a + 0.5 * (b - a);
    let p = DVec3::new(0.15, 0.08, 0.05);
    let local = AttractParams {
        weight: 5.0,
        wp0: 1.0,
        wp1: 1e-3,
        alpha: 40.0,
        keep_ends: true,
    };
    let mut s = CurveSession::new(c0.clone()).unwrap();
    let d0 = c0.point(t0).distance(p);
    let mut prev = d0;
    for _ in 0..5 {
        s.attract(&local, &Target::Point(p), t0, 1).unwrap();
        let d = s.curve.point(t0).distance(p);
        assert!(d < 0.8 * prev, "pointed point moved {prev} -> {d}");
        prev = d;
    }
    assert!(prev < 0.3 * d0, "{prev} of {d0}");
    let hw = (1e3f64.fln() / local.alpha).sqrt();
    let outside = params(&c0, 400)
        .into_iter()
        .filter(|t| ((t - a) / (b - a) - 0.5).abs() > hw);
    let dev = outside
        .map(|t| s.curve.point(t).distance(c0.point(t)))
        .fold(0.0, f64::max);
    assert!(
        dev <= 1e-12,
        "moved outside the gaussian's support by {dev}"
    );
    assert_eq!(s.curve.ctrl[0], c0.ctrl[0]);
    assert_eq!(s.curve.ctrl[c0.n() - 1], c0.ctrl[c0.n() - 1]);
}

fn add(net: &mut CurveNetwork, a: [f64; 3], b: [f64; 3], bow: [f64; 3]) {
    let c = fit_curve(&edge_samples(a, b, bow), FitMode::Interpolate, None).unwrap();
    net.add_curve(c, 1e-3).unwrap();
}

#[test]
fn network_attractors_keep_junctions_and_check_their_input() {
    let mut net = CurveNetwork::new(8, 6).unwrap();
    for (a, b, w) in super::net_tests::box_edges(0.1, 0.01) {
        add(&mut net, a, b, w);
    }
    net.fill_all().unwrap();
    let before = net.clone();
    // Curve 0 runs along x at y = z = -0.1: pull its middle up to z = 0.
    let plane = Attractor::Plane {
        a: [0.0, 0.0, 0.0],
        normal: [0.0, 0.0, 2.0],
    };
    let p = AttractParams {
        weight: 4.0,
        wp0: 1.0,
        wp1: 1e-3,
        alpha: 20.0,
        keep_ends: false,
    };
    let c = net.curve(0).unwrap().clone();
    let (a, b) = c.domain();
    let mid = c.point(0.5 * (a + b));
    net.attract(0, &p, &plane, Some(mid.to_array()), 6).unwrap();
    let moved = net.curve(0).unwrap().point(0.5 * (a + b));
    assert!(
        moved.z.abs() < 0.5 * mid.z.abs(),
        "{} -> {}",
        mid.z,
        moved.z
    );
    assert!(net.junction_gap() < 1e-9, "gap {}", net.junction_gap());
    assert!(super::ngon_tests::boundary_gap(&net) < 1e-9);
    // Another curve as attractor; a curve cannot attract itself.
    let mut n2 = before.clone();
    n2.attract(
        0,
        &uniform(1.0),
        &Attractor::Curve {
            curve: super::CurveId(1),
        },
        None,
        2,
    )
    .unwrap();
    assert!(n2.junction_gap() < 1e-9);
    let bad = [
        (
            Attractor::Curve {
                curve: super::CurveId(0),
            },
            uniform(1.0),
            None,
        ),
        (
            Attractor::Curve {
                curve: super::CurveId(99),
            },
            uniform(1.0),
            None,
        ),
        (
            Attractor::Line {
                a: [0.0; 3],
                dir: [0.0; 3],
            },
            uniform(1.0),
            None,
        ),
        (Attractor::Point { p: [0.0; 3] }, uniform(0.0), None),
        (Attractor::Point { p: [0.0; 3] }, p, None),
    ];
    for (att, prm, at) in bad {
        let mut n3 = before.clone();
        let e = n3.attract(0, &prm, &att, at, 1).unwrap_err();
        assert!(
            matches!(e, StylingError::BadParameter(_) | StylingError::NoCurve(99)),
            "{e:?}"
        );
        assert_eq!(n3, before, "a refused attraction changes nothing");
    }
}
