use crate::math::fm::DetMath as _;
use std::f64::consts::PI;

use proptest::prelude::*;

use crate::doc::{Create, Document, Edit, ObjectKind, Op, OpError, OpLog};
use crate::math::{DQuat, DVec3, Transform};
use crate::mesh::{validate, TriMesh};
use crate::sdf::edits::*;
use crate::sdf::volume::{extract_keys, stitch};
use crate::sdf::{Component, CsgOp, Operand, ScaleAxis, SdfError, SdfVolume};
use crate::solid::SolidShape;

fn sphere(r: f64) -> Component {
    Component::Solid {
        shape: SolidShape::Sphere { radius: r },
    }
}

fn cube(s: f64) -> Component {
    Component::Solid {
        shape: SolidShape::Box { size: [s; 3] },
    }
}

fn at(t: [f64; 3]) -> Transform {
    Transform::translation(t)
}

fn op(c: Component, csg: CsgOp, t: Transform) -> Operand {
    Operand::new(c, csg, t)
}

fn run(step: f64, ops: Vec<Operand>) -> SdfVolume {
    let mut v = SdfVolume::new(step).unwrap();
    v.pending = ops;
    v.updated().unwrap()
}

/// A full extraction of the volume's grid, both ways: the one-pass
/// `extract_all` (dense index, exact block signs) and candidate keys
/// extracted one by one must give the same pieces.
fn full_mesh(v: &SdfVolume) -> TriMesh {
    let s = v.state().unwrap();
    let keys = s.grid.extraction_bricks();
    let one_by_one = extract_keys(&s.grid, &keys, Some(&s.exact));
    let all = s.grid.extract_all(Some(&s.exact));
    assert_eq!(one_by_one, all);
    stitch(&all)
}

