//! GC tests: exact loft, insert invariance, twist, bend, analytic volumes
//! of the three shape types, typed errors.

use crate::math::fm::DetMath as _;
use std::f64::consts::PI;

use glam::DVec3;

use super::*;
use crate::mesh::{validate, ValidationReport};

// `nurbs::tests` is private to `nurbs`, so its helper is included here by
// path rather than named; a second copy of one test helper is intended.
#[allow(clippy::duplicate_mod)]
#[path = "../nurbs/tests/surface_gap.rs"]
mod surface_gap;

pub(crate) fn straight(r: f64, h: f64, shape: ShapeType, res: Resolution) -> Gc {
    let spine = fit_spine(&[DVec3::ZERO, DVec3::new(0.0, 0.0, h)], DVec3::X).unwrap();
    Gc::new(
        spine,
        vec![
            KeySection::new(Profile::Circle { radius: r }, 0.0),
            KeySection::new(Profile::Circle { radius: r }, 1.0),
        ],
        shape,
        res,
    )
    .unwrap()
}

pub(crate) fn vase(shape: ShapeType) -> Gc {
    let spine = fit_spine(
        &[
            DVec3::ZERO,
            DVec3::new(0.05, 0.0, 0.3),
            DVec3::new(-0.05, 0.0, 0.6),
            DVec3::new(0.0, 0.0, 1.0),
        ],
        DVec3::Y,
    )
    .unwrap();
    let sec = |p: Profile, v: f64, s: f64| KeySection {
        profile: p,
        v,
        scale: s,
        twist: 0.0,
    };
    Gc::new(
        spine,
        vec![
            sec(Profile::Circle { radius: 0.25 }, 0.0, 1.0),
            sec(
                Profile::Polygon {
                    sides: 6,
                    radius: 0.4,
                },
                0.3,
                1.0,
            ),
            sec(
                Profile::Points {
                    points: (0..9)
                        .map(|i| {
                            let a = i as f64 / 9.0 * std::f64::consts::TAU;
                            let r = 0.3 + 0.04 * (4.0 * a).fcos();
                            [r * a.fcos(), r * a.fsin()]
                        })
                        .collect(),
                },
                0.55,
                1.0,
            ),
            sec(
                Profile::Rectangle {
                    width: 0.3,
                    height: 0.25,
                },
                0.8,
                1.0,
            ),
            sec(Profile::Ellipse { rx: 0.2, ry: 0.15 }, 1.0, 1.0),
        ],
        shape,
        Resolution::DEFAULT,
    )
    .unwrap()
}

fn report(gc: &Gc) -> ValidationReport {
    let m = mesh_gc(gc).unwrap();
    let r = validate(&m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    r
}

#[test]
fn straight_solid_volume_within_half_percent() {
    let (r, h) = (0.3, 1.2);
    let rep = report(&straight(r, h, ShapeType::Solid, Resolution::DEFAULT));
    let exact = PI * r * r * h;
    let rel = (rep.signed_volume - exact).abs() / exact;
    assert!(rel < 0.005, "relative error {rel}");
    assert_eq!(rep.genus, Some(0));
}

#[test]
fn shell_and_container_volumes() {
    let (r, h, t) = (0.3, 1.2, 0.04);
    let shell = report(&straight(
        r,
        h,
        ShapeType::Shell { thickness: t },
        Resolution::DEFAULT,
    ));
    let exact = PI * (r * r - (r - t) * (r - t)) * h;
    let rel = (shell.signed_volume - exact).abs() / exact;
    assert!(rel < 0.005, "shell relative error {rel}");
    assert_eq!(shell.genus, Some(1));
    for end in [ClosedEnd::Start, ClosedEnd::End] {
        let c = report(&straight(
            r,
            h,
            ShapeType::Container {
                thickness: t,
                closed_end: end,
            },
            Resolution::DEFAULT,
        ));
        let exact = PI * r * r * h - PI * (r - t) * (r - t) * (h - t);
        let rel = (c.signed_volume - exact).abs() / exact;
        assert!(rel < 0.005, "container relative error {rel}");
        assert_eq!(c.genus, Some(0));
    }
}

#[test]
fn rectangle_prism_volume_is_exact_to_rounding() {
    let spine = fit_spine(&[DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)], DVec3::X).unwrap();
    let rect = Profile::Rectangle {
        width: 0.5,
        height: 0.3,
    };
    let gc = Gc::new(
        spine,
        vec![
            KeySection::new(rect.clone(), 0.0),
            KeySection::new(rect, 1.0),
        ],
        ShapeType::Shell { thickness: 0.05 },
        Resolution::PREVIEW,
    )
    .unwrap();
    let rep = report(&gc);
    let exact = 2.0 * (0.5 * 0.3 - 0.4 * 0.2);
    assert!(
        (rep.signed_volume - exact).abs() < 1e-9,
        "{}",
        rep.signed_volume
    );
}

