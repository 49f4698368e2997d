//! Tests of grid brushes generated from meshes: agreement with the
//! analytic brush they approximate, refusal of open / non-manifold meshes,
//! undo and replay with inline and by-id (self included) brushes.

use glam::DQuat;

use super::base::geodesic_sphere;
use super::brush::BrushShape;
use super::mesh_brush::{MeshBrush, MeshSource};
use super::tests::{assert_undo_redo_replay, create_op, sample, settings};
use super::warp::Warp;
use super::{SculptError, SculptStroke};
use crate::doc::{Edit, LogError, ObjectId, Op, OpError, OpLog};

fn inline_sphere(radius: f64, freq: u32, step: f64) -> BrushShape {
    let m = geodesic_sphere(radius, freq);
    BrushShape::Mesh(MeshBrush {
        source: MeshSource::Mesh {
            positions: m.positions,
            triangles: m.triangles,
        },
        step,
        padding: 2.0 * step,
    })
}

fn stroke(id: u32, brush: BrushShape, brush_scale: f64, warp: Warp) -> Op {
    let mut s = settings(brush, 0.2, warp);
    s.brush_scale = brush_scale;
    Op::SculptStroke(Edit::new(
        ObjectId(id),
        SculptStroke {
            mirror: None,
            settings: s,
            samples: (0..4)
                .map(|i| {
                    let t = i as f64 * 0.04;
                    sample([t, 0.05, 1.15 + t], DQuat::from_rotation_y(t), 1.0)
                })
                .collect(),
        },
    ))
}

#[test]
fn sphere_mesh_brush_warps_like_the_analytic_sphere() {
    let step = 0.01;
    let run = |brush: BrushShape| {
        let mut log = OpLog::new();
        log.apply(create_op(0.08)).unwrap();
        let mut op = stroke(1, brush, 1.0, Warp::Explode { delta: -0.2 });
        if let Op::SculptStroke(s) = &mut op {
            // No adaptation: both brushes move the same vertices.
            s.settings.max_edge_rel = 100.0;
            s.settings.min_edge_rel = 1e-6;
        }
        let before = log.document().get(ObjectId(1)).unwrap().mesh.clone();
        log.apply(op).unwrap();
        let after = log.document().get(ObjectId(1)).unwrap().mesh.clone();
        (before, after)
    };
    let (base, analytic) = run(BrushShape::Sphere { radius: 0.3 });
    let (_, grid) = run(inline_sphere(0.3, 24, step));
    assert_eq!(analytic.positions.len(), grid.positions.len());
    let mut max_move = 0.0f64;
    let mut diffs = Vec::new();
    for ((a, g), b) in analytic
        .positions
        .iter()
        .zip(&grid.positions)
        .zip(&base.positions)
    {
        let (a, g, b) = (
            glam::DVec3::from_array(*a),
            glam::DVec3::from_array(*g),
            glam::DVec3::from_array(*b),
        );
        max_move = max_move.max((a - b).length());
        diffs.push((a - g).length());
    }
    diffs.sort_by(f64::total_cmp);
    let p99 = diffs[diffs.len() * 99 / 100];
    let max_diff = diffs[diffs.len() - 1];
    println!("mesh vs analytic brush: p99 {p99:.4}, max {max_diff:.4}");
    assert!(max_move > 0.05, "the stroke moved at most {max_move}");
    // Measured 0.0150 at most (p99 0.0021) over this 4-frame collapse
    // with padding 2·step (the vertices beyond the grid box, up to h
    // away, use the box's extrapolation): within two grid steps, not one.
    // A stronger collapse (delta -0.3) makes the fold guard halve steps,
    // and its verdicts are discrete: one brush's field halving a step the
    // other's does not moved vertices 0.06 apart, which says nothing of
    // the fields' agreement.
    assert!(
        max_diff < 2.0 * step,
        "mesh brush differs from the analytic one by {max_diff} (step {step})"
    );
}

/// What a refused op's error must satisfy.
type Check = dyn Fn(&SculptError) -> bool;

#[test]
fn open_or_non_manifold_brush_mesh_is_refused_and_changes_nothing() {
    let mut log = OpLog::new();
    log.apply(create_op(0.2)).unwrap();
    let before = log.document().content_hash();
    let with_mesh = |f: &dyn Fn(&mut MeshBrush)| {
        let mut b = match inline_sphere(0.3, 4, 0.02) {
            BrushShape::Mesh(b) => b,
            _ => unreachable!(),
        };
        f(&mut b);
        stroke(1, BrushShape::Mesh(b), 1.0, Warp::Drag)
    };
    let tris = |b: &mut MeshBrush, f: &dyn Fn(&mut Vec<[u32; 3]>)| {
        if let MeshSource::Mesh { triangles, .. } = &mut b.source {
            f(triangles)
        }
    };
    let cases: Vec<(Op, &Check)> = vec![
        (
            with_mesh(&|b| {
                tris(b, &|t| {
                    t.pop();
                })
            }),
            &|e: &SculptError| matches!(e, SculptError::NotClosedManifold { what: "brush", .. }),
        ),
        (
            with_mesh(&|b| tris(b, &|t| t.push(t[0]))),
            &|e: &SculptError| matches!(e, SculptError::NotClosedManifold { what: "brush", .. }),
        ),
        (with_mesh(&|b| b.step = 0.0), &|e: &SculptError| {
            matches!(e, SculptError::NonPositive { .. })
        }),
        (with_mesh(&|b| b.padding = -0.1), &|e: &SculptError| {
            matches!(e, SculptError::OutOfRange { .. })
        }),
        (with_mesh(&|b| b.step = 1e-4), &|e: &SculptError| {
            matches!(e, SculptError::BrushTooLarge { .. })
        }),
    ];
    for (op, check) in cases {
        match log.apply(op) {
            Err(LogError::Op(OpError::Sculpt(e))) => assert!(check(&e), "{e}"),
            other => panic!("unexpected {other:?}"),
        }
    }
    // A NaN vertex is refused at the door, naming it; the brush code's own
    // check guards callers that bypass the log.
    let nan = with_mesh(&|b| {
        if let MeshSource::Mesh { positions, .. } = &mut b.source {
            positions[3][1] = f64::NAN;
        }
    });
    match log.apply(nan.clone()) {
        Err(LogError::Op(OpError::BadField { field, .. })) => {
            assert_eq!(field, "settings.brush.source.positions[3][1]")
        }
        other => panic!("unexpected {other:?}"),
    }
    let Op::SculptStroke(s) = &nan else {
        unreachable!()
    };
    let BrushShape::Mesh(b) = &s.settings.brush else {
        unreachable!()
    };
    assert!(matches!(b.validate(), Err(SculptError::NonFinite { .. })));
    let by_bad_id = stroke(
        1,
        BrushShape::Mesh(MeshBrush {
            source: MeshSource::Object { id: ObjectId(9) },
            step: 0.05,
            padding: 0.1,
        }),
        0.2,
        Warp::Drag,
    );
    assert!(matches!(
        log.apply(by_bad_id),
        Err(LogError::Op(OpError::BadId(_)))
    ));
    assert_eq!(log.document().content_hash(), before);
    assert_eq!(log.len(), 1);
}

