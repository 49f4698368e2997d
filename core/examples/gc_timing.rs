//! Times the stages of one GC edit (loft, meshing, validation) at VR
//! preview resolution for K = 8: `cargo run --release --example gc_timing`.

use std::time::Instant;

#[path = "../benches/fixtures/vase.rs"]
mod vase;

use shapewright::gc::{mesh_gc, ShapeType};
use shapewright::mesh::validate;
use vase::vase_k8;

fn main() {
    let gc = vase_k8(ShapeType::Solid);
    let n = 200;
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(gc.surface().expect("surface"));
    }
    let loft = t.elapsed().as_secs_f64() / n as f64;
    let t = Instant::now();
    let mut mesh = None;
    for _ in 0..n {
        mesh = Some(mesh_gc(&gc).expect("mesh"));
    }
    let total = t.elapsed().as_secs_f64() / n as f64;
    let mesh = mesh.expect("mesh");
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(validate(&mesh, &Default::default()));
    }
    let val = t.elapsed().as_secs_f64() / n as f64;
    println!(
        "K=8 preview: {} triangles; loft {:.3} ms, mesh_gc total {:.3} ms (of which validate {:.3} ms)",
        mesh.triangle_count(),
        loft * 1e3,
        total * 1e3,
        val * 1e3
    );
}
