//! Meshing of [`SolidShape`]s. Round shapes are surfaces of revolution of a
//! profile curve around +Z, with single pole vertices where the profile
//! meets the axis, so every mesh is a closed 2-manifold by construction.

use crate::math::fm::DetMath as _;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::{SolidError, SolidShape, MAX_SEGMENTS, MIN_SEGMENTS};
use crate::mesh::TriMesh;

/// Meshes `shape` with `segments` around each circle (and proportionally
/// many along meridians). Normals are computed.
pub fn tessellate(shape: &SolidShape, segments: u32) -> Result<TriMesh, SolidError> {
    shape.validate()?;
    if !(MIN_SEGMENTS..=MAX_SEGMENTS).contains(&segments) {
        return Err(SolidError::Segments(segments));
    }
    let n = segments as usize;
    let quarter = (n / 4).max(2);
    let mut mesh = match *shape {
        SolidShape::Box { size } => box_mesh(size),
        SolidShape::Sphere { radius } => revolve(&sphere_profile(radius, 2 * quarter), n),
        SolidShape::Ellipsoid { radii } => {
            let mut m = revolve(&sphere_profile(1.0, 2 * quarter), n);
            for p in &mut m.positions {
                for k in 0..3 {
                    p[k] *= radii[k];
                }
            }
            m
        }
        SolidShape::Cylinder { radius, height } => {
            let h = height / 2.0;
            revolve(&[(0.0, -h), (radius, -h), (radius, h), (0.0, h)], n)
        }
        SolidShape::Cone { radius, height } => {
            let h = height / 2.0;
            revolve(&[(0.0, -h), (radius, -h), (0.0, h)], n)
        }
        SolidShape::Capsule { radius, length } => {
            let h = length / 2.0;
            let mut profile = vec![(0.0, -h - radius)];
            for i in 1..=quarter {
                let a = -FRAC_PI_2 + FRAC_PI_2 * i as f64 / quarter as f64;
                profile.push((radius * a.fcos(), -h + radius * a.fsin()));
            }
            for i in 0..quarter {
                let a = FRAC_PI_2 * i as f64 / quarter as f64;
                let p = (radius * a.fcos(), h + radius * a.fsin());
                if i > 0 || length > 0.0 {
                    profile.push(p);
                }
            }
            profile.push((0.0, h + radius));
            revolve(&profile, n)
        }
        SolidShape::Torus {
            major_radius,
            minor_radius,
        } => torus(major_radius, minor_radius, n, n),
    };
    mesh.compute_normals();
    Ok(mesh)
}

/// Profile of a sphere from the south pole to the north pole.
fn sphere_profile(r: f64, steps: usize) -> Vec<(f64, f64)> {
    (0..=steps)
        .map(|i| {
            let a = -FRAC_PI_2 + PI * i as f64 / steps as f64;
            if i == 0 {
                (0.0, -r)
            } else if i == steps {
                (0.0, r)
            } else {
                (r * a.fcos(), r * a.fsin())
            }
        })
        .collect()
}

/// Revolves an open profile `(radius, z)` that starts and ends on the axis
/// (radius 0) and has positive radius in between.
fn revolve(profile: &[(f64, f64)], n: usize) -> TriMesh {
    let rings = &profile[1..profile.len() - 1];
    let mut positions = Vec::with_capacity(rings.len() * n + 2);
    positions.push([0.0, 0.0, profile[0].1]);
    for &(r, z) in rings {
        for j in 0..n {
            let a = TAU * j as f64 / n as f64;
            positions.push([r * a.fcos(), r * a.fsin(), z]);
        }
    }
    let top = positions.len() as u32;
    positions.push([0.0, 0.0, profile[profile.len() - 1].1]);
    let ring = |i: usize, j: usize| (1 + i * n + j % n) as u32;
    let mut triangles = Vec::with_capacity(2 * n * rings.len());
    for j in 0..n {
        triangles.push([0, ring(0, j + 1), ring(0, j)]);
    }
    for i in 0..rings.len() - 1 {
        for j in 0..n {
            let (a0, a1, b0, b1) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            triangles.push([a0, a1, b1]);
            triangles.push([a0, b1, b0]);
        }
    }
    let last = rings.len() - 1;
    for j in 0..n {
        triangles.push([top, ring(last, j), ring(last, j + 1)]);
    }
    TriMesh::new(positions, triangles)
}

