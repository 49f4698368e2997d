//! GC edit benchmark (issue 3): one edit = re-interpolate the spine, re-frame
//! by RMF, re-loft K = 8 sections and mesh at VR preview resolution.
//!
//! GC commit benchmark (issue 21, "Unions"): one op through the log, the
//! document's mesh included, with the object's union cache warm as in a
//! session: the chair's last `gc_copy` (8 parts cached, one added) and a
//! resize of the teapot's handle (body and spout cached); beside them the
//! chair's full union from nothing, what every commit cost before.

#![allow(missing_docs)] // criterion_main! generates an undocumented `main`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
#[path = "fixtures/vase.rs"]
mod vase;

use glam::DVec3;
use shapewright::assembly::{union_mesh, GcEditPart, PartEdit};
use shapewright::doc::{parse_script, run_script, Edit, ObjectId, ObjectKind, Op, OpLog};
use shapewright::gc::{mesh_gc, PartId, SectionIndex, ShapeType};
use vase::vase_k8;

fn bench(c: &mut Criterion) {
    for (name, shape) in [
        ("solid", ShapeType::Solid),
        ("shell", ShapeType::Shell { thickness: 0.02 }),
    ] {
        let gc = vase_k8(shape);
        let key = gc.key_points()[4];
        c.bench_function(&format!("gc_bend_reloft_mesh_k8_preview_{name}"), |b| {
            let mut i = 0u32;
            b.iter(|| {
                let mut g = gc.clone();
                i = i.wrapping_add(1);
                let dx = 0.05 + 0.01 * (i % 7) as f64;
                g.bend(4, key + DVec3::new(dx, 0.0, 0.0)).unwrap();
                black_box(mesh_gc(&g).unwrap())
            })
        });
    }
    let gc = vase_k8(ShapeType::Solid);
    c.bench_function("gc_loft_only_k8", |b| {
        b.iter(|| black_box(gc.surface().unwrap()))
    });
}

fn script(name: &str) -> String {
    let path = format!("{}/../tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("script")
}

fn run(text: &str) -> OpLog {
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(text).expect("parses")).expect("runs");
    log
}

fn commit(c: &mut Criterion) {
    let chair = script("chair.jsonl");
    let lines: Vec<&str> = chair.lines().filter(|l| !l.trim().is_empty()).collect();
    let (head, last) = lines.split_at(lines.len() - 1);
    let log = run(&head.join("\n"));
    let last: Op = serde_json::from_str(last[0]).expect("op");
    let mut g = c.benchmark_group("gc_commit");
    g.sample_size(20);
    g.bench_function("chair_add_last_part", |b| {
        b.iter(|| {
            let mut l = log.clone();
            black_box(l.apply(last.clone()).expect("apply"))
        })
    });
    let teapot = run(&script("teapot.jsonl"));
    let mut i = 0u32;
    g.bench_function("teapot_resize_handle", |b| {
        b.iter(|| {
            let mut l = teapot.clone();
            i = i.wrapping_add(1);
            let op = Op::GcEditPart(Edit::new(
                ObjectId(1),
                GcEditPart {
                    part: PartId(2),
                    edit: PartEdit::Resize {
                        section: SectionIndex(0),
                        factor: 1.0 + 1e-4 * (i % 1000) as f64,
                    },
                },
            ));
            black_box(l.apply(op).expect("apply"))
        })
    });
    let full = run(&chair);
    let ObjectKind::GcAssembly(asm) = &full.document().get(ObjectId(1)).expect("chair").kind else {
        panic!("the chair is not an assembly")
    };
    g.bench_function("chair_full_union_uncached", |b| {
        b.iter(|| black_box(union_mesh(asm).expect("union")))
    });
    g.finish();
}

criterion_group!(benches, bench, commit);
criterion_main!(benches);
