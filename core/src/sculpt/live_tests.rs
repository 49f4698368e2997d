//! Tests of live sculpting: a stroke applied sample by sample on a
//! sculptor kept between strokes gives the same bits as the committed
//! `sculpt_stroke` ops, and the render buffers updated from each frame's
//! changes equal buffers built from scratch.

use crate::math::fm::DetMath as _;
use glam::{DQuat, DVec3};

use super::object::stroke_poses;
use super::render::RenderBuffers;
use super::stroke::{Sculptor, StrokeFrames};
use super::tests::{create_op, sample, settings};
use super::warp::Warp;
use super::{BrushShape, SculptStroke, StrokeSample};
use crate::doc::{Edit, ObjectId, ObjectKind, Op, OpLog};

fn surface(log: &OpLog) -> super::HalfEdgeMesh {
    match &log.document().get(ObjectId(1)).unwrap().kind {
        ObjectKind::SculptMesh(m) => m.surface.clone(),
        #[allow(unreachable_patterns)]
        _ => unreachable!(),
    }
}

fn path(z: f64, n: usize, warp_scale: f64) -> Vec<StrokeSample> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.04 * warp_scale;
            sample(
                [t - 0.1, 0.05 * (3.0 * t).fsin(), z + t * 0.4],
                DQuat::from_rotation_y(t),
                (0.6 + t).min(1.0),
            )
        })
        .collect()
}

/// Incrementally updated buffers equal rebuilt ones in every live vertex
/// slot and every face slot (removed vertices may keep stale values).
fn assert_same_buffers(m: &super::HalfEdgeMesh, got: &RenderBuffers) {
    let want = RenderBuffers::from_mesh(m);
    assert_eq!(got.positions.len(), want.positions.len());
    assert_eq!(got.triangles.len(), want.triangles.len());
    for v in m.vertices() {
        let i = v.0 as usize;
        assert_eq!(
            got.positions[i], want.positions[i],
            "position of vertex {i}"
        );
        assert_eq!(got.normals[i], want.normals[i], "normal of vertex {i}");
    }
    for (f, (a, b)) in got.triangles.iter().zip(&want.triangles).enumerate() {
        assert_eq!(a, b, "face {f}");
    }
}

/// Live frames with render syncs after every frame, on one sculptor kept
/// across three strokes (refining, explode, whittle), match the ops.
#[test]
fn live_strokes_match_the_ops_and_incremental_buffers_match_rebuilt_ones() {
    let mut log = OpLog::new();
    log.apply(create_op(0.07)).unwrap();
    let mut sc = Sculptor::new(surface(&log), 0.3);
    let mut buffers = RenderBuffers::from_mesh(sc.mesh());
    let strokes = [
        (Warp::Drag, path(1.0, 12, 1.0), 0.15),
        (Warp::Explode { delta: -0.3 }, path(0.9, 6, 0.5), 0.2),
        (Warp::Whittle, path(1.05, 8, 1.0), 0.2),
    ];
    let mut uploaded = 0usize;
    let mut stats = Vec::new();
    for (warp, samples, r) in strokes {
        // Edges of the base within [min, max]: only the stroke adapts.
        let s = settings(BrushShape::Sphere { radius: r }, 0.12, warp);
        let transform = Default::default();
        let mut frames = StrokeFrames::begin(&mut sc, &s.brush, &s, 1.0);
        let mut prev = None;
        for smp in &samples {
            // The pose of one sample, converted as the op converts its path.
            let (_, poses) = stroke_poses(&transform, &s, std::slice::from_ref(smp)).unwrap();
            let before = prev.unwrap_or(poses[0].0.position);
            prev = Some(poses[0].0.position);
            frames.frame(&mut sc, poses[0].0, poses[0].1);
            let dirty = sc.sync_render(&mut buffers);
            // Only the brush's neighbourhood is rewritten: every uploaded
            // live vertex lies within reach (+ a ring of adapted edges) of
            // the brush's previous or current position.
            let reach = r + 0.12 + 3.0 * 0.6 * r;
            for v in dirty.vertices.iter().flat_map(|x| x.clone()) {
                let v = super::VertId(v);
                if sc.mesh().vert_alive(v) {
                    let x = sc.mesh().position(v);
                    let d = x.distance(before).min(x.distance(poses[0].0.position));
                    assert!(d <= reach, "vertex {} uploaded {d} from the brush", v.0);
                }
            }
            uploaded += dirty.vertex_count();
            assert_same_buffers(sc.mesh(), &buffers);
        }
        let total = frames.total();
        assert!(total.moved > 0);
        stats.push(total);
        log.apply(Op::SculptStroke(Edit::new(
            ObjectId(1),
            SculptStroke {
                mirror: None,
                settings: s,
                samples,
            },
        )))
        .unwrap();
        assert_eq!(*sc.mesh(), surface(&log), "live stroke differs from its op");
    }
    assert!(uploaded > 0);
    // The strokes exercised refinement and coarsening.
    assert!(stats.iter().any(|s| s.splits > 0), "{stats:?}");
    assert!(stats.iter().any(|s| s.collapses > 0), "{stats:?}");
}

