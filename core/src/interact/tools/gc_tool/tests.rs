//! Tests of the GC tool: every Figure 10 transition through the whole
//! pipeline (raw joints -> sanitizer -> classifier -> tool -> op), the bad
//! inputs of issue 8, and the recorded mug and teapot traces.

use crate::doc::{Create, Op, OpLog, ScriptCommand};
use crate::gc::{GcCreate, SectionSpec};
use crate::gc::{Profile, Resolution, ShapeType};
use crate::math::DVec3;
use crate::mesh::{validate, ValidationSettings};

use super::GcTool;
use crate::interact::gesture::GestureLabel;
use crate::interact::input::{Hand, InputFrame, Joint, Pose};
use crate::interact::session::Session;
use crate::interact::testkit::gc_traces::{create, loop_points, outward, path, ring, Rig};
use crate::interact::testkit::{mug_trace, teapot_trace};
use crate::interact::tools::Tool;
use crate::interact::trace::{replay, ModelPlacement, Trace};

/// A cylinder r = 5 cm, 12 cm tall, 4 sections at z = 0, 4, 8, 12 cm.
pub(super) fn body() -> Op {
    Op::GcCreate(Create(GcCreate {
        spine: vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 0.12)],
        plane_normal: DVec3::Y,
        sections: (0..4)
            .map(|i| SectionSpec {
                profile: Profile::Circle { radius: 0.05 },
                v: i as f64 / 3.0,
                scale: 1.0,
                twist: 0.0,
            })
            .collect(),
        shape: ShapeType::Solid,
        resolution: Resolution { u: 48, v: 32 },
    }))
}

pub(super) struct Run {
    commands: Vec<ScriptCommand>,
    pub(super) log: OpLog,
    pub(super) rejected: usize,
}

fn run_frames(start: &[Op], frames: &[InputFrame]) -> Run {
    run_tool(GcTool::default(), start, frames)
}

fn run_tool(tool: GcTool, start: &[Op], frames: &[InputFrame]) -> Run {
    let model = ModelPlacement::desk().similarity().expect("desk");
    let mut session = Session::new(Box::new(tool), model);
    let mut log = OpLog::new();
    for op in start {
        log.apply(op.clone()).expect("start op");
    }
    let mut commands = Vec::new();
    let mut rejected = 0;
    for f in frames {
        if let Some(c) = session.step(f, log.document()) {
            if log.apply_command(&c).is_err() {
                rejected += 1;
            }
            commands.push(c);
        }
    }
    Run {
        commands,
        log,
        rejected,
    }
}

pub(super) fn run(start: &[Op], r: &Rig) -> Run {
    run_frames(start, &r.trace("").frames)
}

pub(super) fn ops(run: &Run) -> Vec<&Op> {
    run.commands
        .iter()
        .filter_map(|c| match c {
            ScriptCommand::Op(op) => Some(op),
            _ => None,
        })
        .collect()
}

fn names(run: &Run) -> Vec<&'static str> {
    ops(run).iter().map(|o| o.name()).collect()
}

fn rig() -> Rig {
    Rig::new(ModelPlacement::desk())
}

fn edit_of(run: &Run) -> crate::assembly::PartEdit {
    match ops(run).as_slice() {
        [Op::GcEditPart(e)] => e.edit.edit.clone(),
        other => panic!("expected one gc_edit_part, got {other:?}"),
    }
}

const A: f64 = -50.0;

