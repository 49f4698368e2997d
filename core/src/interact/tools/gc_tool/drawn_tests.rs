//! Issue 33's older findings in the GC tool: a section template keeps the
//! turn it was drawn at (creating a part and replacing a section), and a
//! sketched spine stays within the spine tolerance of the stroke (the
//! cubic through the stroke's RDP points alone could overshoot a tight
//! bend).

use crate::doc::{Op, OpLog};
use crate::gc::Profile;
use crate::interact::gesture::GestureLabel;
use crate::interact::testkit::gc_traces::{
    create, loop_points, mug_body, outward, path, ring, Rig,
};
use crate::interact::trace::ModelPlacement;
use crate::math::fm::DetMath as _;
use crate::math::DVec3;

use super::tests::{body, ops, run};
use super::GcToolSettings;

fn rig() -> Rig {
    Rig::new(ModelPlacement::desk())
}

/// The world direction of a GC part's first section's local `x` axis
/// (an ellipse's `rx`, a rectangle's width), from its placed curve.
fn first_axis(log: &OpLog, part: usize) -> DVec3 {
    let asm = super::tests::assembly(log, 1);
    let gc = &asm.parts[part].gc;
    let (curves, _) = gc.placed_sections().expect("placed");
    let c = &curves[0];
    // The curve's start is the profile's local +x extreme, its centre the
    // spine's key point.
    (c.point(0.0) - gc.key_points()[0]).normalize()
}

/// An ellipse drawn with its long axis at 45 degrees in the sketch plane
/// makes a part whose sections lie that way (the twist carries the turn;
/// before, every section lay along the spine plane's normal).
#[test]
fn a_diagonal_ellipse_makes_a_diagonal_part() {
    let mut r = rig();
    let o = DVec3::new(0.05, 0.0, 0.06);
    let diag = (DVec3::Y + DVec3::Z).normalize();
    let other = (DVec3::Z - DVec3::Y).normalize();
    let sec = loop_points(o + DVec3::X * 0.06, diag, other, 0.016, 0.008, 32);
    let pt = |a: f64| o + DVec3::X * a;
    let spine = path(&[pt(0.0), pt(0.03), pt(0.07)], 8);
    create(&mut r, o, DVec3::new(0.2, -0.1, 0.05), &sec, &spine);
    let run = run(&[body()], &r);
    assert_eq!(run.rejected, 0);
    let Op::GcAddChild(c) = ops(&run)[0] else {
        panic!("expected gc_add_child, got {:?}", ops(&run));
    };
    assert!(
        matches!(c.sections[0].profile, Profile::Ellipse { .. }),
        "{:?}",
        c.sections[0].profile
    );
    let axis = first_axis(&run.log, 1);
    let cos = axis.dot(diag).abs();
    assert!(
        cos > 10f64.to_radians().fcos(),
        "the ellipse's long axis {axis} is {:.1} degrees from the drawn one",
        cos.facos().to_degrees()
    );
}

/// POINT in empty space, a section, then a spine, with no assembly in the
/// document (the mug's body, as its trace draws it): a new assembly
/// (`gc_create`) whose first section is the drawn circle.
#[test]
pub(crate) fn a_section_then_a_spine_in_empty_space_make_a_new_assembly() {
    let mut r = rig();
    mug_body(&mut r);
    let run = run(&[], &r);
    assert_eq!(run.rejected, 0);
    let [Op::GcCreate(c)] = ops(&run)[..] else {
        panic!("expected one gc_create, got {:?}", ops(&run));
    };
    assert!(
        matches!(c.0.sections[0].profile, Profile::Circle { .. }),
        "{:?}",
        c.0.sections[0].profile
    );
    assert_eq!(super::tests::assembly(&run.log, 1).parts.len(), 1);
}

