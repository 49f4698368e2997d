//! The stitching of the bricks' pieces into one mesh ([`assemble`]):
//! every vertex numbered once by the piece that owns it, shared vertices
//! found by their slot in the owner, feature edges flipped across
//! pieces, orphan vertices added. Extraction brick by brick is
//! [`super::extract`].

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;

use super::extract::{Piece, SHARED_ID};
use super::grid::BrickKey;
use super::mc::BuildKeyHasher;
use crate::math::DVec3;
use crate::mesh::TriMesh;

/// Stitches pieces (in key order) into one indexed mesh with normals:
/// each vertex is numbered once, by the piece that owns it (pieces in key
/// order, owned vertices in slot order); a piece finds each vertex it
/// shares with a +x/+y/+z neighbour by binary search of its slot in that
/// neighbour's owned slots. Every piece writes its own ranges of the
/// output in parallel, so the result does not depend on threads.
pub fn assemble(pieces: &BTreeMap<BrickKey, Arc<Piece>>) -> TriMesh {
    let list: Vec<(BrickKey, &Piece)> = pieces.iter().map(|(k, p)| (*k, p.as_ref())).collect();
    let mut offsets = Vec::with_capacity(list.len());
    let (mut nv, mut nt) = (0usize, 0usize);
    for (_, p) in &list {
        offsets.push((nv as u32, nt));
        nv += p.slots.len();
        nt += p.triangles.len();
    }
    let mut positions = zeroed(nv, [0.0f64; 3]);
    let mut normals = zeroed(nv, [0.0f64; 3]);
    let mut triangles = zeroed(nt, [0u32; 3]);
    // Each piece's output ranges, split off in order.
    let mut jobs = Vec::with_capacity(list.len());
    {
        let (mut pr, mut nr, mut tr) = (&mut positions[..], &mut normals[..], &mut triangles[..]);
        for (_, p) in &list {
            let (a, b) = std::mem::take(&mut pr).split_at_mut(p.slots.len());
            let (c, d) = std::mem::take(&mut nr).split_at_mut(p.slots.len());
            let (e, f) = std::mem::take(&mut tr).split_at_mut(p.triangles.len());
            jobs.push((a, c, e));
            (pr, nr, tr) = (b, d, f);
        }
    }
    // A shared vertex not found in its owner (a piece set that is not
    // closed under the extraction rule) is marked and numbered below.
    let missing = std::sync::atomic::AtomicBool::new(false);
    jobs.into_par_iter()
        .enumerate()
        .with_min_len(8)
        .for_each(|(o, (pos, nor, tri))| {
            let (brick, p) = list[o];
            let owned = p.slots.len();
            pos.copy_from_slice(&p.positions[..owned]);
            nor.copy_from_slice(&p.normals);
            let owners: [Option<usize>; 8] = std::array::from_fn(|bits| {
                let k = [0, 1, 2].map(|a| brick[a] + (bits >> a & 1) as i32);
                list.binary_search_by(|(key, _)| key.cmp(&k)).ok()
            });
            let base = offsets[o].0;
            let remap: Vec<u32> = p
                .shared
                .iter()
                .map(|&(bits, slot)| {
                    owners[bits as usize]
                        .and_then(|w| {
                            let q = list[w].1;
                            q.slots
                                .binary_search(&slot)
                                .ok()
                                .map(|j| offsets[w].0 + j as u32)
                        })
                        .unwrap_or_else(|| {
                            missing.store(true, std::sync::atomic::Ordering::Relaxed);
                            u32::MAX
                        })
                })
                .collect();
            for (out, t) in tri.iter_mut().zip(&p.triangles) {
                *out = t.map(|i| {
                    if i & SHARED_ID == 0 {
                        base + i
                    } else {
                        remap[(i & !SHARED_ID) as usize]
                    }
                });
            }
        });
    if missing.into_inner() {
        add_orphans(
            &list,
            &offsets,
            &mut positions,
            &mut normals,
            &mut triangles,
        );
    }
    flip_feature_edges(&list, &offsets, &mut positions, &mut triangles);
    let mut mesh = TriMesh::new(positions, triangles);
    mesh.normals = normals;
    mesh
}

/// `n` copies of `z`, written on all threads (on small grids, zeroing the
/// mesh arrays on one thread cost a tenth of the extraction on two).
fn zeroed<T: Clone + Send>(n: usize, z: T) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.par_extend(rayon::iter::repeat_n(z, n));
    v
}