#[test]
pub(crate) fn fist_on_a_section_resizes_shifts_or_twists_by_the_motion_component() {
    use crate::assembly::PartEdit;
    let at = ring(0.05, A, 0.08);
    let from = outward(A, 0.2, 0.08);
    let mut r = rig();
    r.fist_drag(at, from, ring(0.01, A, 0.0));
    match edit_of(&run(&[body()], &r)) {
        PartEdit::Resize { section, factor } => {
            assert_eq!(section, crate::gc::SectionIndex(2));
            assert!((factor - 1.2).abs() < 0.04, "factor {factor}");
        }
        e => panic!("expected a resize, got {e:?}"),
    }
    let mut r = rig();
    r.fist_drag(at, from, DVec3::new(0.0, 0.0, -0.01));
    match edit_of(&run(&[body()], &r)) {
        PartEdit::Shift { section, v } => {
            assert_eq!(section, crate::gc::SectionIndex(2));
            // Arc length 12 cm over v in [0, 1]: 1 cm is 1/12.
            assert!((v - (2.0 / 3.0 - 1.0 / 12.0)).abs() < 0.01, "v {v}");
        }
        e => panic!("expected a shift, got {e:?}"),
    }
    let mut r = rig();
    let tangent = DVec3::Z.cross(ring(1.0, A, 0.0)) * 0.01;
    r.fist_drag(at, from, tangent);
    match edit_of(&run(&[body()], &r)) {
        PartEdit::Twist { section, angle } => {
            assert_eq!(section, crate::gc::SectionIndex(2));
            assert!((angle - 0.2).abs() < 0.03, "angle {angle}");
        }
        e => panic!("expected a twist, got {e:?}"),
    }
}

#[test]
pub(crate) fn fist_on_a_key_point_bends_within_the_spine_plane() {
    use crate::assembly::PartEdit;
    let mut r = rig();
    let key = DVec3::new(0.0, 0.0, 0.08);
    r.fist_drag(
        key,
        DVec3::new(0.06, -0.2, 0.1),
        DVec3::new(0.02, 0.01, 0.0),
    );
    match edit_of(&run(&[body()], &r)) {
        PartEdit::Bend { section, to } => {
            assert_eq!(section, crate::gc::SectionIndex(2));
            assert!(to.y.abs() < 1e-12, "off the spine plane: {to}");
            assert!((to - DVec3::new(0.02, 0.0, 0.08)).length() < 0.003, "{to}");
        }
        e => panic!("expected a bend, got {e:?}"),
    }
}

#[test]
pub(crate) fn point_on_the_surface_sketches_a_child_section_and_spine() {
    let mut r = rig();
    let o = DVec3::new(0.05, 0.0, 0.06);
    let sec = loop_points(o + DVec3::X * 0.06, DVec3::Y, DVec3::Z, 0.012, 0.012, 24);
    let pt = |a: f64, b: f64| o + DVec3::X * a + DVec3::Z * b;
    let spine = path(&[pt(0.0, 0.0), pt(0.04, 0.02), pt(0.07, 0.06)], 8);
    create(&mut r, o, DVec3::new(0.2, -0.1, 0.05), &sec, &spine);
    let run = run(&[body()], &r);
    assert_eq!(names(&run), ["gc_add_child"]);
    assert_eq!(run.rejected, 0);
    let Op::GcAddChild(c) = ops(&run)[0] else {
        unreachable!()
    };
    assert_eq!(c.end, crate::assembly::ChildEnd::Free);
    let Profile::Circle { radius } = c.sections[0].profile else {
        panic!("expected a circle, got {:?}", c.sections[0].profile);
    };
    assert!((radius - 0.012).abs() < 0.002, "radius {radius}");
    let end = c.spine.last().expect("spine");
    let depth = c.spine[0][0];
    assert!((end[0] - depth - 0.07).abs() < 0.004 && (end[1] - 0.06).abs() < 0.004);
    let mesh = run.log.document().printable_mesh().expect("union");
    let rep = validate(&mesh, &ValidationSettings::default());
    assert!(rep.is_closed_manifold(), "{rep:?}");
    assert_eq!(rep.components, 1);
}