/// A rectangle drawn turned by 30 degrees on a section replaces it turned
/// by 30 degrees.
#[test]
fn a_turned_rectangle_replaces_a_section_turned() {
    let mut r = rig();
    let at = ring(0.05, -50.0, 0.04);
    let c = DVec3::new(0.0, -0.1, 0.04);
    let turn = 30f64.to_radians();
    let (ex, ey) = (
        DVec3::new(turn.fcos(), turn.fsin(), 0.0),
        DVec3::new(-turn.fsin(), turn.fcos(), 0.0),
    );
    let corners = [
        (-1.0, -1.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (-1.0, 1.0),
        (-1.0, -1.0),
    ]
    .map(|(x, y)| c + ex * (x * 0.05) + ey * (y * 0.03));
    r.select(at, outward(-50.0, 0.2, 0.08), GestureLabel::Point)
        .gesture(GestureLabel::Open, 0.15)
        .stroke(&path(&corners, 8));
    let run = run(&[body()], &r);
    assert_eq!(run.rejected, 0);
    let Op::GcReplaceSection(e) = ops(&run)[0] else {
        panic!("expected gc_replace_section, got {:?}", ops(&run));
    };
    assert!(
        matches!(e.profile, Profile::Rectangle { .. }),
        "{:?}",
        e.profile
    );
    // The rectangle's width is along the drawn long side, whichever of
    // its two symmetric turns.
    let asm = super::tests::assembly(&run.log, 1);
    let gc = &asm.parts[0].gc;
    let (curves, _) = gc.placed_sections().expect("placed");
    let k = e.section.0;
    let width_dir = (curves[k].point(0.0) - gc.key_points()[k]).normalize();
    let cos = width_dir.dot(ex).abs();
    assert!(
        cos > 8f64.to_radians().fcos(),
        "the width lies {:.1} degrees from the drawn side",
        cos.facos().to_degrees()
    );
}

/// Largest distance of the stroke's points from the spine a part got.
fn stroke_to_spine(stroke: &[DVec3], spine: &crate::gc::Spine) -> f64 {
    let dense = spine.curve.polyline(4096);
    stroke
        .iter()
        .map(|p| {
            dense
                .windows(2)
                .map(|w| {
                    let ab = w[1] - w[0];
                    let t = ((*p - w[0]).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                    (w[0] + ab * t - *p).length()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// A spout sketched as a long straight run ending in a tight hook: its
/// spine stays within the spine tolerance of the stroke (RDP keeps only
/// the run's ends, and the cubic through them overshot the hook).
#[test]
fn a_sketched_spine_stays_within_its_tolerance_of_the_stroke() {
    let mut r = rig();
    let o = DVec3::new(0.05, 0.0, 0.06);
    let sec = loop_points(o + DVec3::X * 0.06, DVec3::Y, DVec3::Z, 0.006, 0.006, 24);
    let pt = |a: f64, b: f64| o + DVec3::X * a + DVec3::Z * b;
    let stroke = path(
        &[pt(0.0, 0.0), pt(0.08, 0.0), pt(0.095, 0.004), pt(0.1, 0.02)],
        12,
    );
    create(&mut r, o, DVec3::new(0.2, -0.1, 0.05), &sec, &stroke);
    let run = run(&[body()], &r);
    assert_eq!(run.rejected, 0);
    let asm = super::tests::assembly(&run.log, 1);
    let spine = &asm.parts[1].gc.spine;
    // The child's spine starts sunk into the body along -x: compare with
    // the stroke moved the same way.
    let start = spine.curve.point(spine.curve.domain().0);
    let shift = start - stroke[0];
    let moved: Vec<DVec3> = stroke.iter().map(|p| *p + shift).collect();
    let tol = GcToolSettings::default().spine_tolerance;
    let d = stroke_to_spine(&moved, spine);
    // The tracked fingertip wobbles a little: half a tolerance of slack.
    assert!(
        d <= 1.5 * tol,
        "the spine strays {d} from the stroke (tolerance {tol})"
    );
}