/// Joins the fan vertices of neighbouring feature cells (Kobbelt et al.'s
/// edge flip): where a feature fan's triangle `(f, a, b)` meets another
/// fan's `(g, b, a)` across the crossing edge `a b`, the pair becomes
/// `(f, a, g)`, `(f, g, b)`, so that the sharp edge runs through the fan
/// vertices instead of zigzagging through the crossings between them.
/// Each pair of fan vertices is joined once (a second flip would repeat
/// the edge), and only where the pair stays unfolded; a fan vertex joined
/// to none goes back to its rim's centroid. In piece and triangle order:
/// the same on any thread count.
fn flip_feature_edges(
    list: &[(BrickKey, &Piece)],
    offsets: &[(u32, usize)],
    positions: &mut [[f64; 3]],
    triangles: &mut [[u32; 3]],
) {
    let fans: Vec<usize> = list
        .iter()
        .zip(offsets)
        .flat_map(|((_, p), (_, t0))| p.feature_triangles.iter().map(move |&t| t0 + t as usize))
        .collect();
    if fans.is_empty() {
        return;
    }
    // The crossing edge of each fan triangle, directed as the triangle
    // runs it.
    // Keyed by u64 through the fixed multiply-rotate hasher (only looked
    // up, never iterated: the hasher does not change the result).
    type Set = std::collections::HashSet<u64, BuildKeyHasher>;
    let pair = |a: u32, b: u32| (a as u64) << 32 | b as u64;
    let by_edge: std::collections::HashMap<u64, usize, BuildKeyHasher> = fans
        .iter()
        .map(|&t| {
            let [_, a, b] = triangles[t];
            (pair(a, b), t)
        })
        .collect();
    let mut joined: Vec<(u32, u32)> = Vec::new();
    let mut joined_set = Set::default();
    let mut flipped = Set::default();
    for &t in &fans {
        if flipped.contains(&(t as u64)) {
            continue;
        }
        let [f, a, b] = triangles[t];
        let Some(&u) = by_edge.get(&pair(b, a)) else {
            continue;
        };
        let [g, b2, a2] = triangles[u];
        if flipped.contains(&(u as u64)) || g == f || (b2, a2) != (b, a) {
            continue;
        }
        // The quad f a g b must stay unfolded: both new triangles face
        // the way the old pair did.
        let p = |i: u32| DVec3::from_array(positions[i as usize]);
        let normal = |t: [u32; 3]| (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        let before = normal([f, a, b]) + normal([g, b, a]);
        if normal([f, a, g]).dot(before) <= 0.0 || normal([f, g, b]).dot(before) <= 0.0 {
            continue;
        }
        if !joined_set.insert(pair(f.min(g), f.max(g))) {
            continue;
        }
        joined.push((f, g));
        triangles[t] = [f, a, g];
        triangles[u] = [f, g, b];
        flipped.insert(t as u64);
        flipped.insert(u as u64);
    }
    // A fan vertex joined to no other stands alone on its crease (its
    // neighbours along it found no feature): a spike between chamfers.
    // It goes back to its rim's centroid, the plain fan.
    let joined_vertices: Set = joined
        .iter()
        .flat_map(|&(f, g)| [f as u64, g as u64])
        .collect();
    let mut rims: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for &t in &fans {
        let [f, a, b] = triangles[t];
        if !joined_vertices.contains(&(f as u64)) {
            let rim = rims.entry(f).or_default();
            rim.push(a);
            rim.push(b);
        }
    }
    for (f, mut rim) in rims {
        rim.sort_unstable();
        rim.dedup();
        let c = rim.iter().fold(DVec3::ZERO, |acc, &i| {
            acc + DVec3::from_array(positions[i as usize])
        }) / rim.len() as f64;
        positions[f as usize] = c.to_array();
    }
}

/// Numbers the shared vertices whose owner piece is missing (in piece and
/// triangle order, so still independent of threads).
fn add_orphans(
    list: &[(BrickKey, &Piece)],
    offsets: &[(u32, usize)],
    positions: &mut Vec<[f64; 3]>,
    normals: &mut Vec<[f64; 3]>,
    triangles: &mut [[u32; 3]],
) {
    let mut orphans: std::collections::HashMap<(BrickKey, u32), u32> = Default::default();
    for (o, (brick, p)) in list.iter().enumerate() {
        let owned = p.slots.len();
        let t0 = offsets[o].1;
        for (k, t) in p.triangles.iter().enumerate() {
            for (c, &i) in t.iter().enumerate() {
                if triangles[t0 + k][c] != u32::MAX {
                    continue;
                }
                let k = (i & !SHARED_ID) as usize;
                let (bits, slot) = p.shared[k];
                let owner = [0, 1, 2].map(|a| brick[a] + (bits >> a & 1) as i32);
                let n = positions.len() as u32;
                let id = *orphans.entry((owner, slot)).or_insert(n);
                if id == n {
                    positions.push(p.positions[owned + k]);
                    normals.push([0.0, 0.0, 1.0]);
                }
                triangles[t0 + k][c] = id;
            }
        }
    }
}
