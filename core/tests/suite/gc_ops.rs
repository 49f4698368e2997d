//! GC ops through the op log: undo/redo/replay are bit-identical, bad
//! input is a typed error that leaves the document unchanged, and JSON
//! op scripts round-trip.

use glam::DVec3;
use shapewright::doc::{Create, Edit, LogError, ObjectId, Op, OpError, OpLog};
use shapewright::gc::*;
use shapewright::gc::{ClosedEnd, GcError, Profile, Resolution, ShapeType};
use shapewright::mesh::validate;

fn create(shape: ShapeType) -> Op {
    Op::GcCreate(Create(GcCreate {
        spine: vec![
            DVec3::ZERO,
            DVec3::new(0.1, 0.0, 0.5),
            DVec3::new(0.0, 0.0, 1.0),
        ],
        plane_normal: DVec3::Y,
        sections: vec![
            SectionSpec {
                profile: Profile::Circle { radius: 0.3 },
                v: 0.0,
                scale: 1.0,
                twist: 0.0,
            },
            SectionSpec {
                profile: Profile::Polygon {
                    sides: 5,
                    radius: 0.4,
                },
                v: 0.4,
                scale: 1.0,
                twist: 0.0,
            },
            SectionSpec {
                profile: Profile::Ellipse { rx: 0.3, ry: 0.2 },
                v: 0.7,
                scale: 1.0,
                twist: 0.0,
            },
            SectionSpec {
                profile: Profile::Circle { radius: 0.2 },
                v: 1.0,
                scale: 1.0,
                twist: 0.0,
            },
        ],
        shape,
        resolution: Resolution::PREVIEW,
    }))
}

fn edits(id: ObjectId) -> Vec<Op> {
    vec![
        Op::GcBend(Edit::new(
            id,
            GcBend {
                part: PartId(0),
                section: SectionIndex(2),
                to: DVec3::new(0.3, 0.0, 0.7),
            },
        )),
        Op::GcTwist(Edit::new(
            id,
            GcTwist {
                part: PartId(0),
                section: SectionIndex(1),
                angle: 0.8,
            },
        )),
        Op::GcInsertSection(Edit::new(
            id,
            GcInsertSection {
                part: PartId(0),
                v: 0.55,
            },
        )),
        Op::GcResize(Edit::new(
            id,
            GcResize {
                part: PartId(0),
                section: SectionIndex(2),
                factor: 1.25,
            },
        )),
        Op::GcShift(Edit::new(
            id,
            GcShift {
                part: PartId(0),
                section: SectionIndex(1),
                v: 0.3,
            },
        )),
        Op::GcReplaceSection(Edit::new(
            id,
            GcReplaceSection {
                part: PartId(0),
                section: SectionIndex(3),
                profile: Profile::Rectangle {
                    width: 0.4,
                    height: 0.3,
                },
                twist: 0.0,
            },
        )),
        Op::GcDeleteSection(Edit::new(
            id,
            GcDeleteSection {
                part: PartId(0),
                section: SectionIndex(2),
            },
        )),
        Op::GcSetShape(Edit::new(
            id,
            GcSetShape {
                part: PartId(0),
                shape: ShapeType::Container {
                    thickness: 0.02,
                    closed_end: ClosedEnd::Start,
                },
            },
        )),
        Op::GcReplaceSpine(Edit::new(
            id,
            GcReplaceSpine {
                part: PartId(0),
                points: vec![
                    DVec3::ZERO,
                    DVec3::new(0.3, 0.0, 0.6),
                    DVec3::new(0.8, 0.0, 0.9),
                ],
                plane_normal: DVec3::Y,
            },
        )),
        Op::GcSetResolution(Edit::new(
            id,
            GcSetResolution {
                part: PartId(0),
                resolution: Resolution { u: 40, v: 30 },
            },
        )),
    ]
}

