use crate::math::fm::DetMath as _;
use proptest::prelude::*;

use crate::mesh::{validate, TriMesh};
use crate::sdf::mc::extract_dense;

fn mesh_of(values: &[f32], dims: [usize; 3], step: f64) -> TriMesh {
    let (p, t) = extract_dense(values, dims, [0.0; 3], step);
    TriMesh::new(p, t)
}

fn field(dims: [usize; 3], f: impl Fn(f64, f64, f64) -> f64) -> Vec<f32> {
    let mut v = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                v.push(f(i as f64, j as f64, k as f64) as f32);
            }
        }
    }
    v
}

fn assert_manifold(m: &TriMesh) {
    let r = validate(m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
}

#[test]
fn sphere_volume_and_genus() {
    let n = 40;
    let h = 0.025;
    let r = 0.35;
    let v = field([n; 3], |x, y, z| {
        let c = 0.5 / h;
        (((x - c).fpowi(2) + (y - c).fpowi(2) + (z - c).fpowi(2)).sqrt() * h) - r
    });
    let m = mesh_of(&v, [n; 3], h);
    let rep = validate(&m, &Default::default());
    assert!(rep.is_closed_manifold(), "{}", rep.problems());
    assert_eq!(rep.genus, Some(0));
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r.fpowi(3);
    assert!(
        (rep.signed_volume - exact).abs() / exact < 0.01,
        "{}",
        rep.signed_volume
    );
}

#[test]
fn torus_is_genus_one() {
    let n = 48;
    let h = 0.02;
    let v = field([n; 3], |x, y, z| {
        let c = 0.48 / h;
        let (x, y, z) = ((x - c) * h, (y - c) * h, (z - c) * h);
        let q = ((x * x + y * y).sqrt() - 0.3).fhypot(z);
        q - 0.1
    });
    let rep = validate(&mesh_of(&v, [n; 3], h), &Default::default());
    assert!(rep.is_closed_manifold(), "{}", rep.problems());
    assert_eq!(rep.genus, Some(1));
}

#[test]
fn exact_zeros_everywhere() {
    // A plane of exact zeros and a box whose faces are exact zeros.
    let n = 12;
    let v = field([n; 3], |x, y, z| {
        let d = (x - 5.0).abs().max((y - 5.0).abs()).max((z - 5.0).abs());
        d - 3.0
    });
    assert_manifold(&mesh_of(&v, [n; 3], 0.1));
}

#[test]
fn all_ambiguous_checkerboard() {
    // Alternating signs: every face ambiguous, thin features everywhere.
    let n = 9;
    let v = field([n; 3], |x, y, z| {
        if (x + y + z) as i64 % 2 == 0 {
            -1.0 - 0.1 * x
        } else {
            1.0 + 0.07 * y
        }
    });
    assert_manifold(&mesh_of(&v, [n; 3], 0.1));
}

fn arb_grid() -> impl Strategy<Value = (Vec<f32>, [usize; 3])> {
    (2usize..7, 2usize..7, 2usize..7).prop_flat_map(|(a, b, c)| {
        let n = a * b * c;
        let val = prop_oneof![
            3 => -1.0f32..1.0,
            2 => Just(0.0f32),
            1 => Just(-0.0f32),
            1 => prop_oneof![Just(1e-30f32), Just(-1e-30f32), Just(f32::MIN_POSITIVE), Just(-1e-7f32)],
            1 => Just(-1.0f32),
        ];
        (proptest::collection::vec(val, n), Just([a, b, c]))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]
    /// Random fields with exact zeros, signed zeros, denormal-scale values
    /// and single-voxel (thin) features always give a closed oriented
    /// 2-manifold (or nothing, when no sample is inside).
    #[test]
    fn random_fields_are_closed_manifolds((v, dims) in arb_grid()) {
        let m = mesh_of(&v, dims, 0.01);
        let any_inside = v.iter().any(|x| *x < 0.0);
        prop_assert_eq!(m.triangles.is_empty(), !any_inside);
        if any_inside {
            let r = validate(&m, &Default::default());
            prop_assert!(r.is_closed_manifold(), "{}", r.problems());
        }
    }
}
