//! Sketch tests: templates recognized from noisy strokes, typed errors.

use crate::math::fm::DetMath as _;
use std::f64::consts::TAU;

use glam::{DVec2, DVec3};

use super::*;
use crate::gc::Profile;

fn noisy_loop(f: impl Fn(f64) -> DVec2, n: usize, noise: f64) -> Vec<DVec2> {
    // Deterministic "noise" from a fixed sequence.
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let j = ((i * 7919) % 101) as f64 / 101.0 - 0.5;
            f(t) + DVec2::new(j, -j * 0.7) * noise
        })
        .collect()
}

fn polygon_point(sides: usize, r: f64, rot: f64, t: f64) -> DVec2 {
    let s = t * sides as f64;
    let k = s.floor();
    let f = s - k;
    let a0 = rot + TAU * k / sides as f64;
    let a1 = rot + TAU * (k + 1.0) / sides as f64;
    let p0 = DVec2::new(a0.fcos(), a0.fsin()) * r;
    let p1 = DVec2::new(a1.fcos(), a1.fsin()) * r;
    p0 + (p1 - p0) * f
}

#[test]
fn recognizes_templates() {
    let c = DVec2::new(0.3, -0.2);
    let circle = noisy_loop(
        |t| c + DVec2::new((TAU * t).fcos(), (TAU * t).fsin()) * 0.5,
        150,
        0.01,
    );
    let m = match_section(&circle).unwrap();
    assert!(
        matches!(m.profile, Profile::Circle { radius } if (radius - 0.5).abs() < 0.02),
        "{m:?}"
    );
    assert!(m.score > 0.97);
    assert!((m.center - c).length() < 0.01);

    let ell = noisy_loop(
        |t| DVec2::new(0.8 * (TAU * t).fcos(), 0.3 * (TAU * t).fsin()),
        150,
        0.005,
    );
    let m = match_section(&ell).unwrap();
    assert!(
        matches!(m.profile, Profile::Ellipse { .. }),
        "{:?}",
        m.candidates
    );

    let tri = noisy_loop(|t| polygon_point(3, 0.6, 0.3, t), 120, 0.005);
    let m = match_section(&tri).unwrap();
    assert!(
        matches!(m.profile, Profile::Polygon { sides: 3, .. }),
        "{:?} {:?}",
        m.profile,
        m.candidates
    );

    let hex = noisy_loop(|t| polygon_point(6, 0.6, 0.0, t), 180, 0.004);
    let m = match_section(&hex).unwrap();
    assert!(
        matches!(m.profile, Profile::Polygon { sides: 6, .. }),
        "{:?} {:?}",
        m.profile,
        m.candidates
    );

    // A clockwise square stroke is a square, whatever the direction.
    let mut sq = noisy_loop(
        |t| polygon_point(4, 0.5, 0.25 * std::f64::consts::PI, t),
        120,
        0.003,
    );
    sq.reverse();
    let m = match_section(&sq).unwrap();
    assert!(
        matches!(
            m.profile,
            Profile::Polygon { sides: 4, .. } | Profile::Rectangle { .. }
        ),
        "{:?} {:?}",
        m.profile,
        m.candidates
    );
    assert!(m.score > 0.95);
    assert!(m.sketch.curve().is_ok());
}

#[test]
fn degenerate_strokes_are_typed_errors() {
    let bow = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
    ];
    assert_eq!(match_section(&bow), Err(SketchError::SelfIntersecting));
    assert!(matches!(
        match_section(&[DVec2::ZERO, DVec2::X]),
        Err(SketchError::TooFewPoints { .. })
    ));
    assert_eq!(
        match_section(&[DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)]),
        Err(SketchError::ZeroLength)
    );
    assert_eq!(
        match_section(&[DVec2::ZERO, DVec2::new(f64::NAN, 0.0), DVec2::Y]),
        Err(SketchError::NonFinite(1))
    );
    let plane = SketchPlane::new(DVec3::ZERO, DVec3::Y, DVec3::X).unwrap();
    assert_eq!(
        fit_spine_stroke(&[DVec3::ONE; 5], &plane, 1e-3),
        Err(SketchError::TooFewPoints { got: 1, need: 2 })
    );
    assert_eq!(
        SketchPlane::new(DVec3::ZERO, DVec3::ZERO, DVec3::X),
        Err(SketchError::BadPlane)
    );
}

#[test]
fn spine_fit_is_within_tolerance_and_in_plane() {
    let plane = SketchPlane::new(DVec3::ZERO, DVec3::Y, DVec3::Z).unwrap();
    // A wobbly stroke slightly off the plane.
    let stroke: Vec<DVec3> = (0..200)
        .map(|i| {
            let t = i as f64 / 199.0;
            DVec3::new(0.3 * (3.0 * t).fsin(), 0.01 * (40.0 * t).fsin(), t)
        })
        .collect();
    let fit = fit_spine_stroke(&stroke, &plane, 1e-3).unwrap();
    assert!(fit.simplified.len() >= 2 && fit.simplified.len() < 64);
    // The spine through the simplified points (and what `spine_points`
    // adds) is in the plane and near every stroke point.
    let (points, spine) = super::spine_points(&stroke, &plane, 1e-3).unwrap();
    assert!(points.len() >= fit.simplified.len());
    let (a, b) = spine.curve.domain();
    for i in 0..=100 {
        let p = spine.curve.point(a + (b - a) * i as f64 / 100.0);
        assert!(p.y.abs() < 1e-12, "off plane {p}");
    }
    for s in stroke.iter().step_by(10) {
        let q = DVec3::new(s.x, 0.0, s.z);
        let d = (0..=2000)
            .map(|i| (spine.curve.point(a + (b - a) * i as f64 / 2000.0) - q).length())
            .fold(f64::INFINITY, f64::min);
        assert!(d < 3e-3, "{d}");
    }
}