#[test]
pub(crate) fn point_on_a_section_replaces_it_by_a_sketch() {
    let mut r = rig();
    let at = ring(0.05, A, 0.04);
    // A square loop around the section's plane.
    let c = DVec3::new(0.0, -0.1, 0.04);
    let sq = [
        (-1.0, -1.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (-1.0, 1.0),
        (-1.0, -1.0),
    ]
    .map(|(x, y)| c + DVec3::new(x * 0.04, y * 0.04, 0.0));
    r.select(at, outward(A, 0.2, 0.08), GestureLabel::Point)
        .gesture(GestureLabel::Open, 0.15)
        .stroke(&path(&sq, 8));
    let run1 = run(&[body()], &r);
    assert_eq!(names(&run1), ["gc_replace_section"]);
    assert_eq!(run1.rejected, 0);
}

#[test]
pub(crate) fn point_on_a_key_point_replaces_the_spine_by_a_sketch() {
    let mut r = rig();
    let key = DVec3::new(0.0, 0.0, 0.08);
    let spine = path(
        &[
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.02, 0.0, 0.06),
            DVec3::new(0.0, 0.0, 0.12),
        ],
        10,
    );
    r.select(key, DVec3::new(0.06, -0.2, 0.1), GestureLabel::Point)
        .gesture(GestureLabel::Open, 0.15)
        .stroke(&spine);
    let run2 = run(&[body()], &r);
    assert_eq!(names(&run2), ["gc_replace_spine"]);
    assert_eq!(run2.rejected, 0);
    // The new spine is the sketch: in the spine plane (y = 0), from the
    // old start, bulging 2 cm towards +x at 6 cm.
    let Op::GcReplaceSpine(rs) = ops(&run2)[0] else {
        unreachable!()
    };
    assert!(
        rs.points.iter().all(|p| p.y.abs() < 1e-9),
        "{:?}",
        rs.points
    );
    assert!(rs.points[0].length() < 0.004, "start {}", rs.points[0]);
    let bulge = rs.points.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    assert!((bulge - 0.02).abs() < 0.004, "bulge {bulge}");
    let top = rs.points.last().expect("points");
    assert!((top.z - 0.12).abs() < 0.008, "end {top}");
}

#[test]
pub(crate) fn an_open_hold_on_a_section_deletes_it() {
    let mut r = rig();
    r.aim(ring(0.05, A, 0.04), outward(A, 0.2, 0.08), 0.3)
        .wait(4.5);
    let run1 = run(&[body()], &r);
    assert_eq!(names(&run1), ["gc_delete_section"]);
}

#[test]
pub(crate) fn an_open_hold_on_the_surface_inserts_a_section_once() {
    // Aimed level: a ray from above would pass within the X-ray pick
    // radius of the key point at z = 8 cm and pick it instead.
    let mut r = rig();
    r.aim(ring(0.05, A, 0.1), outward(A, 0.2, 0.0), 0.3)
        .wait(3.4);
    let run2 = run(&[body()], &r);
    assert_eq!(names(&run2), ["gc_insert_section"]);
    let Op::GcInsertSection(i) = ops(&run2)[0] else {
        unreachable!()
    };
    assert!((i.v - 0.1 / 0.12).abs() < 0.03, "v {}", i.v);
    // 2.5 s is not a hold.
    let mut r = rig();
    r.aim(ring(0.05, A, 0.1), outward(A, 0.2, 0.0), 0.3)
        .wait(2.5);
    assert!(run(&[body()], &r).commands.is_empty());
}

#[test]
pub(crate) fn a_static_fist_for_three_seconds_instances_the_part_then_moves_the_copy() {
    let mut r = rig();
    let at = ring(0.05, A, 0.1);
    r.select(at, outward(A, 0.2, 0.0), GestureLabel::Fist)
        .wait(3.2)
        .drag(DVec3::new(0.15, 0.0, 0.0), 0.5)
        .wait(0.25)
        .gesture(GestureLabel::Open, 0.15)
        .wait(0.1);
    let run = run(&[body()], &r);
    assert_eq!(names(&run), ["gc_copy", "gc_transform_part"]);
    assert_eq!(run.rejected, 0);
    let Op::GcTransformPart(t) = ops(&run)[1] else {
        unreachable!()
    };
    assert_eq!(t.part, crate::gc::PartId(1));
    assert!((t.translate - DVec3::new(0.15, 0.0, 0.0)).length() < 0.004);
}

