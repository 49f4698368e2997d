//! Interaction costs per frame (a 90 Hz frame has 11 ms for everything):
//! gesture classification of one hand, ray picking against a scene of
//! solids, a whole session step, and replaying the checked-in trace.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, Criterion};
use shapewright::doc::{AddSolid, Op, OpLog};
use shapewright::interact::testkit::{labelled_sequence, SequenceSettings};
use shapewright::interact::{pick, replay, GestureClassifier, Hand, Ray, Sanitizer, Trace};
use shapewright::math::{DVec3, Transform};
use shapewright::solid::SolidShape;

fn scene(n: usize) -> OpLog {
    let mut log = OpLog::new();
    for i in 0..n {
        log.apply(Op::AddSolid(AddSolid {
            shape: SolidShape::Sphere { radius: 0.1 },
            segments: 64,
            transform: Transform::translation([(i % 4) as f64 * 0.3, (i / 4) as f64 * 0.3, 0.0]),
        }))
        .unwrap();
    }
    log
}

fn bench(c: &mut Criterion) {
    let seq = labelled_sequence(&SequenceSettings {
        segments: 20,
        ..Default::default()
    });
    let mut san = Sanitizer::default();
    let frames: Vec<_> = seq.iter().filter_map(|f| san.accept(&f.frame)).collect();
    c.bench_function("gesture_classify_frame", |b| {
        let mut clf = GestureClassifier::default();
        let mut i = 0;
        b.iter(|| {
            let f = &frames[i % frames.len()];
            i += 1;
            clf.update(f.time, f.hand(Hand::Right), f.head.as_ref())
        })
    });
    let log = scene(16);
    let tris: usize = log
        .document()
        .objects()
        .map(|(_, o)| o.mesh.triangles.len())
        .sum();
    println!("pick scene: 16 spheres, {tris} triangles");
    let ray = Ray {
        origin: DVec3::new(0.9, 0.9, 2.0),
        dir: DVec3::new(0.0, 0.0, -1.0),
    };
    c.bench_function("pick_16_spheres", |b| {
        b.iter(|| pick(log.document(), &ray, 10.0))
    });
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/primitives_session.trace.jsonl"
    ))
    .unwrap();
    let trace = Trace::from_jsonl(&text).unwrap();
    c.bench_function("replay_primitives_session_876_frames", |b| {
        b.iter(|| replay(&trace).unwrap().commands.len())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