fn max_section_miss(gc: &Gc) -> f64 {
    let surf = gc.surface().unwrap();
    let (curves, vs) = gc.placed_sections().unwrap();
    let mut worst: f64 = 0.0;
    for (c, v) in curves.iter().zip(&vs) {
        for i in 0..=500 {
            let u = i as f64 / 500.0;
            worst = worst.max((surf.point(u, *v) - c.point(u)).length());
        }
    }
    worst
}

#[test]
fn loft_interpolates_every_section() {
    let mut gc = vase(ShapeType::Solid);
    assert!(max_section_miss(&gc) < 1e-9);
    gc.twist(2, 0.7).unwrap();
    gc.bend(2, gc.key_points()[2] + DVec3::new(0.2, 0.0, 0.0))
        .unwrap();
    assert!(max_section_miss(&gc) < 1e-9);
    report(&gc);
}

#[test]
fn insert_leaves_surface_unchanged() {
    let mut gc = vase(ShapeType::Solid);
    gc.twist(1, 0.4).unwrap();
    let before = gc.surface().unwrap();
    for v in [0.17, 0.61, 0.93] {
        gc.insert_section(v).unwrap();
    }
    assert_eq!(gc.sections.len(), 8);
    let after = gc.surface().unwrap();
    let worst = surface_gap::max_gap(&before, &after, 80);
    assert!(worst < 1e-9, "surface moved by {worst}");
    // The inserted sections are editable like any other.
    gc.resize(2, 1.3).unwrap();
    report(&gc);
}

#[test]
fn twist_keeps_end_sections_fixed() {
    let mut gc = vase(ShapeType::Solid);
    let (before, _) = gc.placed_sections().unwrap();
    gc.twist(2, 1.1).unwrap();
    let (after, _) = gc.placed_sections().unwrap();
    let k = after.len();
    assert_eq!(before[0], after[0]);
    assert_eq!(before[k - 1], after[k - 1]);
    assert!((gc.sections[2].twist - 1.1).abs() < 1e-15);
    // Linear propagation: section 1 at v = 0.3 gets 1.1 * 0.3 / 0.55.
    assert!((gc.sections[1].twist - 1.1 * 0.3 / 0.55).abs() < 1e-12);
    assert!(before[2] != after[2]);
    assert_eq!(gc.twist(0, 0.3), Err(GcError::EndSectionFixed(0)));
}

#[test]
fn bend_moves_the_key_point_in_plane() {
    let mut gc = vase(ShapeType::Solid);
    let target = gc.key_points()[1] + DVec3::new(0.3, 0.0, 0.05);
    gc.bend(1, target).unwrap();
    assert!((gc.key_points()[1] - target).length() < 1e-12);
    let bad = gc.key_points()[1] + DVec3::new(0.0, 0.5, 0.0);
    assert!(matches!(gc.bend(1, bad), Err(GcError::OffPlane { .. })));
    // Sections stay perpendicular to the new spine (RMF re-framing).
    let frames = gc.frames().unwrap();
    let f = frames.at(&gc.spine, gc.sections[1].v).unwrap();
    let t = gc.spine.curve.tangent(gc.sections[1].v);
    assert!((f.tangent - t).length() < 1e-12);
    assert!(f.r.dot(DVec3::Y).abs() > 1.0 - 1e-9);
    report(&gc);
}

/// The placed section `index` of `gc`, sampled, in its local frame
/// `(x, y)` about the spine point.
fn local_samples(gc: &Gc, index: usize) -> Vec<(f64, f64)> {
    let surf = gc.surface().unwrap();
    let v = gc.sections[index].v;
    let f = gc.frames().unwrap().at(&gc.spine, v).unwrap();
    (0..200)
        .map(|i| {
            let d = surf.point(i as f64 / 200.0, v) - f.origin;
            assert!(d.dot(f.tangent).abs() < 1e-12, "section off its plane");
            (d.dot(f.r), d.dot(f.s))
        })
        .collect()
}