fn check_closed(m: &TriMesh) -> crate::mesh::ValidationReport {
    let r = validate(m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    r
}

/// Volume of sphere (r, centre c) ∩ axis box [-a, a]³, by 1D quadrature
/// of the exact disk–square intersection areas.
fn sphere_box_intersection(r: f64, c: [f64; 3], a: f64) -> f64 {
    let n = 4000;
    let (z0, z1) = ((c[2] - r).max(-a), (c[2] + r).min(a));
    let dz = (z1 - z0) / n as f64;
    let mut vol = 0.0;
    for i in 0..n {
        let z = z0 + (i as f64 + 0.5) * dz;
        let rr = (r * r - (z - c[2]).fpowi(2)).max(0.0).sqrt();
        // Area of disk (centre c.xy, radius rr) within the square, by
        // integrating chord lengths along x.
        let m = 400;
        let (x0, x1) = ((c[0] - rr).max(-a), (c[0] + rr).min(a));
        if x1 <= x0 {
            continue;
        }
        let dx = (x1 - x0) / m as f64;
        let mut area = 0.0;
        for j in 0..m {
            let x = x0 + (j as f64 + 0.5) * dx;
            let hy = (rr * rr - (x - c[0]).fpowi(2)).max(0.0).sqrt();
            let (y0, y1) = ((c[1] - hy).max(-a), (c[1] + hy).min(a));
            area += (y1 - y0).max(0.0) * dx;
        }
        vol += area * dz;
    }
    vol
}

/// Mean and largest distance (|exact field|) of the triangles' centroids
/// from the true surface.
fn surface_error(m: &TriMesh, exact: &crate::sdf::features::ExactField) -> (f64, f64) {
    let errs: Vec<f64> = (0..m.triangles.len())
        .map(|t| {
            let [a, b, c] = m.corners(t);
            exact.value((a + b + c) / 3.0).map_or(0.0, f64::abs)
        })
        .collect();
    let mean = errs.iter().sum::<f64>() / errs.len() as f64;
    (mean, errs.iter().copied().fold(0.0, f64::max))
}

#[test]
fn sharp_features_bring_the_surface_closer_to_the_csg_result() {
    // The paper's cup (a rim and a base of sharp circular edges) and a
    // box with a cylinder hole (straight edges and corners), both off the
    // grid's axes: with feature fans and flips the triangles lie closer to
    // the exact CSG surface, on average and at worst, and the mesh stays
    // a closed 2-manifold of the same genus.
    let cyl = |r: f64, h: f64| Component::Solid {
        shape: SolidShape::Cylinder {
            radius: r,
            height: h,
        },
    };
    let turned = Transform {
        rotate: DQuat::from_rotation_z(0.3).to_array(),
        ..at([0.003, -0.002, 0.001])
    };
    let scenes = [
        vec![
            op(cyl(0.12, 0.24), CsgOp::Union, turned),
            op(
                cyl(0.1, 0.24),
                CsgOp::Subtract,
                Transform {
                    translate: [0.003, -0.002, 0.031],
                    ..turned
                },
            ),
        ],
        vec![
            op(cube(0.3), CsgOp::Union, turned),
            op(cyl(0.06, 0.4), CsgOp::Subtract, turned),
        ],
    ];
    for ops in scenes {
        let v = run(0.01, ops);
        let s = v.state().unwrap();
        let sharp = stitch(&s.grid.extract_all(Some(&s.exact)));
        let plain = stitch(&s.grid.extract_all(None));
        let (rs, rp) = (check_closed(&sharp), check_closed(&plain));
        assert_eq!(rs.genus, rp.genus);
        let (ms, xs) = surface_error(&sharp, &s.exact);
        let (mp, xp) = surface_error(&plain, &s.exact);
        assert!(ms < 0.8 * mp, "mean error {ms} vs plain {mp}");
        assert!(xs < 0.9 * xp, "largest error {xs} vs plain {xp}");
    }
}

#[test]
fn vertex_normals_are_the_outward_field_gradient() {
    // A sphere off the grid's axes: every normal is a unit vector within
    // a few degrees of the radial direction.
    let c = [0.013, -0.021, 0.007];
    let m = run(0.01, vec![op(sphere(0.2), CsgOp::Union, at(c))])
        .evaluate()
        .unwrap();
    assert_eq!(m.normals.len(), m.positions.len());
    let mut worst: f64 = 1.0;
    for (p, n) in m.positions.iter().zip(&m.normals) {
        let r = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let dot = (r[0] * n[0] + r[1] * n[1] + r[2] * n[2]) / len;
        worst = worst.min(dot);
    }
    assert!(worst > 0.99, "worst cosine to the radial direction {worst}");
}

#[test]
fn sphere_box_csg_volumes_within_one_percent() {
    let (r, a, c): (f64, f64, [f64; 3]) = (0.2, 0.2, [0.2, 0.15, 0.1]);
    let vs = 4.0 / 3.0 * PI * r * r * r;
    let vb = (2.0 * a).fpowi(3);
    let vi = sphere_box_intersection(r, c, a);
    let cases = [
        (CsgOp::Union, vs + vb - vi),
        (CsgOp::Intersect, vi),
        (CsgOp::Subtract, vb - vi),
    ];
    for (csg, exact) in cases {
        let v = run(
            0.01,
            vec![
                op(cube(2.0 * a), CsgOp::Union, Transform::IDENTITY),
                op(sphere(r), csg, at(c)),
            ],
        );
        let r = check_closed(&v.evaluate().unwrap());
        let err = (r.signed_volume - exact).abs() / exact;
        assert!(
            err < 0.01,
            "{csg:?}: {} vs {exact} ({err})",
            r.signed_volume
        );
    }
}

#[test]
fn lazy_sequence_with_cancel_and_move_before_update() {
    // ((A ∪ B) ∩ C) − D, with an extra operand cancelled and B moved while
    // queued; one update.
    let mut log = OpLog::new();
    let id = log
        .apply(Op::SdfCreate(Create(SdfCreate { step: 0.01 })))
        .unwrap()
        .created
        .unwrap();
    let add = |c, csg, t| {
        Op::SdfAddOperand(Edit::new(
            id,
            SdfAddOperand {
                component: c,
                csg,
                transform: t,
            },
        ))
    };
    log.apply(add(cube(0.3), CsgOp::Union, Transform::IDENTITY))
        .unwrap();
    log.apply(add(sphere(0.12), CsgOp::Union, at([0.5, 0.0, 0.0])))
        .unwrap();
    log.apply(add(sphere(0.5), CsgOp::Union, at([3.0, 0.0, 0.0])))
        .unwrap();
    log.apply(add(sphere(0.2), CsgOp::Intersect, Transform::IDENTITY))
        .unwrap();
    log.apply(add(sphere(0.08), CsgOp::Subtract, at([0.0, 0.0, 0.15])))
        .unwrap();
    log.apply(Op::SdfCancelOperand(Edit::new(
        id,
        SdfCancelOperand {
            operand: OperandIndex(2),
        },
    )))
    .unwrap();
    log.apply(Op::SdfSetOperandTransform(Edit::new(
        id,
        SdfSetOperandTransform {
            operand: OperandIndex(1),
            transform: at([0.18, 0.0, 0.0]),
        },
    )))
    .unwrap();
    log.apply(Op::SdfUpdate(Edit::new(id, SdfUpdate {})))
        .unwrap();
    let obj = log.document().get(id).unwrap();
    let ObjectKind::SdfVolume(v) = &obj.kind else {
        panic!()
    };
    assert!(v.pending.is_empty());
    assert_eq!(v.fused.len(), 4);
    let r = check_closed(&obj.mesh);
    assert_eq!(r.components, 1);
    // Replay gives the same bits.
    let replay = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(
        replay.document().content_hash(),
        log.document().content_hash()
    );
    // The result equals a from-scratch rebuild.
    assert_eq!(
        *v.without_state().evaluate().unwrap().positions,
        *obj.mesh.positions
    );
}

#[test]
fn two_hand_scale_is_clamped_and_per_axis() {
    let mut log = OpLog::new();
    let id = log
        .apply(Op::SdfCreate(Create(SdfCreate { step: 0.01 })))
        .unwrap()
        .created
        .unwrap();
    log.apply(Op::SdfAddOperand(Edit::new(
        id,
        SdfAddOperand {
            component: sphere(0.1),
            csg: CsgOp::Union,
            transform: Transform::IDENTITY,
        },
    )))
    .unwrap();
    let scale = |axis, end: f64| {
        Op::SdfScaleTwoHand(Edit::new(
            id,
            SdfScaleTwoHand {
                operand: OperandIndex(0),
                axis,
                hands_start: [[0.0; 3], [0.1, 0.0, 0.0]],
                hands_end: [[0.0; 3], [end, 0.0, 0.0]],
            },
        ))
    };
    let scale_now = |log: &OpLog| {
        let ObjectKind::SdfVolume(v) = &log.document().get(id).unwrap().kind else {
            panic!()
        };
        v.pending[0].transform.scale
    };
    log.apply(scale(ScaleAxis::X, 10.0)).unwrap(); // ratio 100 -> 4, X only
    let s = scale_now(&log);
    assert!(
        (s[0] - 4.0).abs() < 1e-12 && s[1] == 1.0 && s[2] == 1.0,
        "{s:?}"
    );
    // Ratio 0.1 on all axes: X 4 -> 0.4, Y and Z 1 -> 0.1, clamped to 0.4
    // of the scale before the first gesture.
    log.apply(scale(ScaleAxis::Uniform, 0.01)).unwrap();
    let s = scale_now(&log);
    assert!(s.iter().all(|x| (x - 0.4).abs() < 1e-12), "{s:?}");
    let mut doc = log.document().clone();
    let bad = Op::SdfScaleTwoHand(Edit::new(
        id,
        SdfScaleTwoHand {
            operand: OperandIndex(0),
            axis: ScaleAxis::Y,
            hands_start: [[0.0; 3], [0.0; 3]],
            hands_end: [[0.0; 3], [1.0, 0.0, 0.0]],
        },
    ))
    .apply(&mut doc);
    assert!(matches!(
        bad,
        Err(OpError::Sdf(SdfError::HandsTooClose { .. }))
    ));
}

#[test]
fn bad_input_gets_typed_errors_and_changes_nothing() {
    let mut log = OpLog::new();
    assert!(matches!(
        log.apply(Op::SdfCreate(Create(SdfCreate { step: 0.05 }))),
        Err(crate::doc::LogError::Op(OpError::Sdf(SdfError::BadStep(_))))
    ));
    let id = log
        .apply(Op::SdfCreate(Create(SdfCreate { step: 0.01 })))
        .unwrap()
        .created
        .unwrap();
    let h = log.document().content_hash();
    let mut nan = Transform::IDENTITY;
    nan.translate[0] = f64::NAN;
    let mut zero = Transform::IDENTITY;
    zero.scale = [1.0, 0.0, 1.0];
    let mut huge = Transform::IDENTITY;
    huge.scale = [1e4; 3];
    for (t, what) in [(nan, "nan"), (zero, "zero scale"), (huge, "budget")] {
        let e = log.apply(Op::SdfAddOperand(Edit::new(
            id,
            SdfAddOperand {
                component: sphere(0.1),
                csg: CsgOp::Union,
                transform: t,
            },
        )));
        match (what, e) {
            ("nan", Err(crate::doc::LogError::Op(OpError::BadField { field, .. })))
                if field == "transform.translate[0]" => {}
            ("zero scale", Err(crate::doc::LogError::Op(OpError::Sdf(SdfError::Transform(_))))) => {
            }
            ("budget", Err(crate::doc::LogError::Op(OpError::Sdf(SdfError::OverBudget(_))))) => {}
            (w, e) => panic!("{w}: {e:?}"),
        }
    }
    // An open mesh.
    let open = TriMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    );
    let e = log.apply(Op::SdfImportComponent(Edit::new(
        id,
        SdfImportComponent {
            name: "tri".into(),
            positions: open.positions.clone(),
            triangles: open.triangles.clone(),
        },
    )));
    assert!(matches!(
        e,
        Err(crate::doc::LogError::Op(OpError::Sdf(SdfError::BadMesh(_))))
    ));
    assert!(matches!(
        log.apply(Op::SdfUpdate(Edit::new(id, SdfUpdate {}))),
        Err(crate::doc::LogError::Op(OpError::Sdf(
            SdfError::NothingPending
        )))
    ));
    assert!(matches!(
        log.apply(Op::SdfCancelOperand(Edit::new(
            id,
            SdfCancelOperand {
                operand: OperandIndex(0),
            }
        ))),
        Err(crate::doc::LogError::Op(OpError::Sdf(
            SdfError::BadOperand { .. }
        )))
    ));
    assert_eq!(log.document().content_hash(), h);
}