/// Issue 18: a FIST instance of a child (the mug's handle) is a plain
/// copy where the hand drops it; a mirrored one only when the palette's
/// "Instance: mirror" is chosen (the op the tool sends; the gesture that
/// triggers it is tested above on the body).
#[test]
fn instancing_a_child_copies_it_unmirrored_unless_mirror_is_chosen() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/mug.jsonl"),
    )
    .unwrap();
    let start: Vec<Op> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let mut log = OpLog::new();
    for op in &start {
        log.apply(op.clone()).unwrap();
    }
    let (mug, obj) = log.document().objects().next().unwrap();
    let crate::doc::ObjectKind::GcAssembly(asm) = &obj.kind else {
        panic!("the mug is an assembly")
    };
    assert!(asm.parts[1].parent.is_some(), "part 1 is the handle");
    let mut tool = GcTool::default();
    let doc = crate::doc::Document::default();
    assert_eq!(tool.choices()[0].active, 0, "copy by default");
    let plain = super::tool::instance_op(asm, 1, tool.choices()[0].active == 1).unwrap();
    assert!(!plain.mirror);
    assert!(tool.choose(&doc, 0, 1).is_none());
    assert_eq!(tool.choices()[0].active, 1);
    let mirrored = super::tool::instance_op(asm, 1, true).unwrap();
    assert!(mirrored.mirror);
    // A root is never mirrored; a part that is not there is no copy.
    assert!(!super::tool::instance_op(asm, 0, true).unwrap().mirror);
    assert!(super::tool::instance_op(asm, 9, false).is_none());
    // The copy applies: a new part, not a twin of the handle.
    let mut after = log.clone();
    after
        .apply(Op::GcCopy(crate::doc::Edit::new(mug, plain)))
        .unwrap();
}

#[test]
pub(crate) fn pinch_on_an_end_section_sets_the_shape_type() {
    let mut r = rig();
    r.pinch(ring(0.05, A, 0.118), outward(A, 0.2, 0.08));
    let run = run(&[body()], &r);
    match ops(&run).as_slice() {
        [Op::GcSetShape(s)] => match s.shape {
            ShapeType::Container {
                thickness,
                closed_end,
            } => {
                assert_eq!(closed_end, crate::gc::ClosedEnd::Start);
                assert!((0.0015..=0.012).contains(&thickness));
            }
            other => panic!("expected a container, got {other:?}"),
        },
        other => panic!("expected one gc_set_shape, got {other:?}"),
    }
}

/// PINCH's finger gap sets the wall thickness: the gap times
/// `thickness_per_gap`, clamped to `thickness_range` (the rig test above
/// only checks that some thickness in the range comes out, which a
/// constant would pass).
#[test]
fn pinch_thickness_follows_the_finger_gap() {
    use super::edit::pinch_shape;
    use crate::gc::ClosedEnd;
    let s = super::GcToolSettings::default();
    let (lo, hi) = s.thickness_range;
    let thick = |shape: ShapeType, gap: f64| match pinch_shape(
        shape,
        ClosedEnd::Start,
        Some(gap),
        false,
        &s,
    ) {
        ShapeType::Shell { thickness } | ShapeType::Container { thickness, .. } => thickness,
        other => panic!("a pinch with a gap gave {other:?}"),
    };
    let shell = ShapeType::Shell { thickness: 0.005 };
    for gap in [0.03, 0.05, 0.1] {
        let t = thick(shell, gap);
        assert!(
            (t - gap * s.thickness_per_gap).abs() < 1e-15,
            "gap {gap} gave {t}"
        );
        assert_eq!(thick(ShapeType::Solid, gap), t, "same rule from a solid");
    }
    assert!(
        thick(shell, 0.05) < thick(shell, 0.1),
        "a wider gap, a thicker wall"
    );
    assert_eq!(thick(shell, 0.001), lo, "clamped below");
    assert_eq!(thick(shell, 1.0), hi, "clamped above");
}

