//! The sculpt ops' time budget (issues 33 and 37): no accepted sculpt op
//! runs longer than `sculpt::budget::MAX_SECONDS` on this machine, a
//! refusal comes at once and says what it estimated, and the estimate is
//! right: each op kind, sized so that its estimate is just under the
//! limit, runs within it (CPU seconds of the whole process, so a loaded
//! machine does not fail it; tests here run one at a time).
//!
//! The estimate's constants are for the release build (what the hosts
//! ship); this test's build runs the core at `opt-level = 1`, measured
//! here to be at most [`BUILD_FACTOR`] times slower, so a run at the limit
//! may take that much longer here. `calibrate` (ignored; run with
//! `--release --ignored --nocapture`) prints the measurements the
//! constants come from.

use crate::common;

use common::timed;
use shapewright::math::fm::DetMath as _;

use glam::{DQuat, DVec3};
use shapewright::budget::OverBudget;
use shapewright::doc::{Create, Edit, LogError, ObjectId, ObjectKind, Op, OpError, OpLog};
use shapewright::math::MirrorPlane;
use shapewright::sculpt::base::geodesic_sphere;
use shapewright::sculpt::budget::MAX_SECONDS;
use shapewright::sculpt::{
    BrushShape, Falloff, MeshBrush, MeshSource, SculptBase, SculptCreate, SculptError,
    SculptStroke, StrokeSample, StrokeSettings, Warp,
};

/// How much slower this build runs a sculpt op than the release build
/// the constants are for.
const BUILD_FACTOR: f64 = if cfg!(debug_assertions) { 2.5 } else { 1.0 };

fn create(radius: f64, edge: f64) -> Op {
    Op::SculptCreate(Create(SculptCreate {
        base: SculptBase::Sphere {
            radius,
            edge_length: edge,
        },
        transform: Default::default(),
    }))
}

fn settings(brush: BrushShape, influence: f64, warp: Warp, max_edge_rel: f64) -> StrokeSettings {
    StrokeSettings {
        brush,
        brush_scale: 1.0,
        influence,
        falloff: Falloff::Smooth,
        warp,
        max_edge_rel,
        min_edge_rel: max_edge_rel * 2.0 / 7.0,
    }
}

/// `n` samples on half a circle, sample `i` at the angle `a` =
/// π·i/n placed by `place(a)` (position, brush rotation).
fn half_circle(n: usize, place: impl Fn(f64) -> ([f64; 3], DQuat)) -> Vec<StrokeSample> {
    (0..n)
        .map(|i| {
            let (position, rotation) =
                place(std::f64::consts::TAU * i as f64 / n.max(1) as f64 * 0.5);
            StrokeSample {
                position,
                rotation: rotation.to_array(),
                pressure: 1.0,
            }
        })
        .collect()
}

/// `n` samples on a circle of radius `ring` at height `z` around the
/// sphere's axis, the brush turning slowly.
fn circle(n: usize, ring: f64, z: f64) -> Vec<StrokeSample> {
    half_circle(n, |a| {
        let p = [ring * a.fcos(), ring * a.fsin(), z];
        (p, DQuat::from_rotation_z(0.3 * a))
    })
}

/// `n` samples on half a circle of radius `ring` around the X axis at
/// `x`: a path that stays on the +X side, so its mirror image in the
/// X = 0 plane stays on the other (the two brushes never meet).
fn circle_around_x(n: usize, ring: f64, x: f64) -> Vec<StrokeSample> {
    half_circle(n, |a| {
        let p = [x, ring * a.fcos(), ring * a.fsin()];
        (p, DQuat::from_rotation_x(0.3 * a))
    })
}

fn stroke(settings: &StrokeSettings, samples: Vec<StrokeSample>, mirror: bool) -> SculptStroke {
    SculptStroke {
        settings: settings.clone(),
        samples,
        mirror: mirror.then(|| Box::new(MirrorPlane::new(DVec3::ZERO, DVec3::X).unwrap())),
    }
}

fn log_with(ops: &[Op]) -> OpLog {
    let mut log = OpLog::new();
    for op in ops {
        log.apply(op.clone()).unwrap();
    }
    log
}

/// The estimate of `s` on object 1 of `log`, or its refusal.
fn estimate(log: &OpLog, s: &SculptStroke) -> Result<f64, SculptError> {
    let ObjectKind::SculptMesh(m) = &log.document().get(ObjectId(1)).unwrap().kind else {
        panic!("object 1 is not a sculpt");
    };
    let brush = s
        .brush_object()
        .map(|id| log.document().get(id).unwrap().mesh.clone());
    Ok(s.estimate(m, brush.as_deref())?.seconds())
}

