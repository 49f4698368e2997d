//! Property test (issue 3): random sections, spines, shape types and edit
//! sequences always mesh to a closed oriented 2-manifold with positive
//! volume, or fail with a typed error that leaves the document unchanged.
//! 500 cases at low resolution (a few seconds in the dev profile). A
//! second test makes sensible GCs and edits (what the tools make) and
//! keeps their refusal rate under 10%.

use glam::DVec3;
use proptest::prelude::*;
use shapewright::doc::{Edit as DocEdit, LogError, ObjectId, Op, OpError, OpLog};
use shapewright::gc::*;
use shapewright::gc::{ClosedEnd, Profile, Resolution, ShapeType};
use shapewright::math::fm::DetMath as _;
use shapewright::mesh::validate;
use shapewright::print::PrintError;

fn profile() -> impl Strategy<Value = Profile> {
    prop_oneof![
        (0.1f64..0.5).prop_map(|radius| Profile::Circle { radius }),
        (0.1f64..0.5, 0.1f64..0.5).prop_map(|(rx, ry)| Profile::Ellipse { rx, ry }),
        (3u32..9, 0.1f64..0.5).prop_map(|(sides, radius)| Profile::Polygon { sides, radius }),
        (0.15f64..0.8, 0.15f64..0.8)
            .prop_map(|(width, height)| Profile::Rectangle { width, height }),
        (
            5usize..12,
            0.15f64..0.4,
            prop::collection::vec(-0.3f64..0.3, 12)
        )
            .prop_map(|(n, r, noise)| {
                Profile::Points {
                    points: (0..n)
                        .map(|i| {
                            let a = i as f64 / n as f64 * std::f64::consts::TAU;
                            let rr = r * (1.0 + noise[i]);
                            [rr * a.fcos(), rr * a.fsin()]
                        })
                        .collect(),
                }
            }),
    ]
}

fn shape() -> impl Strategy<Value = ShapeType> {
    prop_oneof![
        Just(ShapeType::Solid),
        (0.003f64..0.15).prop_map(|thickness| ShapeType::Shell { thickness }),
        (0.003f64..0.15, any::<bool>()).prop_map(|(thickness, s)| ShapeType::Container {
            thickness,
            closed_end: if s { ClosedEnd::Start } else { ClosedEnd::End },
        }),
    ]
}

/// A GC whose spine rises from the origin by `(x, dz)` steps in the XZ
/// plane, with key sections spread along it by their relative gaps `w`
/// (first at 0, last at 1).
fn gc_create(
    spine: Vec<(f64, f64)>,
    secs: Vec<(Profile, f64)>,
    shape: ShapeType,
    resolution: Resolution,
) -> GcCreate {
    let mut pts = vec![DVec3::ZERO];
    let mut z = 0.0;
    for (x, dz) in spine {
        z += dz;
        pts.push(DVec3::new(x, 0.0, z));
    }
    let k = secs.len();
    let total: f64 = secs.iter().skip(1).map(|s| s.1).sum();
    let mut acc = 0.0;
    let sections = secs
        .into_iter()
        .enumerate()
        .map(|(i, (profile, w))| {
            if i > 0 {
                acc += w;
            }
            SectionSpec {
                profile,
                v: if i + 1 == k { 1.0 } else { acc / total },
                scale: 1.0,
                twist: 0.0,
            }
        })
        .collect();
    GcCreate {
        spine: pts,
        plane_normal: DVec3::Y,
        sections,
        shape,
        resolution,
    }
}

fn create() -> impl Strategy<Value = GcCreate> {
    (
        prop::collection::vec((-0.4f64..0.4, 0.2f64..0.8), 1..5),
        prop::collection::vec((profile(), 0.2f64..1.0), 2..6),
        shape(),
        12u32..32,
        4u32..16,
    )
        .prop_map(|(spine, secs, shape, u, v)| gc_create(spine, secs, shape, Resolution { u, v }))
}