#[test]
fn rotated_library_component_resampling_error_is_below_step() {
    // The rotated, translated library sphere (normalized radius 0.2) vs the
    // analytic sphere, compared on the grid samples near the surface.
    let rot = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, 1.1);
    let t = Transform {
        translate: [0.013, -0.021, 0.034],
        rotate: rot.to_array(),
        scale: [1.0; 3],
    };
    let step = 0.01;
    let v = run(
        step,
        vec![op(
            Component::Library {
                name: "sphere".into(),
            },
            CsgOp::Union,
            t,
        )],
    );
    let s = v.state().unwrap();
    let mut worst = 0.0f64;
    let mut n = 0;
    for (k, b) in &s.grid.bricks {
        for l in 0..512 {
            let val = b.get(l) as f64;
            if val.abs() >= s.grid.band as f64 * 0.99 {
                continue;
            }
            let li = [l % 8, l / 8 % 8, l / 64].map(|x| x as i32);
            let p = DVec3::new(
                (k[0] * 8 + li[0]) as f64,
                (k[1] * 8 + li[1]) as f64,
                (k[2] * 8 + li[2]) as f64,
            ) * step;
            let exact = (p - DVec3::from_array(t.translate)).length() - 0.2;
            worst = worst.max((val - exact).abs());
            n += 1;
        }
    }
    assert!(n > 1000);
    assert!(worst < step, "resampling error {worst} >= step {step}");
    let r = check_closed(&v.evaluate().unwrap());
    let exact = 4.0 / 3.0 * PI * 0.008;
    assert!((r.signed_volume - exact).abs() / exact < 0.01);
}