/// The most samples of `make(n)` whose estimate stays within
/// `frac × MAX_SECONDS` (bisection over `1..=max`).
fn samples_for(log: &OpLog, frac: f64, max: usize, make: &dyn Fn(usize) -> SculptStroke) -> usize {
    let (mut lo, mut hi) = (1usize, max);
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        match estimate(log, &make(mid)) {
            Ok(s) if s <= frac * MAX_SECONDS => lo = mid,
            _ => hi = mid - 1,
        }
    }
    lo
}

/// Runs `op` and checks its time against its estimate; returns the CPU
/// seconds. The op either completes or is stopped by the backstop (a
/// surface crumpled under the brush costs more than the parameters say;
/// the stroke counts that work and stops at the limit): either way
/// within the limit, and a stopped op leaves the document as it was.
fn run_at_limit(name: &str, mut log: OpLog, op: Op, estimated: f64) -> f64 {
    let hash = log.document().content_hash();
    let (r, cpu, wall) = timed(|| log.apply(op));
    let outcome = match r {
        Ok(_) => "completed".to_string(),
        Err(LogError::Op(OpError::Sculpt(e @ SculptError::TooSlow { .. }))) => {
            assert_eq!(log.document().content_hash(), hash, "{name}");
            format!("stopped by the backstop: {e}")
        }
        Err(e) => panic!("{name}: {e}"),
    };
    println!(
        "{name}: estimated {estimated:.2} s, ran {cpu:.2} s CPU ({wall:.2} s wall) in a build {BUILD_FACTOR}x slower than release; {outcome}"
    );
    assert!(
        cpu <= MAX_SECONDS * BUILD_FACTOR * 1.2,
        "{name}: ran {cpu:.1} s CPU, over the limit ({MAX_SECONDS} s, x{BUILD_FACTOR} for this build)"
    );
    // The whittle only contracts: the estimate charges it the refinement
    // of its whole reach, which it does not do where the surface is
    // already smooth (measured 5.5x pessimistic, 2026-11-29; 8.9x in the
    // release build once the fold guard tested each pair of triangles
    // once, 2026-11-30). A mirrored stroke whose mirror image retraces
    // its own path (a half circle around Z, which the X = 0 plane maps
    // onto itself, walked back) is charged both brushes in full, but the second
    // refines what the first already refined: up to twice the plain
    // pessimism (measured 4.35x once in a loaded full run, 2026-12-01).
    let pessimism = if name.starts_with("whittle") {
        12.0
    } else if name.contains("retracing") {
        8.0
    } else {
        4.0
    };
    assert!(
        cpu * pessimism >= estimated * BUILD_FACTOR.min(1.0) && cpu >= 0.1,
        "{name}: ran {cpu:.2} s, the estimate {estimated:.2} s is far too pessimistic"
    );
    cpu
}

/// The refusal of an op past the limit comes at once and states what it
/// estimated, above the limit: its time, or (when a frame alone is too
/// big, which is checked first) its size.
fn refused_at_once(name: &str, mut log: OpLog, op: Op) {
    let hash = log.document().content_hash();
    let (r, cpu, _) = timed(|| log.apply(op));
    let e = r.expect_err(name);
    println!("{name}: refused in {cpu:.2} s CPU: {e}");
    match &e {
        LogError::Op(OpError::Sculpt(SculptError::TooSlow { seconds, limit, .. })) => {
            assert!(*seconds > *limit && *limit == MAX_SECONDS, "{name}: {e}");
        }
        LogError::Op(OpError::Sculpt(SculptError::OverBudget(OverBudget {
            estimate,
            limit,
            ..
        }))) => assert!(*estimate > *limit, "{name}: {e}"),
        _ => panic!("{name}: {e}"),
    }
    assert!(cpu < 1.0 * BUILD_FACTOR, "{name}: refused after {cpu:.2} s");
    assert_eq!(log.document().content_hash(), hash);
}