#[test]
fn undo_redo_replay_are_bit_identical() {
    let mut log = OpLog::new();
    // The bend folds the shell through itself: flagged, not refused (this
    // test is about history; print_setup.rs tests the refusal).
    log.apply(
        serde_json::from_str(r#"{"op":"set_self_intersection_policy","policy":"flag"}"#).unwrap(),
    )
    .unwrap();
    let id = log
        .apply(create(ShapeType::Shell { thickness: 0.02 }))
        .unwrap()
        .created
        .unwrap();
    let mut hashes = vec![log.document().content_hash()];
    for op in edits(id) {
        log.apply(op.clone())
            .unwrap_or_else(|e| panic!("{}: {e}", op.name()));
        hashes.push(log.document().content_hash());
        let obj = log.document().get(id).unwrap();
        let r = validate(&obj.mesh, &Default::default());
        assert!(r.is_closed_manifold(), "{}: {}", op.name(), r.problems());
    }
    for h in hashes.iter().rev().skip(1) {
        log.undo().unwrap();
        assert_eq!(log.document().content_hash(), *h);
    }
    for h in hashes.iter().skip(1) {
        log.redo().unwrap();
        assert_eq!(log.document().content_hash(), *h);
    }
    let replayed = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(replayed.document().content_hash(), *hashes.last().unwrap());
    // Ops round-trip through JSON exactly.
    for op in log.ops() {
        let s = serde_json::to_string(op).unwrap();
        let back: Op = serde_json::from_str(&s).unwrap();
        assert_eq!(&back, op);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let mut log = OpLog::new();
    let id = log
        .apply(create(ShapeType::Solid))
        .unwrap()
        .created
        .unwrap();
    let before = log.document().content_hash();
    let n_ops = log.len();
    let bad_create = |f: &dyn Fn(&mut GcCreate)| {
        let Op::GcCreate(mut c) = create(ShapeType::Solid) else {
            unreachable!()
        };
        f(&mut c.0);
        Op::GcCreate(c)
    };
    let cases: Vec<(Op, &str)> = vec![
        (
            bad_create(&|c| c.spine = vec![DVec3::ONE, DVec3::ONE]),
            "zero-length spine",
        ),
        (bad_create(&|c| c.spine[1].x = f64::NAN), "NaN spine point"),
        (bad_create(&|c| c.sections.truncate(1)), "K < 2"),
        (
            bad_create(&|c| {
                c.sections[1].profile = Profile::Points {
                    points: vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],
                }
            }),
            "self-intersecting section",
        ),
        (
            bad_create(&|c| c.shape = ShapeType::Shell { thickness: 0.5 }),
            "thickness >= inscribed radius",
        ),
        (
            bad_create(&|c| c.sections[2].v = 0.3),
            "sections out of order",
        ),
        (
            Op::GcBend(Edit::new(
                id,
                GcBend {
                    part: PartId(0),
                    section: SectionIndex(1),
                    to: DVec3::new(0.0, f64::NAN, 0.0),
                },
            )),
            "NaN bend",
        ),
        (
            Op::GcBend(Edit::new(
                id,
                GcBend {
                    part: PartId(0),
                    section: SectionIndex(1),
                    to: DVec3::new(0.0, 1.0, 0.4),
                },
            )),
            "bend off the plane",
        ),
        (
            Op::GcTwist(Edit::new(
                id,
                GcTwist {
                    part: PartId(0),
                    section: SectionIndex(0),
                    angle: 1.0,
                },
            )),
            "twist an end",
        ),
        (
            Op::GcResize(Edit::new(
                id,
                GcResize {
                    part: PartId(0),
                    section: SectionIndex(9),
                    factor: 2.0,
                },
            )),
            "bad section",
        ),
        (
            Op::GcResize(Edit::new(
                id,
                GcResize {
                    part: PartId(3),
                    section: SectionIndex(0),
                    factor: 2.0,
                },
            )),
            "bad part",
        ),
        (
            Op::GcResize(Edit::new(
                ObjectId(77),
                GcResize {
                    part: PartId(0),
                    section: SectionIndex(0),
                    factor: 2.0,
                },
            )),
            "bad id",
        ),
        (
            Op::GcInsertSection(Edit::new(
                id,
                GcInsertSection {
                    part: PartId(0),
                    v: 0.4,
                },
            )),
            "insert on an existing section",
        ),
        (
            Op::GcSetShape(Edit::new(
                id,
                GcSetShape {
                    part: PartId(0),
                    shape: ShapeType::Container {
                        thickness: 0.25,
                        closed_end: ClosedEnd::End,
                    },
                },
            )),
            "container too thick",
        ),
    ];
    for (op, what) in cases {
        let e = log.apply(op).expect_err(what);
        assert!(matches!(e, LogError::Op(_)), "{what}: {e}");
        assert!(!e.to_string().is_empty());
        assert_eq!(log.document().content_hash(), before, "{what}");
        assert_eq!(log.len(), n_ops, "{what}");
    }
    // One error checked by value.
    let e = log
        .apply(Op::GcDeleteSection(Edit::new(
            id,
            GcDeleteSection {
                part: PartId(0),
                section: SectionIndex(7),
            },
        )))
        .unwrap_err();
    assert_eq!(
        e,
        LogError::Op(OpError::Gc(GcError::BadSection { index: 7, count: 4 }))
    );
}

#[test]
fn script_parses_gc_ops() {
    let text = r#"{"op":"gc_create","spine":[[0,0,0],[0,0,1]],"plane_normal":[1,0,0],"sections":[{"profile":{"template":"circle","radius":0.3},"v":0},{"profile":{"template":"polygon","sides":6,"radius":0.3},"v":1}],"shape":{"type":"shell","thickness":0.03},"resolution":{"u":24,"v":8}}
{"op":"gc_resize","id":1,"section":1,"factor":1.5}"#;
    let lines = shapewright::doc::parse_script(text).unwrap();
    let mut log = OpLog::new();
    shapewright::doc::run_script(&mut log, &lines).unwrap();
    assert_eq!(log.len(), 2);
    let r = validate(&log.document().combined_mesh(), &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    assert_eq!(r.genus, Some(1));
}
