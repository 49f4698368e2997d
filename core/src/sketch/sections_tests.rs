//! Section placement tests: the skin through the chosen sections follows
//! the sketched tube; too-tight bends are refused with a clear error.

use crate::math::fm::DetMath as _;
use std::f64::consts::PI;

use glam::DVec3;

use super::*;
use crate::gc::{fit_spine, Gc, KeySection, Profile, Resolution, ShapeType};

/// A stroke along an arc of radius `r` over `angle` radians in the XZ
/// plane (normal Y), sampled every ~2 mm, with a little deterministic
/// hand jitter off the plane.
fn arc_stroke(r: f64, angle: f64) -> Vec<DVec3> {
    let n = ((r * angle) / 0.002).ceil() as usize + 1;
    (0..n)
        .map(|i| {
            let a = angle * i as f64 / (n - 1) as f64;
            let j = ((i * 7919) % 101) as f64 / 101.0 - 0.5;
            DVec3::new(r * (1.0 - a.fcos()), 1e-4 * j, r * a.fsin())
        })
        .collect()
}

fn xz_plane() -> SketchPlane {
    SketchPlane::new(DVec3::ZERO, DVec3::Y, DVec3::X).unwrap()
}

fn gc_with(points: &[DVec3], params: &[f64], radius: f64) -> Gc {
    let spine = fit_spine(points, DVec3::Y).unwrap();
    let sections = params
        .iter()
        .map(|&v| KeySection::new(Profile::Circle { radius }, v))
        .collect();
    Gc::new(spine, sections, ShapeType::Solid, Resolution::DEFAULT).unwrap()
}

/// Centre and mean radius of the skin's ring at `v`.
fn ring(gc: &Gc, v: f64) -> (DVec3, f64) {
    let s = gc.surface().unwrap();
    let pts: Vec<DVec3> = (0..64).map(|i| s.point(i as f64 / 64.0, v)).collect();
    let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
    let r = pts.iter().map(|p| (*p - c).length()).sum::<f64>() / pts.len() as f64;
    (c, r)
}

/// Largest distance from the skin's ring centres at 20 parameters to the
/// stroke (projected into its plane), and largest ring radius error.
fn tube_error(gc: &Gc, stroke: &[DVec3], radius: f64) -> (f64, f64) {
    let plane = xz_plane();
    let path: Vec<DVec3> = stroke
        .iter()
        .map(|p| plane.lift(plane.project(*p)))
        .collect();
    let centres: Vec<DVec3> = (0..20).map(|i| ring(gc, i as f64 / 19.0).0).collect();
    let to_stroke = stroke_deviation(&centres, &plane, &path);
    let r_err = (0..20)
        .map(|i| (ring(gc, i as f64 / 19.0).1 - radius).abs())
        .fold(0.0, f64::max);
    (to_stroke, r_err)
}

#[test]
fn straight_spines_need_two_sections() {
    let stroke: Vec<DVec3> = (0..50)
        .map(|i| DVec3::new(0.0, 0.0, 0.004 * i as f64))
        .collect();
    let s = sketch_spine(&stroke, &xz_plane(), 0.02, &SectionSettings::default()).unwrap();
    assert_eq!(s.plan.params, vec![0.0, 1.0]);
    assert!(s.plan.min_bend_radius > 1.0, "{}", s.plan.min_bend_radius);
}

#[test]
fn a_sketched_arc_gives_a_tube_that_follows_it() {
    let stroke = arc_stroke(0.1, 0.5 * PI);
    let settings = SectionSettings::default();
    let s = sketch_spine(&stroke, &xz_plane(), 0.02, &settings).unwrap();
    assert!(s.plan.params.len() > 3, "{:?}", s.plan.params);
    assert!(s.plan.max_error <= settings.tolerance);
    let gc = gc_with(&s.points, &s.plan.params, 0.02);
    let (dev, r_err) = tube_error(&gc, &stroke, 0.02);
    assert!(dev < 2e-3, "tube axis {dev} from the stroke");
    assert!(r_err < 1e-3, "ring radius off by {r_err}");
    // The old behaviour (two sections) is what the test is there to catch.
    let straight = gc_with(&s.points, &[0.0, 1.0], 0.02);
    let (dev2, _) = tube_error(&straight, &stroke, 0.02);
    assert!(dev2 > 1e-2, "two sections follow the arc within {dev2}?");
}

#[test]
fn tighter_curves_get_more_sections() {
    let settings = SectionSettings::default();
    let count = |angle: f64| {
        sketch_spine(&arc_stroke(0.1, angle), &xz_plane(), 0.02, &settings)
            .unwrap()
            .plan
            .params
            .len()
    };
    let (a, b, c) = (count(0.2 * PI), count(0.5 * PI), count(PI));
    assert!(a <= b && b < c, "{a} {b} {c}");
}

#[test]
fn a_u_shaped_sketch_works_when_the_tube_fits_its_bend() {
    // Legs 0.1 long joined by a half circle of radius 0.04.
    let mut stroke = Vec::new();
    for i in 0..50 {
        stroke.push(DVec3::new(0.0, 0.0, 0.1 - 0.002 * i as f64));
    }
    for i in 0..=60 {
        let a = PI * i as f64 / 60.0;
        stroke.push(DVec3::new(0.04 * (1.0 - a.fcos()), 0.0, -0.04 * a.fsin()));
    }
    for i in 1..=50 {
        stroke.push(DVec3::new(0.08, 0.0, 0.002 * i as f64));
    }
    let settings = SectionSettings::default();
    let s = sketch_spine(&stroke, &xz_plane(), 0.015, &settings).unwrap();
    let gc = gc_with(&s.points, &s.plan.params, 0.015);
    let mesh = crate::gc::mesh_gc(&gc).unwrap();
    let report = crate::mesh::validate(&mesh, &Default::default());
    assert!(report.is_closed_manifold(), "{:?}", report.problems());
    let (dev, _) = tube_error(&gc, &stroke, 0.015);
    assert!(dev < 2e-3, "{dev}");
    // A section wider than the bend is refused with where and how tight.
    match sketch_spine(&stroke, &xz_plane(), 0.06, &settings) {
        Err(SketchError::TooTight {
            bend_radius,
            radius,
            at,
        }) => {
            assert!((0.02..0.06).contains(&bend_radius), "{bend_radius}");
            assert_eq!(radius, 0.06);
            assert!((0.2..0.8).contains(&at), "{at}");
            let msg = SketchError::TooTight {
                bend_radius,
                radius,
                at,
            }
            .to_string();
            assert!(msg.contains("fold into itself"), "{msg}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_settings_are_typed_errors() {
    let stroke: Vec<DVec3> = arc_stroke(0.1, 1.0)
        .iter()
        .map(|p| DVec3::new(p.x, 0.0, p.z))
        .collect();
    let spine = fit_spine(&stroke[..5], DVec3::Y).unwrap();
    for (r, tol) in [
        (0.0, 1e-3),
        (f64::NAN, 1e-3),
        (0.01, -1.0),
        (0.01, f64::INFINITY),
    ] {
        let settings = SectionSettings {
            tolerance: tol,
            ..Default::default()
        };
        assert!(matches!(
            section_params(&spine, r, &settings),
            Err(SketchError::BadParameter { .. })
        ));
    }
    let few = SectionSettings {
        max_sections: 3,
        tolerance: 1e-9,
        ..Default::default()
    };
    assert!(matches!(
        sketch_spine(&arc_stroke(0.1, PI), &xz_plane(), 0.02, &few),
        Err(SketchError::TooManySections { max: 3, .. })
    ));
}