#[derive(Clone, Debug)]
enum Edit {
    Bend(usize, f64, f64),
    Resize(usize, f64),
    Shift(usize, f64),
    Twist(usize, f64),
    Replace(usize, Profile),
    Delete(usize),
    Insert(f64),
    Shape(ShapeType),
    Spine(Vec<(f64, f64)>),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (0usize..6, -0.3f64..0.3, -0.2f64..0.2).prop_map(|(i, x, z)| Edit::Bend(i, x, z)),
        (0usize..6, 0.5f64..1.6).prop_map(|(i, f)| Edit::Resize(i, f)),
        (0usize..6, 0.0f64..1.0).prop_map(|(i, v)| Edit::Shift(i, v)),
        (0usize..6, -1.5f64..1.5).prop_map(|(i, a)| Edit::Twist(i, a)),
        (0usize..6, profile()).prop_map(|(i, p)| Edit::Replace(i, p)),
        (0usize..6).prop_map(Edit::Delete),
        (0.0f64..1.0).prop_map(Edit::Insert),
        shape().prop_map(Edit::Shape),
        prop::collection::vec((-0.5f64..0.5, 0.2f64..0.8), 1..4).prop_map(Edit::Spine),
    ]
}

fn to_op(id: ObjectId, e: &Edit, log: &OpLog) -> Op {
    let part = 0;
    match e.clone() {
        Edit::Bend(section, dx, dz) => {
            // Move the key point within the spine plane (y = 0).
            let key = match &log.document().get(id).unwrap().kind {
                shapewright::doc::ObjectKind::GcAssembly(a) => {
                    let gc = &a.parts[0].gc;
                    gc.key_points().get(section).copied().unwrap_or(DVec3::ZERO)
                }
                _ => DVec3::ZERO,
            };
            Op::GcBend(DocEdit::new(
                id,
                GcBend {
                    part: PartId(part),
                    section: SectionIndex(section),
                    to: key + DVec3::new(dx, 0.0, dz),
                },
            ))
        }
        Edit::Resize(section, factor) => Op::GcResize(DocEdit::new(
            id,
            GcResize {
                part: PartId(part),
                section: SectionIndex(section),
                factor,
            },
        )),
        Edit::Shift(section, v) => Op::GcShift(DocEdit::new(
            id,
            GcShift {
                part: PartId(part),
                section: SectionIndex(section),
                v,
            },
        )),
        Edit::Twist(section, angle) => Op::GcTwist(DocEdit::new(
            id,
            GcTwist {
                part: PartId(part),
                section: SectionIndex(section),
                angle,
            },
        )),
        Edit::Replace(section, profile) => Op::GcReplaceSection(DocEdit::new(
            id,
            GcReplaceSection {
                part: PartId(part),
                section: SectionIndex(section),
                profile,
                twist: 0.0,
            },
        )),
        Edit::Delete(section) => Op::GcDeleteSection(DocEdit::new(
            id,
            GcDeleteSection {
                part: PartId(part),
                section: SectionIndex(section),
            },
        )),
        Edit::Insert(v) => Op::GcInsertSection(DocEdit::new(
            id,
            GcInsertSection {
                part: PartId(part),
                v,
            },
        )),
        Edit::Shape(shape) => Op::GcSetShape(DocEdit::new(
            id,
            GcSetShape {
                part: PartId(part),
                shape,
            },
        )),
        Edit::Spine(pts) => {
            let mut p = vec![DVec3::ZERO];
            let mut z = 0.0;
            for (x, dz) in pts {
                z += dz;
                p.push(DVec3::new(x, 0.0, z));
            }
            Op::GcReplaceSpine(DocEdit::new(
                id,
                GcReplaceSpine {
                    part: PartId(part),
                    points: p,
                    plane_normal: DVec3::Y,
                },
            ))
        }
    }
}

fn check_closed(log: &OpLog, what: &str) {
    let m = log.document().combined_mesh();
    let r = validate(&m, &Default::default());
    assert!(r.is_closed_manifold(), "{what}: {}", r.problems());
    assert!(r.signed_volume > 0.0);
}

