//! Times the stages of one GC edit (loft, meshing, validation) at VR
//! preview resolution for K = 8: `cargo run --release --example gc_timing`.

use std::time::Instant;

use glam::DVec3;
use shapewright::gc::{fit_spine, mesh_gc, Gc, KeySection, Profile, Resolution, ShapeType};
use shapewright::mesh::validate;

fn main() {
    let spine = fit_spine(
        &[
            DVec3::ZERO,
            DVec3::new(0.05, 0.0, 0.4),
            DVec3::new(-0.05, 0.0, 0.8),
            DVec3::new(0.0, 0.0, 1.2),
        ],
        DVec3::Y,
    )
    .expect("spine");
    let profiles = [
        Profile::Circle { radius: 0.25 },
        Profile::Circle { radius: 0.35 },
        Profile::Polygon {
            sides: 6,
            radius: 0.42,
        },
        Profile::Ellipse { rx: 0.4, ry: 0.33 },
        Profile::Circle { radius: 0.3 },
        Profile::Circle { radius: 0.2 },
        Profile::Rectangle {
            width: 0.3,
            height: 0.26,
        },
        Profile::Circle { radius: 0.22 },
    ];
    let sections = profiles
        .into_iter()
        .enumerate()
        .map(|(i, p)| KeySection::new(p, i as f64 / 7.0))
        .collect();
    let gc = Gc::new(spine, sections, ShapeType::Solid, Resolution::PREVIEW).expect("gc");
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