fn torus(big: f64, small: f64, n: usize, m: usize) -> TriMesh {
    let mut positions = Vec::with_capacity(n * m);
    for j in 0..n {
        let a = TAU * j as f64 / n as f64;
        for i in 0..m {
            let b = TAU * i as f64 / m as f64;
            let r = big + small * b.fcos();
            positions.push([r * a.fcos(), r * a.fsin(), small * b.fsin()]);
        }
    }
    let idx = |j: usize, i: usize| ((j % n) * m + i % m) as u32;
    let mut triangles = Vec::with_capacity(2 * n * m);
    for j in 0..n {
        for i in 0..m {
            let (a0, a1, b0, b1) = (idx(j, i), idx(j + 1, i), idx(j, i + 1), idx(j + 1, i + 1));
            triangles.push([a0, a1, b1]);
            triangles.push([a0, b1, b0]);
        }
    }
    TriMesh::new(positions, triangles)
}

fn box_mesh(size: [f64; 3]) -> TriMesh {
    let [x, y, z] = size.map(|s| s / 2.0);
    let positions = vec![
        [-x, -y, -z],
        [x, -y, -z],
        [x, y, -z],
        [-x, y, -z],
        [-x, -y, z],
        [x, -y, z],
        [x, y, z],
        [-x, y, z],
    ];
    let triangles = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    TriMesh::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::validate;
    use crate::solid::DEFAULT_SEGMENTS;

    fn all_shapes() -> Vec<SolidShape> {
        vec![
            SolidShape::Box {
                size: [1.0, 2.0, 0.5],
            },
            SolidShape::Sphere { radius: 0.7 },
            SolidShape::Ellipsoid {
                radii: [0.3, 0.5, 0.9],
            },
            SolidShape::Cylinder {
                radius: 0.4,
                height: 1.3,
            },
            SolidShape::Cone {
                radius: 0.5,
                height: 0.8,
            },
            SolidShape::Torus {
                major_radius: 1.0,
                minor_radius: 0.25,
            },
            SolidShape::Capsule {
                radius: 0.3,
                length: 1.0,
            },
            SolidShape::Capsule {
                radius: 0.3,
                length: 0.0,
            },
        ]
    }

    #[test]
    fn every_shape_is_closed_with_analytic_volume() {
        for shape in all_shapes() {
            let m = tessellate(&shape, DEFAULT_SEGMENTS).unwrap();
            let r = validate(&m, &Default::default());
            assert!(r.is_closed_manifold(), "{shape:?}: {}", r.problems());
            let want_genus = if matches!(shape, SolidShape::Torus { .. }) {
                1
            } else {
                0
            };
            assert_eq!(r.genus, Some(want_genus), "{shape:?}");
            assert_eq!(r.components, 1);
            let rel = (r.signed_volume - shape.analytic_volume()).abs() / shape.analytic_volume();
            assert!(rel < 0.005, "{shape:?}: volume off by {:.4}%", rel * 100.0);
        }
    }

    #[test]
    fn volume_converges_with_resolution() {
        for shape in all_shapes() {
            let err = |n| {
                let m = tessellate(&shape, n).unwrap();
                (m.signed_volume() - shape.analytic_volume()).abs()
            };
            if !matches!(shape, SolidShape::Box { .. }) {
                assert!(err(128) < err(32) * 0.5, "{shape:?}");
            }
        }
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        assert!(matches!(
            tessellate(&SolidShape::Sphere { radius: 0.0 }, 64),
            Err(SolidError::NonPositive {
                field: "radius",
                ..
            })
        ));
        assert!(matches!(
            tessellate(
                &SolidShape::Box {
                    size: [1.0, -1.0, 1.0]
                },
                64
            ),
            Err(SolidError::NonPositive {
                field: "size[1]",
                ..
            })
        ));
        assert!(matches!(
            tessellate(
                &SolidShape::Cylinder {
                    radius: f64::NAN,
                    height: 1.0
                },
                64
            ),
            Err(SolidError::NonPositive { .. })
        ));
        assert!(matches!(
            tessellate(
                &SolidShape::Torus {
                    major_radius: 1.0,
                    minor_radius: 1.0
                },
                64
            ),
            Err(SolidError::TorusSelfIntersects { .. })
        ));
        assert_eq!(
            tessellate(&SolidShape::Sphere { radius: 1.0 }, 3),
            Err(SolidError::Segments(3))
        );
    }
}