#[test]
fn one_and_two_threads_are_bit_identical() {
    let ops = vec![
        op(cube(0.5), CsgOp::Union, Transform::IDENTITY),
        op(sphere(0.3), CsgOp::Subtract, at([0.1, 0.2, 0.0])),
        op(
            Component::Solid {
                shape: SolidShape::Torus {
                    major_radius: 0.3,
                    minor_radius: 0.05,
                },
            },
            CsgOp::Union,
            at([0.0, 0.0, 0.25]),
        ),
    ];
    let go = |n| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| {
            let mut d = Document::new();
            let v = run(0.008, ops.clone());
            d.insert(ObjectKind::SdfVolume(v)).unwrap();
            d.content_hash()
        })
    };
    assert_eq!(go(1), go(2));
}

fn arb_shape() -> impl Strategy<Value = SolidShape> {
    prop_oneof![
        (0.02f64..0.25).prop_map(|r| SolidShape::Sphere { radius: r }),
        (0.005f64..0.3, 0.01f64..0.3, 0.01f64..0.3)
            .prop_map(|(a, b, c)| SolidShape::Box { size: [a, b, c] }),
        (0.004f64..0.1, 0.02f64..0.4).prop_map(|(r, h)| SolidShape::Cylinder {
            radius: r,
            height: h
        }),
        (0.05f64..0.2, 0.2f64..0.9).prop_map(|(m, f)| SolidShape::Torus {
            major_radius: m,
            minor_radius: m * f
        }),
        (0.02f64..0.15, 0.02f64..0.3).prop_map(|(r, h)| SolidShape::Cone {
            radius: r,
            height: h
        }),
        (0.01f64..0.1, 0.0f64..0.2).prop_map(|(r, l)| SolidShape::Capsule {
            radius: r,
            length: l
        }),
        (0.02f64..0.2, 0.02f64..0.2, 0.005f64..0.2)
            .prop_map(|(a, b, c)| SolidShape::Ellipsoid { radii: [a, b, c] }),
    ]
}

