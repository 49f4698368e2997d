//! The component library: every entry a closed oriented 2-manifold with a
//! closed low-poly preview, names unique, categories covering the paper's
//! families, and the normalized SDF's sign agreeing with the mesh.

use crate::math::fm::DetMath as _;
use std::collections::BTreeSet;

use crate::math::DVec3;
use crate::mesh::{validate, TriMesh};
use crate::sdf::library::{catalog, entry, in_category, Category, STARTER_NAMES};
use crate::sdf::mesh_sdf::{normalize_component, MeshDistance, COMPONENT_PADDING};
use crate::sdf::SdfError;

/// Generalized winding number of a closed mesh at `p` (1 inside, 0
/// outside): an inside test independent of the SDF's pseudo-normals.
fn winding(m: &TriMesh, p: DVec3) -> f64 {
    let mut w = 0.0;
    for t in 0..m.triangles.len() {
        let [a, b, c] = m.corners(t).map(|q| q - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        w += 2.0 * num.fatan2(den);
    }
    w / (4.0 * std::f64::consts::PI)
}

#[test]
fn at_least_60_components_in_the_paper_families_with_unique_names() {
    let all = catalog();
    assert!(all.len() >= 60, "{} components", all.len());
    let names: BTreeSet<&str> = all.iter().map(|e| e.name).collect();
    assert_eq!(names.len(), all.len(), "names are unique");
    // The starters keep their names and order.
    for (e, n) in all.iter().zip(STARTER_NAMES) {
        assert_eq!(e.name, *n);
    }
    // Every family the issue names has at least 5 members; every
    // category is one of the fixed list.
    for c in [
        Category::Leg,
        Category::Seat,
        Category::Back,
        Category::Handle,
        Category::Spout,
        Category::Knob,
        Category::Lid,
        Category::Shade,
        Category::Base,
        Category::Wheel,
        Category::Bracket,
    ] {
        assert!(
            in_category(c).count() >= 5,
            "{c:?}: {}",
            in_category(c).count()
        );
    }
    for e in all {
        assert!(Category::ALL.contains(&e.category));
        let json = serde_json::to_string(&e.category).unwrap();
        assert_eq!(json, format!("\"{}\"", e.category.name()));
    }
    assert!(matches!(entry("nope"), Err(SdfError::UnknownComponent(_))));
}

#[test]
fn every_component_and_preview_is_a_closed_oriented_manifold() {
    for e in catalog() {
        let m = e.mesh();
        let r = validate(&m, &Default::default());
        assert!(r.is_closed_manifold(), "{}: {}", e.name, r.problems());
        assert!(r.signed_volume > 0.0, "{}: inside out", e.name);
        let p = e.preview();
        let rp = validate(&p, &Default::default());
        assert!(
            rp.is_closed_manifold(),
            "{} preview: {}",
            e.name,
            rp.problems()
        );
        assert!(rp.signed_volume > 0.0, "{} preview inside out", e.name);
        assert!(
            p.triangle_count() <= 3000,
            "{} preview has {} triangles",
            e.name,
            p.triangle_count()
        );
        // The preview is the same shape: boxes within 15% of the size.
        let ((a0, a1), (b0, b1)) = (m.bbox().unwrap(), p.bbox().unwrap());
        let size = (a1 - a0).max_element();
        assert!(
            (a0 - b0).abs().max_element() < 0.15 * size
                && (a1 - b1).abs().max_element() < 0.15 * size,
            "{}: preview box {b0}..{b1} vs {a0}..{a1}",
            e.name
        );
        assert_eq!(r.genus, rp.genus, "{}: preview genus", e.name);
    }
}

#[test]
fn every_component_sdf_sign_agrees_with_its_mesh() {
    // The component SDF's samples (§5.2: normalized, padding 0.1) at a
    // deterministic spread of its grid points, against the winding number
    // of the normalized mesh; points nearer the surface than 2 mm (where
    // the sign is a matter of rounding) are skipped.
    for e in catalog() {
        let m = normalize_component(&e.mesh()).unwrap();
        let q = MeshDistance::new(&m, DVec3::ZERO).unwrap();
        let (lo, hi) = m.bbox().unwrap();
        let lo = lo - DVec3::splat(COMPONENT_PADDING * 0.5);
        let hi = hi + DVec3::splat(COMPONENT_PADDING * 0.5);
        let n = 7;
        let (mut inside, mut outside) = (0, 0);
        for i in 0..n * n * n {
            let f = DVec3::new(
                (i % n) as f64 + 0.37,
                (i / n % n) as f64 + 0.61,
                (i / (n * n)) as f64 + 0.23,
            ) / n as f64;
            let p = lo + (hi - lo) * f;
            let d = q.signed_distance(p);
            if d.abs() < 0.002 {
                continue;
            }
            let w = winding(&m, p);
            assert!(
                (w > 0.5) == (d < 0.0),
                "{}: at {p} the SDF says {d}, the winding number {w}",
                e.name
            );
            if d < 0.0 {
                inside += 1;
            } else {
                outside += 1;
            }
        }
        assert!(outside > 0, "{}", e.name);
        let _ = inside;
    }
}
