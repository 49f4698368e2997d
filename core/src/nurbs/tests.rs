//! Cross-module NURBS tests: skinning exactness, insert invariance,
//! surface derivatives.

use crate::math::fm::DetMath as _;
use glam::{DAffine3, DVec3};

use super::shapes::{ellipse, rectangle, regular_polygon};
use super::*;

mod surface_gap;

fn sections() -> (Vec<NurbsCurve>, Vec<f64>) {
    let pts: Vec<DVec3> = (0..11)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 11.0;
            let r = 1.0 + 0.25 * (3.0 * a).fcos();
            DVec3::new(r * a.fcos(), r * a.fsin(), 0.0)
        })
        .collect();
    let curves = [
        ellipse(1.0, 0.7),
        regular_polygon(5, 1.2).unwrap(),
        interpolate_closed(&pts, ParamMethod::ChordLength).unwrap(),
        rectangle(1.5, 0.8).unwrap(),
        ellipse(0.5, 0.5),
    ];
    let placed = curves
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let m = DAffine3::from_translation(DVec3::new(0.1 * k as f64, 0.0, k as f64))
                * DAffine3::from_rotation_y(0.1 * k as f64);
            c.transformed(&m)
        })
        .collect();
    (placed, vec![0.0, 0.2, 0.5, 0.8, 1.0])
}

#[test]
fn skinning_interpolates_every_section() {
    let (secs, v) = sections();
    for scheme in [SkinV::NaturalCubic, SkinV::Averaged { q: 3 }] {
        let s = skin(&secs, &v, scheme).unwrap();
        for (c, vk) in secs.iter().zip(&v) {
            let mut worst: f64 = 0.0;
            for i in 0..=400 {
                let u = i as f64 / 400.0;
                worst = worst.max((s.point(u, *vk) - c.point(u)).length());
            }
            assert!(
                worst < 1e-9,
                "{scheme:?}: section at v={vk} missed by {worst}"
            );
        }
    }
}

#[test]
fn skinning_with_chord_length_v_params() {
    let (secs, _) = sections();
    let v = skin_params(&secs).unwrap();
    assert_eq!(v[0], 0.0);
    assert_eq!(v[v.len() - 1], 1.0);
    let s = skin(&secs, &v, SkinV::Averaged { q: 3 }).unwrap();
    for (c, vk) in secs.iter().zip(&v) {
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            assert!((s.point(u, *vk) - c.point(u)).length() < 1e-9);
        }
    }
}

#[test]
fn inserting_an_iso_curve_leaves_the_surface_unchanged() {
    let (mut secs, mut v) = sections();
    let s = skin(&secs, &v, SkinV::NaturalCubic).unwrap();
    let iso = s.iso_curve_v(0.63);
    secs.insert(3, iso);
    v.insert(3, 0.63);
    let s2 = skin(&secs, &v, SkinV::NaturalCubic).unwrap();
    let worst = surface_gap::max_gap(&s, &s2, 60);
    assert!(worst < 1e-9, "surface moved by {worst}");
}

#[test]
fn surface_derivatives_match_finite_differences() {
    let (secs, v) = sections();
    let s = skin(&secs, &v, SkinV::NaturalCubic).unwrap();
    let h = 1e-6;
    for (u, w) in [(0.13, 0.3), (0.55, 0.71), (0.9, 0.05)] {
        let d = s.derivatives(u, w, 2);
        assert!((d[0][0] - s.point(u, w)).length() < 1e-12);
        let du = (s.point(u + h, w) - s.point(u - h, w)) / (2.0 * h);
        let dv = (s.point(u, w + h) - s.point(u, w - h)) / (2.0 * h);
        assert!(
            (du - d[1][0]).length() < 1e-5 * du.length().max(1.0),
            "{u} {w} {du} {:?}",
            d[1][0]
        );
        assert!((dv - d[0][1]).length() < 1e-5 * dv.length().max(1.0));
        let duv = (s.derivatives(u, w + h, 1)[1][0] - s.derivatives(u, w - h, 1)[1][0]) / (2.0 * h);
        assert!((duv - d[1][1]).length() < 1e-4 * duv.length().max(1.0));
    }
}

#[test]
fn ellipse_is_exact() {
    let e = ellipse(2.0, 1.0);
    for i in 0..100 {
        let p = e.point(i as f64 / 100.0);
        assert!(((p.x / 2.0).fpowi(2) + p.y.fpowi(2) - 1.0).abs() < 1e-14);
    }
    let c = e.elevate_degree(1);
    for i in 0..100 {
        let u = i as f64 / 100.0;
        assert!((c.point(u) - e.point(u)).length() < 1e-14);
    }
}