#[test]
fn bimanual_fist_in_empty_space_scales_the_view_without_an_op() {
    let mut r = rig();
    let left = Pose::new(DVec3::new(-0.15, 1.2, -0.25), r.wrist().orientation);
    r.aim(DVec3::new(0.3, 0.0, 0.0), DVec3::new(0.0, -0.2, 0.3), 0.3)
        .wait(0.2);
    r.p.hand(Hand::Left, GestureLabel::Open, left);
    r.wait(0.1).gesture(GestureLabel::Fist, 0.15);
    r.p.gesture(Hand::Left, GestureLabel::Fist, 0.15);
    r.wait(0.1);
    r.p.move_to(
        Hand::Left,
        Pose::new(DVec3::new(-0.3, 1.2, -0.25), left.orientation),
        0.5,
    );
    let frames = r.trace("").frames;
    let model = ModelPlacement::desk().similarity().expect("desk");
    let mut session = Session::new(Box::new(GcTool::default()), model);
    let mut log = OpLog::new();
    log.apply(body()).expect("body");
    let before = log.document().content_hash();
    for f in &frames {
        assert!(session.step(f, log.document()).is_none());
    }
    assert_eq!(log.document().content_hash(), before);
    let view = session
        .preview()
        .gc()
        .expect("the GC tool's preview")
        .view
        .expect("a view change");
    assert!(view.scale > 1.2, "scale {}", view.scale);
}

fn drag_rig() -> (Rig, DVec3, DVec3) {
    let mut r = rig();
    let at = ring(0.05, A, 0.08);
    let from = outward(A, 0.2, 0.08);
    r.select(at, from, GestureLabel::Fist)
        .drag(ring(0.005, A, 0.0), 0.3);
    (r, at, from)
}

#[test]
fn nan_joints_are_dropped_and_change_nothing() {
    let (mut r, _, _) = drag_rig();
    r.drag(ring(0.005, A, 0.0), 0.3)
        .wait(0.2)
        .gesture(GestureLabel::Open, 0.15)
        .wait(0.1);
    let clean = r.trace("").frames;
    let mut dirty = clean.clone();
    for (i, f) in dirty.iter_mut().enumerate() {
        if i % 7 == 3 {
            if let Some(h) = f.hands[1].as_mut() {
                h.joints[Joint::IndexProximal.index()].pose.position.x = f64::NAN;
                h.joints[Joint::Wrist.index()].pose.orientation.w = f64::NAN;
            }
        }
    }
    let a = run_frames(&[body()], &clean);
    let b = run_frames(&[body()], &dirty);
    assert_eq!(names(&a), ["gc_edit_part"]);
    assert_eq!(names(&b), ["gc_edit_part"]);
    // Only NaN frames: nothing at all.
    let mut all_nan = clean;
    for f in &mut all_nan {
        if let Some(h) = f.hands[1].as_mut() {
            for j in h.joints.iter_mut() {
                j.pose.position.y = f64::NAN;
            }
        }
    }
    let c = run_frames(&[body()], &all_nan);
    assert!(c.commands.is_empty());
}

#[test]
fn a_hand_that_vanishes_mid_drag_or_mid_sketch_leaves_the_document_unchanged() {
    let (mut r, _, _) = drag_rig();
    r.p.hide_hand(Hand::Right);
    r.wait(1.0);
    let w = r.wrist();
    r.p.hand(Hand::Right, GestureLabel::Open, w);
    r.wait(0.5);
    let run1 = run(&[body()], &r);
    assert!(run1.commands.is_empty(), "{:?}", names(&run1));
    // Mid-sketch of a child's spine.
    let mut r = rig();
    let o = DVec3::new(0.05, 0.0, 0.06);
    let sec = loop_points(o + DVec3::X * 0.06, DVec3::Y, DVec3::Z, 0.012, 0.012, 24);
    r.select(o, DVec3::new(0.2, -0.1, 0.05), GestureLabel::Point)
        .gesture(GestureLabel::Open, 0.15)
        .stroke(&sec)
        .pen_to(o, 0.3)
        .gesture(GestureLabel::Point, 0.15)
        .pen_to(o + DVec3::X * 0.05, 0.3);
    r.p.hide_hand(Hand::Right);
    r.wait(1.0);
    let w = r.wrist();
    r.p.hand(Hand::Right, GestureLabel::Open, w);
    r.wait(0.5);
    assert!(run(&[body()], &r).commands.is_empty());
}