/// Each of shift, delete, replace section and replace spine does what it
/// says (not only "the result is valid"), and a refused edit leaves the
/// GC as it was.
#[test]
fn shift_delete_replace_and_replace_spine() {
    let mut gc = vase(ShapeType::Shell { thickness: 0.02 });
    let orig = gc.clone();
    assert!(matches!(
        gc.shift(2, 0.9),
        Err(GcError::SectionOrder { .. })
    ));
    assert_eq!(gc, orig, "a refused shift changes nothing");
    // shift: only section 2's parameter changes; the section sits at the
    // spine point A(0.5), its profile unchanged (same local samples)
    let before = local_samples(&gc, 2);
    gc.shift(2, 0.5).unwrap();
    assert_eq!(gc.sections[2].v, 0.5);
    assert_eq!(gc.spine, orig.spine);
    for i in [0, 1, 3, 4] {
        assert_eq!(gc.sections[i], orig.sections[i]);
    }
    let after = local_samples(&gc, 2);
    for (a, b) in before.iter().zip(&after) {
        assert!((a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
    }
    // delete: the rectangle at 0.8 is gone, the others are untouched
    gc.delete_section(3).unwrap();
    let vs: Vec<f64> = gc.sections.iter().map(|s| s.v).collect();
    assert_eq!(vs, vec![0.0, 0.3, 0.5, 1.0]);
    assert_eq!(gc.sections[3], orig.sections[4]);
    // replace: section 1 is now the ellipse 0.35 x 0.3 (unit scale, no
    // twist), and the surface passes through it
    gc.replace_section(1, Profile::Ellipse { rx: 0.35, ry: 0.3 }, 0.0)
        .unwrap();
    assert_eq!(
        gc.sections[1].profile,
        Profile::Ellipse { rx: 0.35, ry: 0.3 }
    );
    assert_eq!((gc.sections[1].scale, gc.sections[1].twist), (1.0, 0.0));
    for (x, y) in local_samples(&gc, 1) {
        let e = (x / 0.35).fpowi(2) + (y / 0.3).fpowi(2);
        assert!(
            (e - 1.0).abs() < 1e-9,
            "a surface point at v = 0.3 is not on the ellipse: {e}"
        );
    }
    // replace spine: the new spine interpolates the points (chord length
    // parameters), sections keep their relative parameters and follow it
    let pts = [
        DVec3::ZERO,
        DVec3::new(0.2, 0.0, 0.5),
        DVec3::new(0.6, 0.0, 0.8),
    ];
    gc.replace_spine(&pts, DVec3::Y).unwrap();
    let (l1, l2) = (pts[1].distance(pts[0]), pts[2].distance(pts[1]));
    for (p, t) in pts.iter().zip([0.0, l1 / (l1 + l2), 1.0]) {
        let d = gc.spine.curve.point(t).distance(*p);
        assert!(d < 1e-12, "spine misses its point by {d}");
    }
    let vs: Vec<f64> = gc.sections.iter().map(|s| s.v).collect();
    assert_eq!(vs, vec![0.0, 0.3, 0.5, 1.0]);
    assert!(max_section_miss(&gc) < 1e-9);
    // the first (circle) section is centred on the new spine's start, the
    // ellipse keeps its size on the new spine
    let c0 = local_samples(&gc, 0);
    let mean = c0.iter().fold((0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    assert!(mean.0.abs() < 1e-9 && mean.1.abs() < 1e-9);
    for (x, y) in local_samples(&gc, 1) {
        assert!(((x / 0.35).fpowi(2) + (y / 0.3).fpowi(2) - 1.0).abs() < 1e-9);
    }
    let rep = report(&gc);
    assert_eq!(rep.genus, Some(1));
    let mut two = straight(0.3, 1.0, ShapeType::Solid, Resolution::PREVIEW);
    assert_eq!(
        two.delete_section(0),
        Err(GcError::TooFewSections { got: 1 })
    );
}

#[test]
fn thickness_at_or_above_inscribed_radius_is_an_error() {
    let gc = straight(
        0.3,
        1.0,
        ShapeType::Shell { thickness: 0.3 },
        Resolution::PREVIEW,
    );
    assert!(matches!(
        mesh_gc(&gc),
        Err(GcError::ThicknessTooLarge { .. })
    ));
    let gc = straight(
        0.3,
        0.05,
        ShapeType::Container {
            thickness: 0.1,
            closed_end: ClosedEnd::Start,
        },
        Resolution::PREVIEW,
    );
    assert!(matches!(
        mesh_gc(&gc),
        Err(GcError::ThicknessTooLarge { .. })
    ));
}

#[test]
fn bad_profiles_are_typed_errors() {
    let bow = Profile::Points {
        points: vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],
    };
    assert!(matches!(bow.curve(), Err(GcError::DegenerateSection(_))));
    assert!(matches!(
        Profile::Circle { radius: f64::NAN }.curve(),
        Err(GcError::NonFinite(_))
    ));
    assert!(matches!(
        Profile::Polygon {
            sides: 2,
            radius: 1.0
        }
        .curve(),
        Err(GcError::TooFewSides(2))
    ));
    assert!(matches!(
        fit_spine(&[DVec3::ONE, DVec3::ONE], DVec3::X),
        Err(GcError::ZeroLengthSpine)
    ));
    assert!(matches!(
        fit_spine(
            &[DVec3::ZERO, DVec3::Z, DVec3::new(1.0, 1.0, 2.0)],
            DVec3::X
        ),
        Err(GcError::NonPlanarSpine { .. })
    ));
}