fn arb_operand() -> impl Strategy<Value = Operand> {
    let coord = prop_oneof![
        3 => -0.2f64..0.2,
        // Grid-aligned positions: faces and tangencies exactly on samples.
        2 => (-20i32..20).prop_map(|i| i as f64 * 0.01),
    ];
    (
        arb_shape(),
        prop_oneof![
            Just(CsgOp::Union),
            Just(CsgOp::Intersect),
            Just(CsgOp::Subtract)
        ],
        [coord.clone(), coord.clone(), coord],
        prop_oneof![
            Just([0.0, 0.0, 0.0, 1.0]),
            [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0]
        ],
        prop_oneof![Just([1.0; 3]), [0.4f64..2.0, 0.4f64..2.0, 0.4f64..2.0]],
    )
        .prop_map(|(shape, csg, t, q, s)| {
            Operand::new(
                Component::Solid { shape },
                csg,
                Transform {
                    translate: t,
                    rotate: q,
                    scale: s,
                },
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]
    /// Random placements and op sequences (thin plates and rods, grazing
    /// and grid-aligned contacts): every update gives a closed 2-manifold
    /// and the incremental extraction equals a full one, bit for bit.
    #[test]
    fn random_sequences_stay_closed_and_incremental_equals_full(
        first in arb_operand(),
        batches in proptest::collection::vec(proptest::collection::vec(arb_operand(), 1..3), 1..3),
    ) {
        let mut v = SdfVolume::new(0.012).unwrap();
        v.pending.push(Operand { csg: CsgOp::Union, ..first });
        v = v.updated().unwrap();
        for b in batches {
            v.pending = b;
            v = v.updated().unwrap();
            let m = v.evaluate().unwrap();
            let full = full_mesh(&v);
            prop_assert_eq!(&m.positions, &full.positions);
            prop_assert_eq!(&m.normals, &full.normals);
            prop_assert_eq!(&m.triangles, &full.triangles);
            prop_assert!(m.normals.iter().all(|n| ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0).abs() < 1e-9));
            if !m.triangles.is_empty() {
                let r = validate(&m, &Default::default());
                prop_assert!(r.is_closed_manifold(), "{}", r.problems());
            }
        }
    }
}

#[test]
fn two_hand_scale_clamp_holds_across_gestures() {
    // Two gestures of ratio 4 each used to reach 16x; the reference scale
    // recorded by the first keeps every axis within [0.4, 4] of it.
    let o = op(sphere(0.1), CsgOp::Union, Transform::IDENTITY);
    let start = [[0.0; 3], [0.1, 0.0, 0.0]];
    let grow = [[0.0; 3], [1.0, 0.0, 0.0]];
    let shrink = [[0.0; 3], [0.001, 0.0, 0.0]];
    let a = o.scaled_two_hand(ScaleAxis::Uniform, start, grow).unwrap();
    assert_eq!(a.transform.scale, [4.0; 3]);
    let b = a.scaled_two_hand(ScaleAxis::Uniform, start, grow).unwrap();
    assert_eq!(
        b.transform.scale, [4.0; 3],
        "a second gesture cannot pass 4x"
    );
    let c = b.scaled_two_hand(ScaleAxis::X, start, shrink).unwrap();
    assert!(
        (c.transform.scale[0] - 0.4).abs() < 1e-12,
        "{:?}",
        c.transform.scale
    );
    assert_eq!(c.transform.scale[1], 4.0);
    let d = c.scaled_two_hand(ScaleAxis::X, start, shrink).unwrap();
    assert!((d.transform.scale[0] - 0.4).abs() < 1e-12, "nor below 0.4x");
    // A gesture inside the range scales by its ratio.
    let e = o
        .scaled_two_hand(ScaleAxis::Z, start, [[0.0; 3], [0.15, 0.0, 0.0]])
        .unwrap();
    assert!((e.transform.scale[2] - 1.5).abs() < 1e-12);
    assert!(matches!(
        o.scaled_two_hand(ScaleAxis::Z, [[0.0; 3]; 2], grow),
        Err(SdfError::HandsTooClose { .. })
    ));
}

fn lib(name: &str) -> Component {
    Component::Library { name: name.into() }
}

#[test]
fn a_drag_resamples_only_the_moved_operand_and_equals_a_cold_update() {
    let cache = crate::sdf::SdfCache::new();
    let mut v = SdfVolume::new(0.008).unwrap();
    v.pending = vec![
        op(lib("chair_seat"), CsgOp::Union, at([0.0, 0.0, 0.2])),
        op(lib("chair_leg"), CsgOp::Union, at([0.15, 0.15, 0.0])),
        op(cube(0.1), CsgOp::Subtract, at([0.0, 0.0, 0.25])),
    ];
    v.updated_with(&cache).unwrap();
    let (_, seat) = v.sampled_with(&v.pending[0], &cache).unwrap();
    let moved = v.with_pending(|p| p[1].transform.translate[0] = 0.12);
    let (_, seat2) = moved.sampled_with(&moved.pending[0], &cache).unwrap();
    assert!(
        std::sync::Arc::ptr_eq(&seat, &seat2),
        "the unmoved operand is reused"
    );
    let (_, leg) = v.sampled_with(&v.pending[1], &cache).unwrap();
    let (_, leg2) = moved.sampled_with(&moved.pending[1], &cache).unwrap();
    assert!(
        !std::sync::Arc::ptr_eq(&leg, &leg2),
        "the moved one is resampled"
    );
    // With cached samples or none, the same bits.
    let warm = moved
        .updated_with(&cache)
        .unwrap()
        .evaluate_with(&cache)
        .unwrap();
    let mut cold = SdfVolume::new(0.008).unwrap();
    cold.pending = moved.pending.clone();
    let cold = cold
        .updated_with(&crate::sdf::SdfCache::new())
        .unwrap()
        .evaluate_with(&cache)
        .unwrap();
    assert_eq!(warm.positions, cold.positions);
    assert_eq!(warm.triangles, cold.triangles);
    let r = check_closed(&warm);
    assert_eq!(r.components, 1);
}

#[test]
fn step_0_004_is_allowed_closed_and_the_same_on_one_and_two_threads() {
    assert!(matches!(SdfVolume::new(0.0039), Err(SdfError::BadStep(_))));
    let ops = vec![
        op(
            lib("cylinder"),
            CsgOp::Union,
            Transform {
                scale: [0.6; 3],
                ..Transform::IDENTITY
            },
        ),
        op(
            lib("cup_handle"),
            CsgOp::Union,
            Transform {
                translate: [0.17, 0.0, 0.0],
                rotate: [0.5f64.sqrt(), 0.0, 0.0, 0.5f64.sqrt()],
                scale: [0.38; 3],
            },
        ),
        op(
            lib("cylinder"),
            CsgOp::Subtract,
            Transform {
                translate: [0.0, 0.0, 0.03],
                scale: [0.525, 0.525, 0.6],
                ..Transform::IDENTITY
            },
        ),
    ];
    let go = |n| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| {
            let cache = crate::sdf::SdfCache::new();
            let mut v = SdfVolume::new(0.004).unwrap();
            v.pending = ops.clone();
            v.updated_with(&cache)
                .unwrap()
                .evaluate_with(&cache)
                .unwrap()
        })
    };
    let (a, b) = (go(1), go(2));
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.normals, b.normals);
    assert_eq!(a.triangles, b.triangles);
    let r = check_closed(&a);
    assert_eq!(r.genus, Some(1), "the cup and its handle: genus 1");
}