#[test]
fn each_stroke_kind_at_the_time_limit_runs_within_it() {
    let _one = crate::serial();
    let base = [create(1.0, 0.03)];
    let log = log_with(&base);
    let sphere = |r| BrushShape::Sphere { radius: r };
    let drag = settings(sphere(0.3), 0.3, Warp::Drag, 0.05);
    type Path = fn(usize) -> Vec<StrokeSample>;
    let around_z: Path = |n| circle(n, 0.6, 0.85);
    let apart: Path = |n| circle_around_x(n, 0.35, 0.9);
    let kinds: Vec<(&str, StrokeSettings, bool, Path)> = vec![
        ("drag", drag.clone(), false, around_z),
        (
            "explode",
            settings(sphere(0.3), 0.3, Warp::Explode { delta: 0.05 }, 0.05),
            false,
            around_z,
        ),
        (
            "whittle",
            settings(sphere(0.3), 0.2, Warp::Whittle, 0.05),
            false,
            around_z,
        ),
        // The mirror image of the half circle around Z is the same half
        // circle, walked the other way.
        ("mirrored drag, retracing", drag.clone(), true, around_z),
        // Around +X: the two brushes stay 1.8 apart.
        ("mirrored drag, apart", drag, true, apart),
    ];
    for (name, s, mirror, path) in kinds {
        let make = |n: usize| stroke(&s, path(n), mirror);
        let n = samples_for(&log, 0.9, 20_000, &make);
        let op = make(n);
        let est = estimate(&log, &op).unwrap();
        println!("{name}: {n} samples");
        let over = make(n * 3 / 2 + 2);
        run_at_limit(
            name,
            log_with(&base),
            Op::SculptStroke(Edit::new(ObjectId(1), op)),
            est,
        );
        refused_at_once(
            &format!("{name} x1.5"),
            log_with(&base),
            Op::SculptStroke(Edit::new(ObjectId(1), over)),
        );
    }
}

#[test]
fn a_mesh_brush_stroke_at_the_time_limit_runs_within_it() {
    let _one = crate::serial();
    let base = [create(1.0, 0.03)];
    let log = log_with(&base);
    let m = geodesic_sphere(0.3, 16);
    // A fine grid: most of the time is sampling it.
    let brush = BrushShape::Mesh(MeshBrush {
        source: MeshSource::Mesh {
            positions: m.positions,
            triangles: m.triangles,
        },
        step: 0.6 / 60.0,
        padding: 0.3,
    });
    let s = settings(brush, 0.3, Warp::Drag, 0.05);
    let make = |n: usize| stroke(&s, circle(n, 0.6, 0.85), false);
    let n = samples_for(&log, 0.9, 20_000, &make);
    let op = make(n);
    let est = estimate(&log, &op).unwrap();
    println!("mesh brush: {n} samples");
    run_at_limit(
        "mesh brush",
        log_with(&base),
        Op::SculptStroke(Edit::new(ObjectId(1), op)),
        est,
    );
    refused_at_once(
        "mesh brush x1.5",
        log_with(&base),
        Op::SculptStroke(Edit::new(ObjectId(1), make(n * 3 / 2 + 2))),
    );
}

#[test]
fn a_base_mesh_at_the_time_limit_is_built_within_it() {
    let _one = crate::serial();
    // The finest sphere under 0.9 of the limit (edge lengths in 2% steps).
    let mut edge = 0.0005;
    let ok = |e: f64| {
        shapewright::sculpt::base::sphere_frequency(1.0, e).is_ok_and(|n| {
            let v = 10.0 * (n as f64).fpowi(2) + 2.0;
            shapewright::sculpt::budget::CreateCost { vertices: v }.seconds() <= 0.9 * MAX_SECONDS
        })
    };
    while !ok(edge) {
        edge *= 1.02;
    }
    let n = shapewright::sculpt::base::sphere_frequency(1.0, edge).unwrap() as f64;
    let est = shapewright::sculpt::budget::CreateCost {
        vertices: 10.0 * n * n + 2.0,
    }
    .seconds();
    run_at_limit("sculpt_create", OpLog::new(), create(1.0, edge), est);
    refused_at_once("sculpt_create x1.5", OpLog::new(), create(1.0, edge / 1.25));
}

/// Issue 37: "a single 600-sample sculpt_stroke (a 52 KB script) passes
/// the stroke budget and runs 368 s before it is refused, with a
/// self-contradicting message". Such a stroke (each frame refining about
/// 700 k triangles, the old budget's sum 4.2e8 of its 5e8) is refused at
/// once, with a message whose estimate is above its limit.
#[test]
fn the_600_sample_stroke_is_refused_at_once() {
    let _one = crate::serial();
    let base = [create(1.0, 0.06)];
    let s = settings(BrushShape::Sphere { radius: 0.7 }, 0.7, Warp::Drag, 0.0027);
    let op = stroke(&s, circle(600, 0.1, 0.6), false);
    let text =
        serde_json::to_string(&Op::SculptStroke(Edit::new(ObjectId(1), op.clone()))).unwrap();
    println!("the stroke is {} KB of script", text.len() / 1024);
    refused_at_once(
        "600 samples",
        log_with(&base),
        Op::SculptStroke(Edit::new(ObjectId(1), op)),
    );
}

