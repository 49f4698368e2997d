use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::sdf::cache::{self, SdfCache, SdfStore};
use crate::sdf::library::starter_mesh;
use crate::sdf::mesh_sdf::{component_sdf, mesh_to_sdf, MeshDistance};
use crate::solid::{tessellate, SolidShape};

fn unit_cube() -> TriMesh {
    tessellate(&SolidShape::Box { size: [1.0; 3] }, 16).unwrap()
}

#[test]
fn cube_sign_is_right_on_and_near_faces_edges_vertices() {
    let sdf = mesh_to_sdf(&unit_cube(), 0.05, 0.1).unwrap();
    // Grid samples lie exactly on the cube's faces, edges and corners
    // (origin -0.6, step 0.05): their values must be 0 (up to f32) and
    // every other sample must have the exact box distance and sign.
    let mut on = 0;
    for k in 0..sdf.dims[2] {
        for j in 0..sdf.dims[1] {
            for i in 0..sdf.dims[0] {
                let p = DVec3::from_array(sdf.origin)
                    + DVec3::new(i as f64, j as f64, k as f64) * sdf.step;
                let q = p.abs() - DVec3::splat(0.5);
                let exact = q.max(DVec3::ZERO).length() + q.max_element().min(0.0);
                let v = sdf.values[i + sdf.dims[0] * (j + sdf.dims[1] * k)] as f64;
                assert!((v - exact).abs() < 1e-5, "at {p}: {v} vs {exact}");
                if exact.abs() < 1e-9 {
                    on += 1;
                }
            }
        }
    }
    assert!(on > 100);
    // Points just off faces, edges and vertices, both sides.
    let q = MeshDistance::new(&unit_cube(), DVec3::ZERO).unwrap();
    for (p, n) in [
        (DVec3::new(0.5, 0.1, 0.2), DVec3::X),
        (
            DVec3::new(0.5, 0.5, 0.1),
            DVec3::new(1.0, 1.0, 0.0).normalize(),
        ),
        (DVec3::new(0.5, 0.5, 0.5), DVec3::ONE.normalize()),
        (
            DVec3::new(0.5, 0.5, 0.5),
            DVec3::new(1.0, 0.2, 0.1).normalize(),
        ),
        (
            DVec3::new(-0.5, 0.5, -0.5),
            DVec3::new(-1.0, 0.3, -0.2).normalize(),
        ),
    ] {
        let out = q.signed_distance(p + n * 1e-3);
        let inn = q.signed_distance(p - n * 1e-3);
        assert!(out > 0.0 && inn < 0.0, "{p}: out {out} in {inn}");
    }
}

#[test]
fn normalized_component_matches_section_5_2() {
    let s = component_sdf(&starter_mesh("chair_leg").unwrap()).unwrap();
    let (lo, hi) = s.bounds();
    // Longest side 0.4 plus 0.1 padding each side (rounded up to the step).
    assert!(((hi - lo).max_element() - 0.6).abs() < 0.011, "{lo} {hi}");
    assert_eq!(s.step, 0.01);
    assert!(s.sample(DVec3::ZERO).unwrap() < 0.0);
    let g = s.gradient(DVec3::new(0.0, 0.0, 0.25)).unwrap();
    assert!(g.z > 0.9, "{g}");
}

#[derive(Default)]
struct MemStore(Mutex<HashMap<String, Vec<u8>>>);

impl SdfStore for MemStore {
    fn load(&self, key: &str) -> Option<Vec<u8>> {
        self.0.lock().unwrap().get(key).cloned()
    }
    fn store(&self, key: &str, bytes: &[u8]) {
        self.0.lock().unwrap().insert(key.into(), bytes.to_vec());
    }
}

#[test]
fn cache_blobs_roundtrip_and_reject_corruption() {
    let s = component_sdf(&starter_mesh("cone").unwrap()).unwrap();
    let b = cache::encode(42, &s);
    assert_eq!(cache::decode(42, &b).as_ref(), Some(&s));
    assert!(cache::decode(43, &b).is_none(), "wrong key");
    for i in [0, 9, 20, b.len() / 2, b.len() - 1] {
        let mut c = b.clone();
        c[i] ^= 0x10;
        assert!(cache::decode(42, &c).is_none(), "flipped byte {i}");
    }
    assert!(cache::decode(42, &b[..b.len() - 4]).is_none());
    assert!(cache::decode(42, &[]).is_none());
    // A cache with a store: written on a miss, read back by a second
    // cache on the same store, and a corrupt entry is regenerated.
    let store = Arc::new(MemStore::default());
    let mesh = starter_mesh("cone").unwrap();
    let a = SdfCache::with_store(store.clone());
    assert_eq!(*a.component_sdf(&mesh).unwrap(), s);
    let name = cache::key_name(cache::mesh_key(&mesh));
    assert!(
        store.0.lock().unwrap().contains_key(&name),
        "written on a miss"
    );
    let b = SdfCache::with_store(store.clone());
    assert!(!b.same(&a) && b.is_empty());
    assert_eq!(b.load(cache::mesh_key(&mesh)).as_ref(), Some(&s));
    store.0.lock().unwrap().get_mut(&name).unwrap()[30] ^= 1;
    assert!(
        b.load(cache::mesh_key(&mesh)).is_none(),
        "corrupt blob is a miss"
    );
    assert_eq!(*b.component_sdf(&mesh).unwrap(), s, "recomputed");
    assert_eq!(
        b.load(cache::mesh_key(&mesh)).as_ref(),
        Some(&s),
        "and rewritten"
    );
    // A cache without a store never sees another's entries.
    assert!(SdfCache::new().load(cache::mesh_key(&mesh)).is_none());
}
