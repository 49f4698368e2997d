//! GC edit benchmark (issue 3): one edit = re-interpolate the spine, re-frame
//! by RMF, re-loft K = 8 sections and mesh at VR preview resolution.

#![allow(missing_docs)] // criterion_main! generates an undocumented `main`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
#[path = "fixtures/vase.rs"]
mod vase;

use glam::DVec3;
use shapewright::gc::{mesh_gc, ShapeType};
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

criterion_group!(benches, bench);
criterion_main!(benches);