fn typed(e: &LogError) -> bool {
    matches!(
        e,
        LogError::Op(OpError::Gc(_))
            | LogError::Op(OpError::Print(PrintError::SelfIntersecting { .. }))
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn random_gcs_mesh_closed_or_fail_typed(c in create(), edits in prop::collection::vec(edit(), 0..6)) {
        let mut log = OpLog::new();
        let id = match log.apply(Op::GcCreate(shapewright::doc::Create(c))) {
            Ok(out) => out.created.unwrap(),
            Err(e) => {
                prop_assert!(typed(&e), "untyped error {e:?}");
                prop_assert!(log.document().is_empty());
                return Ok(());
            }
        };
        check_closed(&log, "create");
        for e in &edits {
            let before = log.document().content_hash();
            let op = to_op(id, e, &log);
            match log.apply(op) {
                Ok(_) => check_closed(&log, &format!("{e:?}")),
                Err(err) => {
                    prop_assert!(typed(&err), "untyped error {err:?}");
                    prop_assert_eq!(log.document().content_hash(), before);
                }
            }
        }
    }
}

/// Sensible random GCs: sections 0.1 to 0.3 across, gently bent spines,
/// wall thickness under a third of the smallest inscribed radius (what a
/// user sketches; the wild inputs above test the refusals).
fn sensible_create() -> impl Strategy<Value = GcCreate> {
    let profile = prop_oneof![
        (0.1f64..0.3).prop_map(|radius| Profile::Circle { radius }),
        (0.1f64..0.3, 0.1f64..0.3).prop_map(|(rx, ry)| Profile::Ellipse { rx, ry }),
        (4u32..9, 0.12f64..0.3).prop_map(|(sides, radius)| Profile::Polygon { sides, radius }),
        (0.2f64..0.6, 0.2f64..0.6).prop_map(|(width, height)| Profile::Rectangle { width, height }),
    ];
    (
        prop::collection::vec((-0.08f64..0.08, 0.3f64..0.8), 1..4),
        prop::collection::vec((profile, 0.3f64..1.0), 2..6),
        0u8..3,
        0.003f64..0.02,
        12u32..32,
        4u32..16,
    )
        .prop_map(|(spine, secs, kind, thickness, u, v)| {
            let shape = match kind {
                0 => ShapeType::Solid,
                1 => ShapeType::Shell { thickness },
                _ => ShapeType::Container {
                    thickness,
                    closed_end: ClosedEnd::Start,
                },
            };
            gc_create(spine, secs, shape, Resolution { u, v })
        })
}

/// A sensible edit of the GC as it is now, from random numbers: bends of
/// a few centimetres in the spine plane, resizes by 0.8 to 1.25, shifts
/// and twists of interior sections between their neighbours, deletes of
/// interior sections, inserts between sections, a replacement profile of
/// the same kind, a spine through the key points moved in the plane.
fn sensible_op(id: ObjectId, gc: &Gc, r: (u8, f64, f64, f64)) -> Op {
    let (kind, a, b, c) = r;
    let k = gc.sections.len();
    let part = PartId(0);
    let pick = |x: f64, lo: usize, hi: usize| (lo + (x * (hi - lo) as f64) as usize).min(hi - 1);
    let kind = if matches!(kind, 2 | 3 | 5) && k < 3 {
        6
    } else {
        kind
    };
    match kind {
        0 => {
            let i = pick(a, 0, k);
            let to = gc.key_points()[i]
                + DVec3::new(0.04 * (2.0 * b - 1.0), 0.0, 0.03 * (2.0 * c - 1.0));
            Op::GcBend(DocEdit::new(
                id,
                GcBend {
                    part,
                    section: SectionIndex(i),
                    to,
                },
            ))
        }
        1 => Op::GcResize(DocEdit::new(
            id,
            GcResize {
                part,
                section: SectionIndex(pick(a, 0, k)),
                factor: 0.8 + 0.45 * b,
            },
        )),
        2 => {
            let i = pick(a, 1, k - 1);
            let (lo, hi) = (gc.sections[i - 1].v, gc.sections[i + 1].v);
            Op::GcShift(DocEdit::new(
                id,
                GcShift {
                    part,
                    section: SectionIndex(i),
                    v: lo + (hi - lo) * (0.2 + 0.6 * b),
                },
            ))
        }
        3 => Op::GcTwist(DocEdit::new(
            id,
            GcTwist {
                part,
                section: SectionIndex(pick(a, 1, k - 1)),
                angle: 1.2 * (b - 0.5),
            },
        )),
        4 => {
            let i = pick(a, 0, k);
            let f = 0.85 + 0.3 * b;
            let profile = match &gc.sections[i].profile {
                Profile::Circle { radius } => Profile::Circle { radius: radius * f },
                Profile::Ellipse { rx, ry } => Profile::Ellipse {
                    rx: rx * f,
                    ry: *ry,
                },
                Profile::Polygon { sides, radius } => Profile::Polygon {
                    sides: *sides,
                    radius: radius * f,
                },
                Profile::Rectangle { width, height } => Profile::Rectangle {
                    width: width * f,
                    height: *height,
                },
                other => other.clone(),
            };
            Op::GcReplaceSection(DocEdit::new(
                id,
                GcReplaceSection {
                    part,
                    section: SectionIndex(i),
                    profile,
                    twist: 0.0,
                },
            ))
        }
        5 => Op::GcDeleteSection(DocEdit::new(
            id,
            GcDeleteSection {
                part,
                section: SectionIndex(pick(a, 1, k - 1)),
            },
        )),
        6 => {
            let i = pick(a, 0, k - 1);
            let (lo, hi) = (gc.sections[i].v, gc.sections[i + 1].v);
            Op::GcInsertSection(DocEdit::new(
                id,
                GcInsertSection {
                    part,
                    v: lo + (hi - lo) * (0.2 + 0.6 * b),
                },
            ))
        }
        7 => {
            let t = 0.003 + 0.012 * b;
            let shape = match (a * 3.0) as u8 {
                0 => ShapeType::Solid,
                1 => ShapeType::Shell { thickness: t },
                _ => ShapeType::Container {
                    thickness: t,
                    closed_end: if c < 0.5 {
                        ClosedEnd::Start
                    } else {
                        ClosedEnd::End
                    },
                },
            };
            Op::GcSetShape(DocEdit::new(id, GcSetShape { part, shape }))
        }
        _ => {
            let keys = gc.key_points();
            let n = keys.len() as f64;
            let points = keys
                .iter()
                .enumerate()
                .map(|(j, q)| *q + DVec3::new(0.05 * (2.0 * b - 1.0) * j as f64 / n, 0.0, 0.0))
                .collect();
            Op::GcReplaceSpine(DocEdit::new(
                id,
                GcReplaceSpine {
                    part,
                    points,
                    plane_normal: DVec3::Y,
                },
            ))
        }
    }
}

/// Not only typed errors: sensible GCs and edits (what the tools make)
/// succeed. Counts outcomes over 500 deterministic samples, prints them
/// and keeps the refusals under 10% (the wild generator above refuses
/// some 40%, which is what it is for).
#[test]
fn sensible_gcs_and_edits_succeed() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strat = (
        sensible_create(),
        prop::collection::vec((0u8..9, 0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 0..6),
    );
    let (mut created, mut edits_ok, mut edits_err) = (0usize, 0usize, 0usize);
    let mut errors: std::collections::BTreeMap<String, usize> = Default::default();
    let n = 500;
    let key = |err: &LogError| {
        let s = format!("{err:?}");
        s.trim_start_matches("Op(Gc(")
            .split(['{', '(', ' '])
            .next()
            .unwrap_or(&s)
            .to_string()
    };
    for _ in 0..n {
        let (c, es) = strat.new_tree(&mut runner).unwrap().current();
        let mut log = OpLog::new();
        let out = match log.apply(Op::GcCreate(shapewright::doc::Create(c.clone()))) {
            Ok(out) => out,
            Err(err) => {
                *errors.entry(format!("create: {}", key(&err))).or_default() += 1;
                continue;
            }
        };
        created += 1;
        let id = out.created.unwrap();
        for e in &es {
            let gc = match &log.document().get(id).unwrap().kind {
                shapewright::doc::ObjectKind::GcAssembly(a) => a.parts[0].gc.clone(),
                _ => unreachable!(),
            };
            match log.apply(sensible_op(id, &gc, *e)) {
                Ok(_) => edits_ok += 1,
                Err(err) => {
                    edits_err += 1;
                    *errors.entry(key(&err)).or_default() += 1;
                }
            }
        }
    }
    let edits = edits_ok + edits_err;
    eprintln!(
        "created {created}/{n}; edits ok {edits_ok}, refused {edits_err} ({:.1}%): {errors:?}",
        100.0 * edits_err as f64 / edits.max(1) as f64
    );
    assert!(
        created * 10 > n * 9,
        "only {created} of {n} sensible GCs were created"
    );
    assert!(
        edits_err * 10 < edits,
        "{edits_err} of {edits} sensible edits refused"
    );
}