#[test]
fn tracking_lost_during_a_drag_resumes_within_grace_or_cancels() {
    use crate::assembly::PartEdit;
    // 0.1 s gap: the drag continues and commits once.
    let (mut r, _, _) = drag_rig();
    r.p.hide_hand(Hand::Right);
    r.wait(0.1);
    let w = r.wrist();
    r.p.hand(Hand::Right, GestureLabel::Fist, w);
    r.drag(ring(0.005, A, 0.0), 0.3)
        .wait(0.25)
        .gesture(GestureLabel::Open, 0.15)
        .wait(0.1);
    match edit_of(&run(&[body()], &r)) {
        PartEdit::Resize { factor, .. } => assert!((factor - 1.2).abs() < 0.05, "{factor}"),
        e => panic!("expected a resize, got {e:?}"),
    }
    // 0.6 s gap: cancelled; the hand comes back in FIST and opens: no op.
    let (mut r, _, _) = drag_rig();
    r.p.hide_hand(Hand::Right);
    r.wait(0.6);
    let w = r.wrist();
    r.p.hand(Hand::Right, GestureLabel::Fist, w);
    r.wait(0.2).gesture(GestureLabel::Open, 0.15).wait(0.2);
    assert!(run(&[body()], &r).commands.is_empty());
}

#[test]
fn a_teleporting_hand_commits_the_drag_it_had_before_the_jump() {
    use crate::assembly::PartEdit;
    let (mut r, _, _) = drag_rig();
    r.wait(0.3);
    r.p.teleport(Hand::Right, DVec3::new(0.0, 0.5, 0.0));
    r.wait(0.3).gesture(GestureLabel::Open, 0.15).wait(0.2);
    let run = run(&[body()], &r);
    assert_eq!(run.rejected, 0);
    match edit_of(&run) {
        PartEdit::Resize { factor, .. } => assert!((factor - 1.1).abs() < 0.03, "{factor}"),
        e => panic!("expected a resize, got {e:?}"),
    }
}

