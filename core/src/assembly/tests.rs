//! Unit tests of the assembly module's geometry helpers (op-level tests
//! are in core/tests/suite/gc_assembly.rs).

use glam::DVec3;

use super::{mirror_gc, reflect, transform_gc};
use crate::gc::{mesh_gc, Profile, Resolution, ShapeType};
use crate::gc::{GcCreate, SectionSpec};

/// A solid GC on a bent spine in the y = 0 plane with the given sections.
fn bent(sections: Vec<SectionSpec>) -> crate::gc::Gc {
    GcCreate {
        spine: vec![
            DVec3::ZERO,
            DVec3::new(0.2, 0.0, 0.5),
            DVec3::new(0.1, 0.0, 1.0),
        ],
        plane_normal: DVec3::Y,
        sections,
        shape: ShapeType::Solid,
        resolution: Resolution::PREVIEW,
    }
    .build()
    .expect("gc")
}

fn section(profile: Profile, v: f64, twist: f64) -> SectionSpec {
    SectionSpec {
        profile,
        v,
        scale: 1.0,
        twist,
    }
}

fn sample() -> crate::gc::Gc {
    bent(vec![
        section(Profile::Ellipse { rx: 0.2, ry: 0.1 }, 0.0, 0.0),
        section(Profile::Circle { radius: 0.15 }, 1.0, 0.3),
    ])
}

#[test]
fn mirrored_gc_is_the_mirror_image() {
    let gc = sample();
    let (o, n) = (DVec3::new(0.3, 0.0, 0.0), DVec3::X);
    let m = mirror_gc(&gc, o, n);
    let off = mirror_mismatch(&gc, &m, o, n);
    assert!(off < 1e-9, "mirrored surface off by {off}");
    let (a, b) = (mesh_gc(&gc).expect("mesh"), mesh_gc(&m).expect("mesh"));
    let (va, vb) = (a.signed_volume(), b.signed_volume());
    eprintln!("volume drift {}", (va - vb).abs() / va.abs());
    // Quads split along their shorter diagonal, so the mirrored or moved
    // mesh is the same piecewise-linear surface: volumes agree to rounding.
    assert!((va - vb).abs() <= 1e-9 * va.abs(), "{va} vs {vb}");
    // placed sections: every mirrored section point lies on the twin's curve
    let (ca, _) = gc.placed_sections().expect("placed");
    let (cb, _) = m.placed_sections().expect("placed");
    for (x, y) in ca.iter().zip(&cb) {
        let py = y.polyline(400);
        for p in x.polyline(50) {
            let q = reflect(p, o, n);
            let d = py
                .iter()
                .map(|r| r.distance(q))
                .fold(f64::INFINITY, f64::min);
            assert!(d < 2e-3, "mirrored section point off by {d}");
        }
    }
}

#[test]
fn rigid_transform_keeps_volume() {
    let gc = sample();
    let r = glam::DAffine3::from_rotation_translation(
        glam::DQuat::from_rotation_x(0.7),
        DVec3::new(1.0, 2.0, 3.0),
    );
    let t = transform_gc(&gc, &r);
    let (a, b) = (mesh_gc(&gc).expect("mesh"), mesh_gc(&t).expect("mesh"));
    let (va, vb) = (a.signed_volume(), b.signed_volume());
    eprintln!("volume drift {}", (va - vb).abs() / va.abs());
    // Quads split along their shorter diagonal, so the mirrored or moved
    // mesh is the same piecewise-linear surface: volumes agree to rounding.
    assert!((va - vb).abs() <= 1e-9 * va.abs(), "{va} vs {vb}");
}

/// The mirror of a GC whose sections are sketched loops and free curves
/// (not symmetric in `y`) is the mirror image of its surface, between the
/// key sections too: the loft's correspondence (each loop's start point)
/// must survive the flip.
#[test]
fn mirrored_sketched_sections_give_the_mirror_surface() {
    let loop_pts = vec![
        [0.2, 0.0],
        [0.1, 0.15],
        [-0.12, 0.1],
        [-0.18, -0.05],
        [0.02, -0.16],
    ];
    let curve = Profile::Polygon {
        sides: 5,
        radius: 0.2,
    }
    .curve()
    .expect("curve");
    let gc = bent(vec![
        section(Profile::Points { points: loop_pts }, 0.0, 0.0),
        section(Profile::Curve { curve }, 1.0, 0.4),
    ]);
    let (o, n) = (DVec3::new(0.3, 0.0, 0.0), DVec3::X);
    let m = mirror_gc(&gc, o, n);
    let worst = mirror_mismatch(&gc, &m, o, n);
    assert!(worst < 1e-9, "mirrored surface off by {worst}");
}

/// How far the worst vertex of `m`'s mesh is from the reflection of
/// `gc`'s mesh vertices.
fn mirror_mismatch(gc: &crate::gc::Gc, m: &crate::gc::Gc, o: DVec3, n: DVec3) -> f64 {
    let (a, b) = (mesh_gc(gc).expect("mesh"), mesh_gc(m).expect("mesh"));
    let reflected: Vec<DVec3> = a
        .positions
        .iter()
        .map(|p| reflect(DVec3::from_array(*p), o, n))
        .collect();
    b.positions
        .iter()
        .map(|p| {
            let q = DVec3::from_array(*p);
            reflected
                .iter()
                .map(|r| r.distance(q))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Regression (found by `gc_structure_props`): a handle re-placed by a
/// rotation of a few 1e-9 rad. glam's `from_rotation_arc` returns the
/// identity below ~3e-8 rad, which left the handle's end 4.5e-10 m off its
/// anchor; `similarity_about` must take `from` exactly onto `to`.
#[test]
fn tiny_rotations_still_take_the_handle_end_onto_its_anchor() {
    use glam::{DQuat, DVec3};
    let pivot = DVec3::new(0.01, -0.02, 0.03);
    let from = DVec3::new(0.06, 0.0, -0.04);
    for angle in [1e-12, 3e-9, 2e-8, 1e-4, 1.0, 3.0] {
        let to = DQuat::from_rotation_y(angle) * from * 1.0000001;
        let m = super::propagate::similarity_about(pivot, from, to);
        let got = m.transform_point3(pivot + from);
        assert!(
            (got - (pivot + to)).length() < 1e-15,
            "angle {angle}: {:e} off",
            (got - (pivot + to)).length()
        );
    }
}
