//! Base meshes to sculpt from: a geodesic sphere, a box and a slab, all
//! closed with near-uniform edges of a requested length, so the first
//! strokes adapt locally instead of bisecting huge triangles.
//!
//! Shared vertices are computed once from canonical (sorted) inputs, so
//! neighbouring faces agree on every bit and no welding is needed.

use super::budget::CreateCost;
use std::collections::HashMap;

use glam::DVec3;

use super::brush::positive;
use super::SculptError;
use crate::mesh::TriMesh;

/// The most vertices a base mesh may have.
pub const MAX_BASE_VERTICES: u64 = 4_000_000;

const ICO_EDGE: f64 = 1.051_462_224_238_267_2; // icosahedron edge / circumradius

/// A geodesic sphere: an icosahedron with each face cut into `n²`
/// triangles, projected onto the sphere. `10n² + 2` vertices.
pub fn geodesic_sphere(radius: f64, n: u32) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let corners: [DVec3; 12] = [
        DVec3::new(-1.0, t, 0.0),
        DVec3::new(1.0, t, 0.0),
        DVec3::new(-1.0, -t, 0.0),
        DVec3::new(1.0, -t, 0.0),
        DVec3::new(0.0, -1.0, t),
        DVec3::new(0.0, 1.0, t),
        DVec3::new(0.0, -1.0, -t),
        DVec3::new(0.0, 1.0, -t),
        DVec3::new(t, 0.0, -1.0),
        DVec3::new(t, 0.0, 1.0),
        DVec3::new(-t, 0.0, -1.0),
        DVec3::new(-t, 0.0, 1.0),
    ];
    let faces: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let n = n.max(1) as usize;
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(10 * n * n + 2);
    let mut edge_ids: HashMap<(usize, usize, usize), u32> = HashMap::new();
    let push = |p: DVec3, positions: &mut Vec<[f64; 3]>| {
        positions.push((p.normalize() * radius).to_array());
        positions.len() as u32 - 1
    };
    let corner_ids: Vec<u32> = corners.iter().map(|&c| push(c, &mut positions)).collect();
    let mut triangles = Vec::with_capacity(20 * n * n);
    for &[a, b, c] in faces.iter() {
        // Index of lattice point (i, j): i steps along a->b, j along a->c.
        let mut ids = vec![0u32; (n + 1) * (n + 1)];
        let idx = |i: usize, j: usize| j * (n + 1) + i;
        let mut edge_point = |u: usize, v: usize, k: usize, positions: &mut Vec<[f64; 3]>| {
            // Point k of n from corner u towards v, canonical by (min, max).
            let (lo, hi, kk) = if u < v { (u, v, k) } else { (v, u, n - k) };
            *edge_ids.entry((lo, hi, kk)).or_insert_with(|| {
                let p = corners[lo] + (corners[hi] - corners[lo]) * (kk as f64 / n as f64);
                positions.push((p.normalize() * radius).to_array());
                positions.len() as u32 - 1
            })
        };
        for j in 0..=n {
            for i in 0..=(n - j) {
                let id = if i == 0 && j == 0 {
                    corner_ids[a]
                } else if i == n {
                    corner_ids[b]
                } else if j == n {
                    corner_ids[c]
                } else if j == 0 {
                    edge_point(a, b, i, &mut positions)
                } else if i == 0 {
                    edge_point(a, c, j, &mut positions)
                } else if i + j == n {
                    edge_point(b, c, j, &mut positions)
                } else {
                    let p = corners[a]
                        + (corners[b] - corners[a]) * (i as f64 / n as f64)
                        + (corners[c] - corners[a]) * (j as f64 / n as f64);
                    positions.push((p.normalize() * radius).to_array());
                    positions.len() as u32 - 1
                };
                ids[idx(i, j)] = id;
            }
        }
        for j in 0..n {
            for i in 0..(n - j) {
                let p00 = ids[idx(i, j)];
                let p10 = ids[idx(i + 1, j)];
                let p01 = ids[idx(i, j + 1)];
                triangles.push([p00, p10, p01]);
                if i + j + 1 < n {
                    let p11 = ids[idx(i + 1, j + 1)];
                    triangles.push([p10, p11, p01]);
                }
            }
        }
    }
    TriMesh::new(positions, triangles)
}

/// The geodesic frequency giving edges of at most about `edge_length`.
pub fn sphere_frequency(radius: f64, edge_length: f64) -> Result<u32, SculptError> {
    positive("base.radius", radius)?;
    positive("base.edge_length", edge_length)?;
    let n = (ICO_EDGE * radius / edge_length).ceil().max(1.0);
    let verts = 10.0 * n * n + 2.0;
    if verts > MAX_BASE_VERTICES as f64 {
        return Err(SculptError::TooLarge {
            vertices: verts.min(u64::MAX as f64) as u64,
            limit: MAX_BASE_VERTICES,
        });
    }
    CreateCost { vertices: verts }.check("base.edge_length")?;
    Ok(n as u32)
}

/// A box of `size` centred on the origin, each face a grid of right
/// triangles with legs of at most `edge_length`.
pub fn grid_box(size: [f64; 3], edge_length: f64) -> Result<TriMesh, SculptError> {
    for s in size {
        positive("base.size", s)?;
    }
    positive("base.edge_length", edge_length)?;
    let nf = size.map(|s| (s / edge_length).ceil().max(1.0));
    let verts = 2.0 * (nf[0] * nf[1] + nf[1] * nf[2] + nf[2] * nf[0]) + 2.0;
    if verts > MAX_BASE_VERTICES as f64 {
        return Err(SculptError::TooLarge {
            vertices: verts as u64,
            limit: MAX_BASE_VERTICES,
        });
    }
    CreateCost { vertices: verts }.check("base.edge_length")?;
    let n = nf.map(|x| x as u32);
    let coord = |axis: usize, i: u32| -size[axis] * 0.5 + size[axis] * (i as f64 / n[axis] as f64);
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut vid = |l: [u32; 3], positions: &mut Vec<[f64; 3]>| {
        *ids.entry(l).or_insert_with(|| {
            positions.push([coord(0, l[0]), coord(1, l[1]), coord(2, l[2])]);
            positions.len() as u32 - 1
        })
    };
    for a in 0..3 {
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0u32, n[a]] {
            for j in 0..n[v] {
                for i in 0..n[u] {
                    let lat = |di: u32, dj: u32| {
                        let mut l = [0u32; 3];
                        l[a] = side;
                        l[u] = i + di;
                        l[v] = j + dj;
                        l
                    };
                    let q = [lat(0, 0), lat(1, 0), lat(1, 1), lat(0, 1)]
                        .map(|l| vid(l, &mut positions));
                    // e_u x e_v = e_a: counter-clockwise on the + side.
                    if side == n[a] {
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    } else {
                        triangles.push([q[0], q[2], q[1]]);
                        triangles.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    Ok(TriMesh::new(positions, triangles))
}