/// A frame far from the surface changes nothing and uploads nothing; a
/// sync with no frame in between uploads nothing either.
#[test]
fn idle_frames_upload_nothing() {
    let mut log = OpLog::new();
    log.apply(create_op(0.2)).unwrap();
    let mut sc = Sculptor::new(surface(&log), 0.3);
    let mut buffers = RenderBuffers::from_mesh(sc.mesh());
    let s = settings(BrushShape::Sphere { radius: 0.2 }, 0.1, Warp::Drag);
    let mut frames = StrokeFrames::begin(&mut sc, &s.brush, &s, 1.0);
    let far = super::BrushPose {
        position: DVec3::new(5.0, 0.0, 0.0),
        rotation: DQuat::IDENTITY,
        scale: 1.0,
    };
    let st = frames.frame(&mut sc, far, 1.0);
    assert_eq!(st.moved, 0);
    let d = sc.sync_render(&mut buffers);
    assert_eq!((d.vertex_count(), d.triangle_count()), (0, 0));
    assert!(!d.capacity_grew);
    assert_eq!(sc.sync_render(&mut buffers), Default::default());
}

/// Frames large enough for every parallel pass (thousands of reached
/// vertices, splits and collapses) give the same bits on one and on two
/// threads.
#[test]
fn large_frames_give_the_same_bits_on_one_and_two_threads() {
    let base =
        super::HalfEdgeMesh::from_trimesh(&super::base::geodesic_sphere(1.0, 80), "base").unwrap();
    let mut s = settings(BrushShape::Sphere { radius: 0.4 }, 0.3, Warp::Drag);
    // Edges of the 80-frequency sphere are about 0.013.
    s.max_edge_rel = 0.022 / 0.4;
    s.min_edge_rel = 0.009 / 0.4;
    let poses: Vec<(super::BrushPose, f64)> = (0..6)
        .map(|i| {
            let t = i as f64 * 0.03;
            (
                super::BrushPose {
                    position: DVec3::new(t, 0.2 * t, 1.1 + t),
                    rotation: DQuat::from_rotation_x(t),
                    scale: 1.0,
                },
                1.0,
            )
        })
        .collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut sc = Sculptor::new(base.clone(), 0.2);
            let mut buffers = RenderBuffers::from_mesh(sc.mesh());
            let mut frames = StrokeFrames::begin(&mut sc, &s.brush, &s, 1.0);
            let mut dirty = Vec::new();
            for &(pose, pressure) in &poses {
                frames.frame(&mut sc, pose, pressure);
                dirty.push(sc.sync_render(&mut buffers));
            }
            (frames.total(), sc.into_mesh(), buffers, dirty)
        })
    };
    let (stats, one, buf1, dirty1) = run(1);
    let (_, two, buf2, dirty2) = run(2);
    assert!(stats.moved > 6 * super::par::PAR_MIN, "{stats:?}");
    assert!(stats.splits > 0 && stats.collapses > 0, "{stats:?}");
    assert!(one == two, "meshes differ between 1 and 2 threads");
    assert!(buf1 == buf2 && dirty1 == dirty2);
    one.check().unwrap();
}