/// Issue 37: "one glitched rotation sample in a mirrored stroke does the
/// same". A mirrored stroke whose one sample turns the brush half a turn
/// and back either runs within the limit or is refused at once.
#[test]
fn a_mirrored_stroke_with_a_glitched_rotation_is_bounded() {
    let _one = crate::serial();
    let base = [create(1.0, 0.06)];
    let s = settings(BrushShape::Sphere { radius: 0.7 }, 0.7, Warp::Drag, 0.05);
    let mut samples = circle(60, 0.3, 0.8);
    samples[30].rotation = DQuat::from_rotation_x(std::f64::consts::PI).to_array();
    let op = Op::SculptStroke(Edit::new(ObjectId(1), stroke(&s, samples, true)));
    let mut log = log_with(&base);
    let (r, cpu, wall) = timed(|| log.apply(op));
    println!(
        "glitched mirrored stroke: {:?} in {cpu:.2} s CPU ({wall:.2} s wall)",
        r.as_ref().err().map(|e| e.to_string())
    );
    match r {
        Ok(_) => assert!(cpu <= MAX_SECONDS * BUILD_FACTOR * 1.2, "ran {cpu} s"),
        Err(e) => {
            assert!(cpu < 1.0 * BUILD_FACTOR, "refused after {cpu} s: {e}");
            assert!(matches!(e, LogError::Op(OpError::Sculpt(_))), "{e}");
        }
    }
}

/// Prints what the constants of `sculpt::budget` are fitted to: each
/// case's estimate terms and its measured CPU time.
#[test]
#[ignore]
fn calibrate() {
    let _one = crate::serial();
    println!("case\tfaces\tgrid\tunits\tframes\testimate\tcpu\twall\test_tris\tfaces_after");
    let row = |name: &str, log: &mut OpLog, s: SculptStroke| {
        let ObjectKind::SculptMesh(m) = &log.document().get(ObjectId(1)).unwrap().kind else {
            unreachable!()
        };
        let cost = match s.estimate(m, None) {
            Ok(c) => c,
            Err(e) => {
                println!("{name}\trefused: {e}");
                return;
            }
        };
        let (r, cpu, wall) = timed(|| log.apply(Op::SculptStroke(Edit::new(ObjectId(1), s))));
        let after = log
            .document()
            .get(ObjectId(1))
            .unwrap()
            .mesh
            .triangles
            .len();
        println!(
            "{name}\t{}\t{}\t{:.0}\t{}\t{:.3}\t{cpu:.3}\t{wall:.3}\t{:.0}\t{after}\t{}",
            cost.faces,
            cost.grid_samples,
            cost.units,
            cost.frames,
            cost.seconds(),
            cost.triangles,
            r.err().map_or(String::new(), |e| e.to_string())
        );
    };
    for edge in [0.02, 0.01, 0.005, 0.0025] {
        let (r, cpu, wall) = timed(|| log_with(&[create(1.0, edge)]));
        let faces = r.document().get(ObjectId(1)).unwrap().mesh.triangles.len();
        println!(
            "create {edge}\t{faces}\t0\t0\t0\t{:.3}\t{cpu:.3}\t{wall:.3}",
            0.0
        );
        let mut log = r;
        let s = settings(BrushShape::Sphere { radius: 0.01 }, 0.01, Warp::Drag, 0.5);
        row(
            &format!("dab on {edge}"),
            &mut log,
            stroke(&s, circle(2, 0.0, 1.0), false),
        );
    }
    for (r, max, n, warp) in [
        (0.3, 0.05, 50, Warp::Drag),
        (0.3, 0.05, 100, Warp::Drag),
        (0.2, 0.05, 50, Warp::Drag),
        (0.4, 0.05, 50, Warp::Drag),
        (0.5, 0.05, 50, Warp::Drag),
        (0.3, 0.1, 50, Warp::Drag),
        (0.3, 0.02, 20, Warp::Drag),
        (0.1, 0.05, 200, Warp::Drag),
        (0.5, 0.03, 20, Warp::Drag),
        (0.3, 0.05, 50, Warp::Explode { delta: 0.05 }),
        (0.3, 0.05, 50, Warp::Whittle),
        (0.3, 0.02, 50, Warp::Explode { delta: -0.05 }),
    ] {
        let mut log = log_with(&[create(1.0, 0.03)]);
        let s = settings(BrushShape::Sphere { radius: r }, r, warp, max);
        row(
            &format!("{warp:?} r{r} max{max} n{n}"),
            &mut log,
            stroke(&s, circle(n, 0.6, 0.85), false),
        );
    }
    for cells in [40.0, 80.0, 120.0] {
        let mut log = log_with(&[create(1.0, 0.03)]);
        let m = geodesic_sphere(0.3, 16);
        let brush = BrushShape::Mesh(MeshBrush {
            source: MeshSource::Mesh {
                positions: m.positions,
                triangles: m.triangles,
            },
            step: 0.6 / cells,
            padding: 0.3,
        });
        let s = settings(brush, 0.3, Warp::Drag, 0.5);
        row(
            &format!("mesh brush {cells}"),
            &mut log,
            stroke(&s, circle(2, 0.0, 1.0), false),
        );
    }
}