/// Replays a recorded trace (checked fresh against its puppet script):
/// the op names must be `expected`, nothing rejected, the printable model
/// one closed 2-manifold of genus `genus`, and a second replay bit-identical.
fn check_trace(file: &str, expected: &[&str], genus: i64, fresh: &Trace) -> crate::doc::OpLog {
    let path = format!("{}/../tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("trace file");
    assert!(text.len() < 4_000_000, "{file} is {} bytes", text.len());
    let trace = Trace::from_jsonl(&text).expect("parse");
    assert_eq!(
        &trace, fresh,
        "{file} is stale: regenerate with `cargo run -p shapewright --example make_traces`"
    );
    let a = replay(&trace).expect("replay");
    let kinds: Vec<&str> = a.commands.iter().map(ScriptCommand::name).collect();
    assert_eq!(kinds, expected, "{file}");
    assert!(a.rejected.is_empty(), "{:?}", a.rejected);
    let mesh = a.log.document().printable_mesh().expect("union");
    let rep = validate(&mesh, &ValidationSettings::default());
    assert!(rep.is_closed_manifold(), "{file}: {rep:?}");
    assert_eq!(rep.components, 1, "{file}");
    assert_eq!(rep.genus, Some(genus), "{file}: {rep:?}");
    let b = replay(&trace).expect("replay");
    assert_eq!(
        a.log.document().content_hash(),
        b.log.document().content_hash()
    );
    a.log
}

pub(super) fn assembly(log: &OpLog, id: u32) -> crate::gc::GcAssembly {
    match &log
        .document()
        .get(crate::doc::ObjectId(id))
        .expect("object")
        .kind
    {
        crate::doc::ObjectKind::GcAssembly(a) => a.clone(),
        other => panic!("object {id} is not an assembly: {other:?}"),
    }
}

#[test]
fn mug_trace_replays_to_a_printable_mug() {
    let log = check_trace(
        "mug.trace.jsonl",
        &["gc_create", "gc_edit_part", "gc_set_shape", "gc_add_child"],
        1,
        &mug_trace(),
    );
    let mug = assembly(&log, 1);
    assert_eq!(mug.parts.len(), 2);
    assert!(matches!(mug.parts[0].gc.shape, ShapeType::Container { .. }));
}

#[test]
fn teapot_trace_replays_to_a_printable_teapot() {
    let log = check_trace(
        "teapot.trace.jsonl",
        &[
            // Body: create, shape three rings, open the top.
            "gc_create",
            "gc_edit_part",
            "gc_edit_part",
            "gc_edit_part",
            "gc_set_shape",
            // Spout: create, taper the tip, open it (a tube).
            "gc_add_child",
            "gc_edit_part",
            "gc_set_shape",
            // Handle.
            "gc_add_child",
            // Lid: create, dome, insert a knob section, pinch it, place it.
            "gc_create",
            "gc_edit_part",
            "gc_edit_part",
            "gc_insert_section",
            "gc_edit_part",
            "gc_transform_part",
        ],
        // The handle, and the passage in at the spout (its channel opens
        // through the body's wall) and out past the lid, which rests in
        // the opening without sealing it.
        2,
        &teapot_trace(),
    );
    let pot = assembly(&log, 1);
    assert_eq!(pot.parts.len(), 3);
    assert!(matches!(pot.parts[0].gc.shape, ShapeType::Container { .. }));
    assert!(matches!(pot.parts[1].gc.shape, ShapeType::Shell { .. }));
    // Hand-drawn rings are circles (not 9-gons).
    for part in &pot.parts[1..] {
        for sec in &part.gc.sections {
            assert!(
                matches!(sec.profile, Profile::Circle { .. }),
                "{:?}",
                sec.profile
            );
        }
    }
    let lid = assembly(&log, 2);
    assert_eq!(lid.parts[0].gc.sections.len(), 4);
    // The lid sits on the body's rim.
    let bottom = lid.parts[0].gc.spine.curve.point(0.0);
    assert!((bottom.z - 0.155).abs() < 0.01, "lid bottom at {bottom}");
}

/// The same scripts with a controller instead of a tracked hand (buttons
/// stand for the gestures): the same op sequence, a printable model.
#[test]
fn controller_traces_build_the_same_models_as_the_hand_traces() {
    for (hand, ctl) in [
        (
            mug_trace(),
            crate::interact::testkit::mug_controller_trace(),
        ),
        (
            teapot_trace(),
            crate::interact::testkit::teapot_controller_trace(),
        ),
    ] {
        assert!(ctl.frames.iter().all(|f| f.hands == [None, None]));
        let a = replay(&hand).expect("replay");
        let b = replay(&ctl).expect("replay");
        let names = |r: &crate::interact::trace::Replay| -> Vec<&'static str> {
            r.commands.iter().map(ScriptCommand::name).collect()
        };
        assert_eq!(names(&a), names(&b), "{}", ctl.header.note);
        assert!(b.rejected.is_empty(), "{:?}", b.rejected);
        let mesh = b.log.document().printable_mesh().expect("union");
        let rep = validate(&mesh, &ValidationSettings::default());
        assert!(rep.is_closed_manifold(), "{rep:?}");
        assert_eq!(rep.components, 1, "{}: {rep:?}", ctl.header.note);
        let va = validate(
            &a.log.document().printable_mesh().expect("union"),
            &Default::default(),
        )
        .signed_volume;
        // The hand jitters, the controller does not: sizes differ a little.
        assert!(
            (rep.signed_volume - va).abs() < 0.1 * va,
            "{} vs {va}",
            rep.signed_volume
        );
    }
}
