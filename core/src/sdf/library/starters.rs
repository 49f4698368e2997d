//! The 22 starter components of the first library, unchanged (their
//! meshes, hence their SDFs and every model built from them, are the same
//! bits as before the library grew): primitives, chair parts, cup parts
//! and four organic blends. Their order is [`super::STARTER_NAMES`]'s.

use super::kit::{dist, implicit_at_step, smin, Detail};
use super::{Category, Entry};
use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::solid::{tessellate, SolidShape};

use Category::*;
use SolidShape::*;

fn solid(shape: SolidShape, d: Detail) -> TriMesh {
    tessellate(&shape, d.segments() as u32).expect("library shapes are valid")
}

/// A smooth union (polynomial smooth-min, radius `k`) of placed solids,
/// meshed by marching cubes at `step` (coarser for the preview).
fn organic(parts: &[(SolidShape, [f64; 3])], k: f64, step: f64, d: Detail) -> TriMesh {
    let f = |p: DVec3| {
        let mut acc = f64::INFINITY;
        for (s, c) in parts {
            let e = dist(s, p, *c);
            acc = if acc.is_infinite() {
                e
            } else {
                smin(acc, e, k)
            };
        }
        acc
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
    let step = match d {
        Detail::Full => step,
        Detail::Preview => (hi - lo).max_element() / Detail::Preview.cells(),
    };
    implicit_at_step(f, lo, hi, step)
}

macro_rules! solids {
    ($($name:literal, $cat:ident, $shape:expr;)*) => {
        vec![$(Entry {
            name: $name,
            category: $cat,
            build: |d| solid($shape, d),
        },)*]
    };
}

/// The starter entries, in [`super::STARTER_NAMES`] order.
pub(super) fn entries() -> Vec<Entry> {
    let mut v = solids![
        "box", Primitive, Box { size: [1.0; 3] };
        "sphere", Primitive, Sphere { radius: 1.0 };
        "cylinder", Primitive, Cylinder { radius: 0.5, height: 1.0 };
        "cone", Primitive, Cone { radius: 0.5, height: 1.0 };
        "torus", Primitive, Torus { major_radius: 0.35, minor_radius: 0.15 };
        "capsule", Primitive, Capsule { radius: 0.25, length: 0.5 };
        "ellipsoid", Primitive, Ellipsoid { radii: [0.5, 0.35, 0.25] };
        "chair_seat", Seat, Box { size: [0.45, 0.45, 0.05] };
        "chair_back", Back, Box { size: [0.45, 0.05, 0.5] };
        "chair_leg", Leg, Cylinder { radius: 0.025, height: 0.45 };
        "chair_leg_square", Leg, Box { size: [0.045, 0.045, 0.45] };
        "chair_armrest", Handle, Capsule { radius: 0.03, length: 0.4 };
        "chair_crossbar", Leg, Cylinder { radius: 0.015, height: 0.4 };
        "cup_body", Body, Cylinder { radius: 0.2, height: 0.4 };
        "cup_hollow", Body, Cylinder { radius: 0.18, height: 0.4 };
        "cup_handle", Handle, Torus { major_radius: 0.15, minor_radius: 0.03 };
        "cup_saucer", Base, Ellipsoid { radii: [0.35, 0.35, 0.04] };
        "cup_rim", Body, Torus { major_radius: 0.2, minor_radius: 0.015 };
    ];
    v.extend([
        Entry {
            name: "blob",
            category: Organic,
            build: |d| {
                organic(
                    &[
                        (Sphere { radius: 0.3 }, [0.0, 0.0, 0.0]),
                        (Sphere { radius: 0.22 }, [0.32, 0.1, 0.05]),
                        (Sphere { radius: 0.18 }, [-0.2, 0.25, 0.15]),
                    ],
                    0.12,
                    0.02,
                    d,
                )
            },
        },
        Entry {
            name: "bean",
            category: Organic,
            build: |d| {
                organic(
                    &[
                        (Sphere { radius: 0.25 }, [-0.2, 0.0, 0.0]),
                        (Sphere { radius: 0.25 }, [0.2, 0.08, 0.0]),
                    ],
                    0.2,
                    0.02,
                    d,
                )
            },
        },
        Entry {
            name: "mushroom",
            category: Organic,
            build: |d| {
                organic(
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
                    d,
                )
            },
        },
        Entry {
            name: "snowman",
            category: Organic,
            build: |d| {
                organic(
                    &[
                        (Sphere { radius: 0.25 }, [0.0, 0.0, -0.3]),
                        (Sphere { radius: 0.19 }, [0.0, 0.0, 0.08]),
                        (Sphere { radius: 0.13 }, [0.0, 0.0, 0.37]),
                    ],
                    0.06,
                    0.02,
                    d,
                )
            },
        },
    ]);
    v
}