#[test]
fn mesh_brushes_by_id_and_inline_undo_and_replay_bit_identically() {
    let mut log = OpLog::new();
    log.apply(create_op(0.1)).unwrap();
    let by_id = |id: u32, step: f64| {
        BrushShape::Mesh(MeshBrush {
            source: MeshSource::Object { id: ObjectId(id) },
            step,
            padding: 2.0 * step,
        })
    };
    let ops = [
        // Object 2: a coarse sphere used as a brush by id.
        create_op(0.3),
        stroke(1, by_id(2, 0.05), 0.25, Warp::Drag),
        // The sculpted model itself, as it is before this stroke.
        stroke(1, by_id(1, 0.05), 0.2, Warp::Explode { delta: 0.2 }),
        stroke(1, inline_sphere(0.2, 6, 0.02), 1.0, Warp::Whittle),
    ];
    assert_undo_redo_replay(&mut log, &ops);
}

/// Issue 33: mesh brushes refined four times coarser than the analytic
/// brush of the same shape (their size was the padded grid box's corner:
/// an explode made 498 triangles against 3,920). The headset's "explode"
/// preset (a 4.5 cm sphere, max edge 0.14 of its size) on its 10 cm
/// sculpt sphere, as the analytic sphere and as a brush made from a
/// sphere mesh of the same radius (gridded as the brush tool grids
/// objects: 40 cells across, padded by the influence): both refine alike.
#[test]
fn a_mesh_brush_refines_like_the_analytic_brush_of_its_shape() {
    let r = 0.045;
    let run = |brush: BrushShape| {
        let mut log = OpLog::new();
        log.apply(Op::SculptCreate(crate::doc::Create(super::SculptCreate {
            base: super::SculptBase::Sphere {
                radius: 0.1,
                edge_length: 0.006,
            },
            transform: Default::default(),
        })))
        .unwrap();
        let before = log
            .document()
            .get(ObjectId(1))
            .unwrap()
            .mesh
            .triangles
            .len() as i64;
        let mut s = settings(brush, r, Warp::Explode { delta: 0.15 });
        s.max_edge_rel = 0.14;
        s.min_edge_rel = 0.04;
        log.apply(Op::SculptStroke(Edit::new(
            ObjectId(1),
            SculptStroke {
                mirror: None,
                settings: s,
                samples: (0..4)
                    .map(|i| sample([0.005 * i as f64, 0.0, 0.06], DQuat::IDENTITY, 1.0))
                    .collect(),
            },
        )))
        .unwrap();
        log.document()
            .get(ObjectId(1))
            .unwrap()
            .mesh
            .triangles
            .len() as i64
            - before
    };
    let analytic = run(BrushShape::Sphere { radius: r });
    let m = geodesic_sphere(r, 12);
    let mesh = run(BrushShape::Mesh(MeshBrush {
        source: MeshSource::Mesh {
            positions: m.positions,
            triangles: m.triangles,
        },
        step: 2.0 * r / 40.0,
        padding: r,
    }));
    println!(
        "explode added {analytic} triangles with the analytic sphere, {mesh} with the mesh brush"
    );
    assert!(analytic > 1000, "{analytic}");
    let ratio = mesh as f64 / analytic as f64;
    assert!(
        (0.8..1.25).contains(&ratio),
        "the mesh brush refined {mesh} triangles, the analytic one {analytic}"
    );
}

/// A grid brush's size is its surface's radius, not its box's corner.
#[test]
fn a_grid_brush_is_the_size_of_its_surface() {
    for (r, pad) in [(0.045, 0.045), (1.0, 0.3)] {
        let m = geodesic_sphere(r, 12);
        let grid = MeshBrush {
            source: MeshSource::Mesh {
                positions: m.positions,
                triangles: m.triangles,
            },
            step: 2.0 * r / 40.0,
            padding: pad,
        }
        .to_grid(None)
        .unwrap();
        let shape = BrushShape::Grid(grid);
        let size = shape.size_radius();
        println!(
            "sphere {r}: grid brush size {size}, bound {}",
            shape.bound_radius()
        );
        assert!((size - r).abs() < 0.02 * r, "size {size} for radius {r}");
        assert!(shape.bound_radius() >= size);
    }
}
