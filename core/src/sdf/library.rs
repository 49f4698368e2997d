//! The starter component library (paper 2 §3: primitives, chair parts, cup
//! and handle parts, organic shapes), made by the project itself as code.
//!
//! Every entry is a closed mesh built here: primitives and parts are
//! [`SolidShape`]s with the part's proportions, tessellated; organic shapes
//! are smooth unions of analytic solids meshed by our own marching cubes.
//! The mesh is turned into a normalized discrete SDF by
//! [`component_sdf`] (§5.2) the first time it is used, then kept in a
//! process-wide memory cache and, when the host installed one, in an
//! on-disk [`super::cache::SdfStore`]. The values only depend on the code,
//! so a replay computes the same bits whether or not a cache hit.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use super::analytic::solid_distance;
use super::cache;
use super::dense::DenseSdf;
use super::mc::extract_dense;
use super::mesh_sdf::component_sdf;
use super::SdfError;
use crate::hash::ContentHasher;
use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::solid::{tessellate, SolidShape};

/// Names of the starter components.
pub const STARTER_NAMES: &[&str] = &[
    // primitives
    "box",
    "sphere",
    "cylinder",
    "cone",
    "torus",
    "capsule",
    "ellipsoid",
    // chair parts
    "chair_seat",
    "chair_back",
    "chair_leg",
    "chair_leg_square",
    "chair_armrest",
    "chair_crossbar",
    // cup and handle parts
    "cup_body",
    "cup_hollow",
    "cup_handle",
    "cup_saucer",
    "cup_rim",
    // organic
    "blob",
    "bean",
    "mushroom",
    "snowman",
];

fn solid(shape: SolidShape) -> TriMesh {
    tessellate(&shape, 48).expect("library shapes are valid")
}

/// A smooth union (polynomial smooth-min, radius `k`) of placed solids,
/// meshed by marching cubes at `step`.
fn organic(parts: &[(SolidShape, [f64; 3])], k: f64, step: f64) -> TriMesh {
    let f = |p: DVec3| {
        let mut d = f64::INFINITY;
        for (s, c) in parts {
            let e = solid_distance(s, p - DVec3::from_array(*c));
            d = if d.is_infinite() {
                e
            } else {
                let h = (0.5 + 0.5 * (e - d) / k).clamp(0.0, 1.0);
                e + (d - e) * h - k * h * (1.0 - h)
            };
        }
        d
    };
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for (s, c) in parts {
        let h = DVec3::from_array(s.half_extents());
        lo = lo.min(DVec3::from_array(*c) - h);
        hi = hi.max(DVec3::from_array(*c) + h);
    }
    lo -= DVec3::splat(2.0 * step + k);
    hi += DVec3::splat(2.0 * step + k);
    let n = ((hi - lo) / step).ceil();
    let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
    let mut v = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                v.push(f(lo + DVec3::new(x as f64, y as f64, z as f64) * step) as f32);
            }
        }
    }
    let (p, t) = extract_dense(&v, dims, lo.to_array(), step);
    TriMesh::new(p, t)
}