#[test]
fn the_fused_result_moves_copies_and_becomes_a_component() {
    let cache = crate::sdf::SdfCache::new();
    let mut v = SdfVolume::new(0.01).unwrap();
    v.pending = vec![
        op(sphere(0.15), CsgOp::Union, at([0.0, 0.0, 0.05])),
        op(
            Component::Solid {
                shape: SolidShape::Torus {
                    major_radius: 0.15,
                    minor_radius: 0.06,
                },
            },
            CsgOp::Subtract,
            at([0.0, 0.0, 0.05]),
        ),
    ];
    let v = v.updated_with(&cache).unwrap();
    let m0 = v.evaluate_with(&cache).unwrap();
    let r0 = check_closed(&m0);
    // Moved by a rigid motion and a uniform scale: the same solid there.
    let t = Transform {
        translate: [0.3, -0.1, 0.2],
        rotate: DQuat::from_rotation_z(0.7).to_array(),
        scale: [0.5; 3],
    };
    let moved = v.with_fused_moved(&t, &cache).unwrap();
    let m1 = moved.evaluate_with(&cache).unwrap();
    let r1 = check_closed(&m1);
    assert_eq!(r1.genus, r0.genus);
    let ratio = r1.signed_volume / (r0.signed_volume * 0.125);
    assert!((ratio - 1.0).abs() < 0.03, "volume ratio {ratio}");
    let c0 = m0.bbox().map(|(a, b)| (a + b) * 0.5).unwrap();
    let c1 = m1.bbox().map(|(a, b)| (a + b) * 0.5).unwrap();
    let want = DVec3::from_array(t.translate) + DQuat::from_array(t.rotate) * (c0 * 0.5);
    assert!((c1 - want).length() < 0.01, "{c1} vs {want}");
    let bad = Transform {
        scale: [1.0, 2.0, 1.0],
        ..Transform::IDENTITY
    };
    assert!(matches!(
        v.with_fused_moved(&bad, &cache),
        Err(SdfError::NotSimilarity(_))
    ));
    // Copied beside itself as a new operand, then fused: twice the volume.
    let copy = v
        .with_fused_copy("m", &at([0.5, 0.0, 0.0]), CsgOp::Union, &cache)
        .unwrap();
    assert_eq!(copy.pending.len(), 1);
    let both = copy
        .updated_with(&cache)
        .unwrap()
        .evaluate_with(&cache)
        .unwrap();
    let r2 = check_closed(&both);
    assert_eq!(r2.components, 2);
    assert!(
        (r2.signed_volume / (2.0 * r0.signed_volume) - 1.0).abs() < 0.03,
        "{} vs {}",
        r2.signed_volume,
        r0.signed_volume
    );
    assert!(matches!(
        copy.with_fused_copy("m", &Transform::IDENTITY, CsgOp::Union, &cache),
        Err(SdfError::DuplicateComponent(_))
    ));
    // Any closed mesh becomes a component placed where it was.
    let (user, back) = crate::sdf::reuse::component_from_mesh(&m0, None, &cache).unwrap();
    assert_eq!(user.positions.len(), m0.positions.len());
    let open = TriMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    );
    assert!(matches!(
        crate::sdf::reuse::component_from_mesh(&open, None, &cache),
        Err(SdfError::BadMesh(_))
    ));
    let mut w = SdfVolume::new(0.01).unwrap();
    w.user_components.insert("m".into(), user);
    w.pending
        .push(op(Component::User { name: "m".into() }, CsgOp::Union, back));
    let m3 = w
        .updated_with(&cache)
        .unwrap()
        .evaluate_with(&cache)
        .unwrap();
    let r3 = check_closed(&m3);
    assert_eq!(r3.genus, r0.genus);
    assert!((r3.signed_volume / r0.signed_volume - 1.0).abs() < 0.03);
}