/// The closed mesh of starter component `name` (before normalization).
pub fn starter_mesh(name: &str) -> Result<TriMesh, SdfError> {
    use SolidShape::*;
    let m = match name {
        "box" => solid(Box { size: [1.0; 3] }),
        "sphere" => solid(Sphere { radius: 1.0 }),
        "cylinder" => solid(Cylinder {
            radius: 0.5,
            height: 1.0,
        }),
        "cone" => solid(Cone {
            radius: 0.5,
            height: 1.0,
        }),
        "torus" => solid(Torus {
            major_radius: 0.35,
            minor_radius: 0.15,
        }),
        "capsule" => solid(Capsule {
            radius: 0.25,
            length: 0.5,
        }),
        "ellipsoid" => solid(Ellipsoid {
            radii: [0.5, 0.35, 0.25],
        }),
        "chair_seat" => solid(Box {
            size: [0.45, 0.45, 0.05],
        }),
        "chair_back" => solid(Box {
            size: [0.45, 0.05, 0.5],
        }),
        "chair_leg" => solid(Cylinder {
            radius: 0.025,
            height: 0.45,
        }),
        "chair_leg_square" => solid(Box {
            size: [0.045, 0.045, 0.45],
        }),
        "chair_armrest" => solid(Capsule {
            radius: 0.03,
            length: 0.4,
        }),
        "chair_crossbar" => solid(Cylinder {
            radius: 0.015,
            height: 0.4,
        }),
        "cup_body" => solid(Cylinder {
            radius: 0.2,
            height: 0.4,
        }),
        "cup_hollow" => solid(Cylinder {
            radius: 0.18,
            height: 0.4,
        }),
        "cup_handle" => solid(Torus {
            major_radius: 0.15,
            minor_radius: 0.03,
        }),
        "cup_saucer" => solid(Ellipsoid {
            radii: [0.35, 0.35, 0.04],
        }),
        "cup_rim" => solid(Torus {
            major_radius: 0.2,
            minor_radius: 0.015,
        }),
        "blob" => organic(
            &[
                (Sphere { radius: 0.3 }, [0.0, 0.0, 0.0]),
                (Sphere { radius: 0.22 }, [0.32, 0.1, 0.05]),
                (Sphere { radius: 0.18 }, [-0.2, 0.25, 0.15]),
            ],
            0.12,
            0.02,
        ),
        "bean" => organic(
            &[
                (Sphere { radius: 0.25 }, [-0.2, 0.0, 0.0]),
                (Sphere { radius: 0.25 }, [0.2, 0.08, 0.0]),
            ],
            0.2,
            0.02,
        ),
        "mushroom" => organic(
            &[
                (
                    Capsule {
                        radius: 0.08,
                        length: 0.3,
                    },
                    [0.0, 0.0, -0.1],
                ),
                (
                    Ellipsoid {
                        radii: [0.3, 0.3, 0.14],
                    },
                    [0.0, 0.0, 0.12],
                ),
            ],
            0.05,
            0.015,
        ),
        "snowman" => organic(
            &[
                (Sphere { radius: 0.25 }, [0.0, 0.0, -0.3]),
                (Sphere { radius: 0.19 }, [0.0, 0.0, 0.08]),
                (Sphere { radius: 0.13 }, [0.0, 0.0, 0.37]),
            ],
            0.06,
            0.02,
        ),
        _ => return Err(SdfError::UnknownComponent(name.to_owned())),
    };
    Ok(m)
}

fn memory() -> &'static Mutex<BTreeMap<u64, Arc<DenseSdf>>> {
    static M: OnceLock<Mutex<BTreeMap<u64, Arc<DenseSdf>>>> = OnceLock::new();
    M.get_or_init(Default::default)
}

/// The cache key of a mesh's component SDF: the format version and the
/// exact bits of the mesh.
pub fn mesh_key(mesh: &TriMesh) -> u64 {
    let mut h = ContentHasher::new();
    h.u64(cache::FORMAT_VERSION as u64);
    h.mesh(mesh);
    h.finish()
}

/// The normalized SDF of `mesh`, from the memory cache, the host's disk
/// store (verified) or computed (and then stored).
pub fn cached_component_sdf(mesh: &TriMesh) -> Result<Arc<DenseSdf>, SdfError> {
    let key = mesh_key(mesh);
    if let Some(s) = memory().lock().ok().and_then(|m| m.get(&key).cloned()) {
        return Ok(s);
    }
    let sdf = match cache::load(key) {
        Some(s) => Arc::new(s),
        None => {
            let s = component_sdf(mesh)?;
            cache::store(key, &s);
            Arc::new(s)
        }
    };
    if let Ok(mut m) = memory().lock() {
        m.insert(key, sdf.clone());
    }
    Ok(sdf)
}

/// The SDF of starter component `name` (memoized by name, so placing a
/// component does not rebuild and hash its mesh).
pub fn starter_sdf(name: &str) -> Result<Arc<DenseSdf>, SdfError> {
    static BY_NAME: OnceLock<Mutex<BTreeMap<String, Arc<DenseSdf>>>> = OnceLock::new();
    let map = BY_NAME.get_or_init(Default::default);
    if let Some(s) = map.lock().ok().and_then(|m| m.get(name).cloned()) {
        return Ok(s);
    }
    let s = cached_component_sdf(&starter_mesh(name)?)?;
    if let Ok(mut m) = map.lock() {
        m.insert(name.to_owned(), s.clone());
    }
    Ok(s)
}