/// A copy of the fused result that contains itself, or copies nested past
/// the limit (a document the ops cannot make, from a file or a peer), is a
/// typed error when sampled, not a stack overflow.
#[test]
fn copies_nested_in_themselves_or_too_deep_are_refused() {
    use crate::sdf::volume::UserMesh;
    let user = |n: &str| Component::User { name: n.into() };
    let mesh = crate::solid::tessellate(&SolidShape::Sphere { radius: 0.1 }, 16).unwrap();
    let mut v = SdfVolume::new(0.01).unwrap();
    v.user_components.insert(
        "a".into(),
        UserMesh::from_fused(
            mesh.clone(),
            vec![op(user("a"), CsgOp::Union, at([0.0; 3]))],
        ),
    );
    let looped = v.local_field(&user("a")).unwrap_err();
    assert!(
        matches!(&looped, SdfError::BadMesh(m) if m.contains("nested")),
        "{looped}"
    );
    let mut w = SdfVolume::new(0.01).unwrap();
    w.user_components.insert(
        "c0".into(),
        UserMesh::from_fused(
            mesh.clone(),
            vec![op(sphere(0.1), CsgOp::Union, at([0.0; 3]))],
        ),
    );
    for k in 1..=70 {
        let inner = op(user(&format!("c{}", k - 1)), CsgOp::Union, at([0.0; 3]));
        w.user_components.insert(
            format!("c{k}"),
            UserMesh::from_fused(mesh.clone(), vec![inner]),
        );
    }
    assert!(w.local_field(&user("c10")).is_ok());
    let deep = w.local_field(&user("c70")).unwrap_err();
    assert!(
        matches!(&deep, SdfError::BadMesh(m) if m.contains("deep")),
        "{deep}"
    );
}
