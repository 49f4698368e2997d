//! Surface extraction from the sparse grid (paper 2 §5.1, "extract the
//! zero level set"), brick by brick, into pieces; `sdf::assemble`
//! stitches the pieces into one mesh. The cell polygons come from
//! [`super::mc`].
//!
//! - Each brick's cells read a 9³ block (the brick plus one sample layer
//!   of its +x/+y/+z neighbours). The bricks' per-region signs, computed
//!   when a brick is made, say whether a block changes sign at all, so
//!   blocks without surface are never loaded.
//! - Vertices are named by their slot in the brick's vertex table (see
//!   [`Piece`]), owned by exactly one brick, numbered in slot order, so
//!   that a piece depends on its block alone and incremental extraction
//!   equals a full one. Every crossing edge of a 9³ block belongs to a
//!   cell of its brick, so a brick makes its edge vertices up front, in
//!   slot order, from per-row inside bitmasks of the block (which also
//!   give the crossing cells and their corner configurations): no lookup
//!   table is stamped per vertex and nothing is sorted or renumbered.
//! - Normals are the gradient of the field (the trilinear interpolant of a
//!   canonical cell), computed by the owning brick: no pass over the
//!   stitched triangles.
//! - [`SparseGrid::extract_all`] gives every candidate brick its 8
//!   neighbours through a dense index over the bricks' bounding box, in
//!   one parallel pass.
//!
//! Measured against a single-thread "classify every cell" pass over the
//! dense grid by `scripts/bench/sdf.py` (sphere minus torus); the README's
//! performance table has the latest run. `sdf_bench --phase full N` loops
//! this extraction alone for a profiler, `--phase hash all` prints the
//! bits of every bench extraction (to check that a speed-up keeps them).

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;

use super::dense::trilinear_gradient;
use super::features::{feature_apex, ExactField};
use super::grid::{Brick, BrickKey, SparseGrid, BRICK, SIGN_IN, SIGN_OUT};
use super::mc::{polygonize_config, MeshSink, VertKey, MIN_TWICE_AREA_REL};
use crate::math::DVec3;

pub use super::assemble::assemble;

/// The triangles extracted from the cells of one brick, with vertices
/// named by their slot in the brick's vertex table, so that pieces stitch
/// by slot.
///
/// A brick's vertex table numbers the crossing vertex on the grid edge
/// with lower corner `l` (local, `0..=8` per axis) along axis `a` as
/// `(l.x + 9 (l.y + 9 l.z)) 3 + a`, and the centroid vertex of loop `k` of
/// cell `c` (local index) as [`EDGE_SLOTS`]` + 4 c + k`. The brick *owns*
/// its centroids and the edge vertices with `l < 8` on every axis; the
/// others lie on edges starting in a +x/+y/+z neighbour brick, which owns
/// them. The first `slots.len()` vertices are the owned ones, in slot
/// order; the rest are shared, each naming its owner and its slot there.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piece {
    /// Slots of the owned vertices, increasing.
    pub(crate) slots: Vec<u32>,
    /// Positions of all vertices: owned first, then shared.
    pub(crate) positions: Vec<[f64; 3]>,
    /// Unit normals of the owned vertices (the gradient of the field).
    pub(crate) normals: Vec<[f64; 3]>,
    /// Per shared vertex: its owner (bit `a` set: `+1` along axis `a`)
    /// and its slot in the owner's table.
    pub(crate) shared: Vec<(u8, u32)>,
    /// Triangles, counter-clockwise seen from outside: the index of an
    /// owned vertex, or [`SHARED_ID`]` | k` for shared vertex `k` (at
    /// `positions[slots.len() + k]`).
    pub(crate) triangles: Vec<[u32; 3]>,
    /// The triangles (indices into `triangles`) of feature fans, each with
    /// its fan vertex first.
    pub(crate) feature_triangles: Vec<u32>,
}

impl Piece {
    /// Bytes its buffers hold.
    pub fn heap_bytes(&self) -> usize {
        self.slots.len() * 4
            + (self.positions.len() + self.normals.len()) * 24
            + self.shared.len() * 8
            + self.triangles.len() * 12
            + self.feature_triangles.len() * 4
    }
}

/// Samples per edge of the block a brick's cells read.
const N: usize = BRICK as usize + 1;
/// Slots of edge vertices in a brick's vertex table (see [`Piece`]).
pub const EDGE_SLOTS: u32 = (N * N * N * 3) as u32;

fn unit_or_z(g: [f64; 3]) -> [f64; 3] {
    let l = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    if l > 0.0 && l.is_finite() {
        let inv = 1.0 / l;
        g.map(|x| x * inv)
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Marks a shared vertex's index in a piece's triangles (the owned ones
/// are numbered first, as they are made, and the shared ones apart: so the
/// triangles need no renumbering once the count of owned ones is known).
pub(crate) const SHARED_ID: u32 = 1 << 31;

/// Per-thread scratch of brick extraction: the 9³ block, its inside masks,
/// the vertex id of every crossing edge slot and the temporary buffers,
/// reused from brick to brick.
struct Scratch {
    block: [f32; N * N * N],
    /// Per row `y + 9 z` of the block, bit `x` set for an inside sample.
    rows: [u16; N * N],
    out: Out,
}

/// The piece under construction (see [`PieceSink`]).
struct Out {
    /// Vertex id per edge slot; valid for the current brick's crossing
    /// edges only (the only ones the cells ask for).
    id: Vec<u32>,
    slots: Vec<u32>,
    positions: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    shared: Vec<(u8, u32)>,
    shared_positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    feature_triangles: Vec<u32>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch {
        block: [0.0; N * N * N],
        rows: [0; N * N],
        out: Out {
            id: vec![0; EDGE_SLOTS as usize],
            slots: Vec::new(),
            positions: Vec::new(),
            normals: Vec::new(),
            shared: Vec::new(),
            shared_positions: Vec::new(),
            triangles: Vec::new(),
            feature_triangles: Vec::new(),
        },
    });
}

/// Builds one brick's piece. The edge vertices are all made up front, in
/// slot order, from the block's inside masks (every crossing edge of the
/// 9³ block belongs to a cell of the brick, so the cells ask for exactly
/// these): the owned ones are numbered in slot order at once and get their
/// normals, the shared ones are numbered after the owned ones (and the
/// cells' centroids, which come in slot order as the cells do) at the end.
struct PieceSink<'a> {
    base: [i32; 3],
    step: f64,
    inv_step: f64,
    exact: Option<&'a ExactField>,
    block: &'a [f32; N * N * N],
    rows: &'a [u16; N * N],
    out: &'a mut Out,
}

#[inline]
fn block_index(l: [usize; 3]) -> usize {
    l[0] + N * (l[1] + N * l[2])
}

/// The unit normal of an owned vertex (in `slot` at `pos`, brick corner
/// sample `base`): the gradient of the trilinear interpolant of the cell at
/// the vertex's edge's lower corner (a canonical cell, so the normal does
/// not depend on which cell met the vertex first), or of the centroid's own
/// cell.
#[inline]
fn vertex_normal(
    b: &[f32; N * N * N],
    base: [i32; 3],
    inv_step: f64,
    slot: u32,
    pos: [f64; 3],
) -> [f64; 3] {
    if slot >= EDGE_SLOTS {
        let cell = ((slot - EDGE_SLOTS) / 4) as usize;
        let bs = BRICK as usize;
        let l = [cell % bs, cell / bs % bs, cell / (bs * bs)];
        let mut c = [0f32; 8];
        for (i, o) in super::mc::CORNER_OFFSETS.iter().enumerate() {
            c[i] = b[block_index([0, 1, 2].map(|a| l[a] + o[a] as usize))];
        }
        let f = [0, 1, 2].map(|a| pos[a] * inv_step - (base[a] + l[a] as i32) as f64);
        return unit_or_z(trilinear_gradient(&c.map(f64::from), f));
    }
    let e = (slot / 3) as usize;
    let axis = (slot % 3) as usize;
    // The edge's lower sample is block sample `e`.
    let strides = [1, N, N * N];
    let (i0, i1) = (e, e + strides[axis]);
    let (v0, v1) = (b[i0] as f64, b[i1] as f64);
    // Where the vertex lies along its edge (read back from its position: a
    // multiply instead of the division that placed it).
    let la = e / strides[axis] % N;
    let t = pos[axis] * inv_step - (base[axis] + la as i32) as f64;
    let mut g = [0.0; 3];
    for (a, ga) in g.iter_mut().enumerate() {
        *ga = if a == axis {
            v1 - v0
        } else {
            let stride = strides[a];
            let d0 = b[i0 + stride] as f64 - v0;
            let d1 = b[i1 + stride] as f64 - v1;
            d0 + (d1 - d0) * t
        };
    }
    unit_or_z(g)
}

impl PieceSink<'_> {
    /// Makes every crossing edge's vertex of the block, in slot order (see
    /// the type's doc), from the rows' inside masks.
    fn edge_vertices(&mut self) {
        const B: usize = BRICK as usize;
        let (block, rows, out) = (self.block, self.rows, &mut *self.out);
        for z in 0..N {
            for y in 0..N {
                let m = rows[y + N * z];
                // Crossing edges starting at x along x, y and z.
                let ex = (m ^ (m >> 1)) & 0xff;
                let ey = if y < B { m ^ rows[y + 1 + N * z] } else { 0 };
                let ez = if z < B { m ^ rows[y + N * (z + 1)] } else { 0 };
                let mut any = ex | ey | ez;
                let row = N * (y + N * z);
                while any != 0 {
                    let x = any.trailing_zeros() as usize;
                    any &= any - 1;
                    let i = row + x;
                    for (axis, mask) in [ex, ey, ez].into_iter().enumerate() {
                        if mask >> x & 1 == 0 {
                            continue;
                        }
                        let slot = (i * 3 + axis) as u32;
                        let stride = [1, N, N * N][axis];
                        let lo = [
                            self.base[0] + x as i32,
                            self.base[1] + y as i32,
                            self.base[2] + z as i32,
                        ];
                        let pos = super::mc::edge_vertex(
                            lo,
                            axis,
                            block[i],
                            block[i + stride],
                            self.step,
                        );
                        if x < B && y < B && z < B {
                            out.id[slot as usize] = out.positions.len() as u32;
                            out.slots.push(slot);
                            out.positions.push(pos);
                        } else {
                            out.id[slot as usize] = SHARED_ID | out.shared.len() as u32;
                            out.shared.push(slot_owner(slot));
                            out.shared_positions.push(pos);
                        }
                    }
                }
            }
        }
    }

    /// Numbers the shared vertices after the owned ones and copies the
    /// piece out of the scratch.
    fn finish(self) -> Piece {
        // The owned vertices' normals, in one loop of independent
        // iterations (a square root and a division each: interleaved with
        // the vertices' making, their latency was not hidden).
        let out = &mut *self.out;
        let (block, base, inv_step) = (self.block, self.base, self.inv_step);
        out.normals.extend(
            out.slots
                .iter()
                .zip(&out.positions)
                .map(|(&slot, &pos)| vertex_normal(block, base, inv_step, slot, pos)),
        );
        let sc = &*out;
        let mut positions = Vec::with_capacity(sc.positions.len() + sc.shared_positions.len());
        positions.extend_from_slice(&sc.positions);
        positions.extend_from_slice(&sc.shared_positions);
        let triangles = sc.triangles.clone();
        Piece {
            slots: sc.slots.clone(),
            positions,
            normals: sc.normals.clone(),
            shared: sc.shared.clone(),
            triangles,
            feature_triangles: sc.feature_triangles.clone(),
        }
    }
}

/// The owner of the vertex in `slot` (bit `a`: the +`a` neighbour; 0: the
/// brick itself) and its slot in the owner's table.
pub(super) fn slot_owner(slot: u32) -> (u8, u32) {
    if slot >= EDGE_SLOTS {
        return (0, slot);
    }
    let cell = (slot / 3) as usize;
    let axis = slot % 3;
    let mut l = [cell % N, cell / N % N, cell / (N * N)];
    let mut owner = 0u8;
    for (a, c) in l.iter_mut().enumerate() {
        if *c == BRICK as usize {
            owner |= 1 << a;
            *c = 0;
        }
    }
    (owner, (block_index(l) * 3) as u32 + axis)
}

impl MeshSink for PieceSink<'_> {
    #[inline]
    fn vertex(&mut self, key: VertKey, _pos: impl FnOnce() -> [f64; 3]) -> u32 {
        // Made up front by `edge_vertices` (the same position).
        let l = [0, 1, 2].map(|a| (key.at[a] - self.base[a]) as usize);
        self.out.id[block_index(l) * 3 + key.kind as usize]
    }

    fn fresh(&mut self, key: VertKey, pos: [f64; 3]) -> u32 {
        let l = [0, 1, 2].map(|a| (key.at[a] - self.base[a]) as usize);
        let cell = l[0] + BRICK as usize * (l[1] + BRICK as usize * l[2]);
        let slot = EDGE_SLOTS + (cell * 4) as u32 + (key.kind - 3) as u32;
        let out = &mut *self.out;
        let n = out.positions.len() as u32;
        out.slots.push(slot);
        out.positions.push(pos);
        n
    }

    #[inline]
    fn position(&self, id: u32) -> [f64; 3] {
        if id & SHARED_ID != 0 {
            self.out.shared_positions[(id & !SHARED_ID) as usize]
        } else {
            self.out.positions[id as usize]
        }
    }

    fn keeps_features(&self) -> bool {
        self.exact.is_some()
    }

    fn feature_apex(&mut self, cell: [i32; 3], loop_points: &[[f64; 3]]) -> Option<[f64; 3]> {
        let lo = DVec3::new(cell[0] as f64, cell[1] as f64, cell[2] as f64) * self.step;
        let min = MIN_TWICE_AREA_REL * self.step * self.step;
        feature_apex(self.exact?, lo, self.step, loop_points, min)
    }

    #[inline]
    fn triangle(&mut self, t: [u32; 3]) {
        self.out.triangles.push(t)
    }

    fn feature_triangle(&mut self, t: [u32; 3]) {
        self.out
            .feature_triangles
            .push(self.out.triangles.len() as u32);
        self.out.triangles.push(t)
    }
}

impl SparseGrid {
    /// Marching cubes over the 8³ cells whose lower corner lies in brick
    /// `key` (reading one sample layer of the +x/+y/+z neighbours). A
    /// block without a sign change is skipped after the loads. With
    /// `exact`, cells on sharp features keep them ([`super::features`]).
    pub fn extract_brick(&self, key: BrickKey, exact: Option<&ExactField>) -> Piece {
        let nbs: [Option<&Brick>; 8] = super::mc::CORNER_OFFSETS.map(|o| {
            self.bricks
                .get(&[key[0] + o[0], key[1] + o[1], key[2] + o[2]])
        });
        self.extract_with(key, &nbs, exact)
    }

    /// Extracts every brick with surface (in parallel, merged in key
    /// order), as [`Self::extraction_bricks`] and [`Self::extract_brick`]
    /// would, but faster: where the stored bricks fill their bounding box
    /// reasonably, a dense index over the box gives each candidate its 8
    /// bricks without map lookups, and each brick's per-region signs (the
    /// whole brick, the low faces, edges and corner that lower neighbours
    /// read) tell exactly which candidates' 9³ blocks change sign, so no
    /// block without surface is loaded.
    pub fn extract_all(&self, exact: Option<&ExactField>) -> BTreeMap<BrickKey, Arc<Piece>> {
        let Some(bbox) = self.candidate_box() else {
            let keys = self.extraction_bricks();
            let v: Vec<(BrickKey, Piece)> = keys
                .par_iter()
                .with_min_len(2)
                .map(|k| (*k, self.extract_brick(*k, exact)))
                .collect();
            return v
                .into_iter()
                .filter(|(_, p)| !p.triangles.is_empty())
                .map(|(k, p)| (k, Arc::new(p)))
                .collect();
        };
        let (lo, dims) = bbox;
        let at = |l: [usize; 3]| (l[0] * dims[1] + l[1]) * dims[2] + l[2];
        let stored: Vec<(&BrickKey, &Brick)> = self.bricks.iter().collect();
        let mut index = vec![u32::MAX; dims[0] * dims[1] * dims[2]];
        for (i, (k, _)) in stored.iter().enumerate() {
            index[at([0, 1, 2].map(|a| (k[a] - lo[a]) as usize))] = i as u32;
        }
        let signs: Vec<[u8; 8]> = stored.iter().map(|(_, b)| b.region_signs()).collect();
        let (index, signs, stored) = (&index, &signs, &stored);
        // One task per (x, y) column: surface is unevenly spread over x.
        let v: Vec<(BrickKey, Arc<Piece>)> = (0..dims[0] * dims[1])
            .into_par_iter()
            .flat_map_iter(|xy| {
                let (x, y) = (xy / dims[1], xy % dims[1]);
                {
                    (0..dims[2]).filter_map(move |z| {
                        let mut nbs: [Option<&Brick>; 8] = [None; 8];
                        let mut seen = 0u8;
                        for (c, o) in super::mc::CORNER_OFFSETS.iter().enumerate() {
                            let l = [x + o[0] as usize, y + o[1] as usize, z + o[2] as usize];
                            let i = if l[0] < dims[0] && l[1] < dims[1] && l[2] < dims[2] {
                                index[at(l)]
                            } else {
                                u32::MAX
                            };
                            if i == u32::MAX {
                                seen |= SIGN_OUT;
                            } else {
                                seen |= signs[i as usize][c];
                                nbs[c] = Some(stored[i as usize].1);
                            }
                        }
                        if seen != SIGN_OUT | SIGN_IN {
                            return None;
                        }
                        let key = [lo[0] + x as i32, lo[1] + y as i32, lo[2] + z as i32];
                        let piece = self.extract_with(key, &nbs, exact);
                        (!piece.triangles.is_empty()).then(|| (key, Arc::new(piece)))
                    })
                }
            })
            .collect();
        v.into_iter().collect()
    }

    /// Marching cubes over brick `key`'s cells, given the 8 bricks
    /// `key + {0,1}³` (`None`: absent).
    fn extract_with(
        &self,
        key: BrickKey,
        nbs: &[Option<&Brick>; 8],
        exact: Option<&ExactField>,
    ) -> Piece {
        const B: usize = BRICK as usize;
        // The block changes sign only if the parts of the 8 bricks that
        // it reads do (absent bricks are outside).
        let mut seen = 0u8;
        for (o, nb) in nbs.iter().enumerate() {
            seen |= nb.map_or(SIGN_OUT, |b| b.region_signs()[o]);
        }
        if seen != SIGN_OUT | SIGN_IN {
            return Piece::default();
        }
        SCRATCH.with(|sc| {
            let sc = &mut *sc.borrow_mut();
            // The 9³ block: brick `key` plus one sample layer of its
            // +x/+y/+z neighbours, filled region by region.
            for (o, nb) in super::mc::CORNER_OFFSETS.iter().zip(nbs) {
                let range = |a: usize| if o[a] == 0 { 0..B } else { B..N };
                for z in range(2) {
                    for y in range(1) {
                        let row = N * (y + N * z);
                        let lrow = (y % B) * B + (z % B) * B * B;
                        // Rows of 8 (this brick's x range) or 1 (the +x
                        // layer), copied with fixed lengths so that the
                        // copies inline.
                        if o[0] == 0 {
                            let dst: &mut [f32; B] = (&mut sc.block[row..row + B])
                                .try_into()
                                .expect("a row of 8");
                            match nb {
                                None => *dst = [self.band; B],
                                Some(Brick::Uniform(v)) => *dst = [*v; B],
                                Some(Brick::Dense(d)) => {
                                    *dst = d[lrow..lrow + B].try_into().expect("a row of 8");
                                }
                            }
                        } else {
                            let v = match nb {
                                None => self.band,
                                Some(Brick::Uniform(v)) => *v,
                                Some(Brick::Dense(d)) => d[lrow],
                            };
                            sc.block[row + B] = v;
                        }
                    }
                }
            }
            for (m, row) in sc.rows.iter_mut().zip(sc.block.chunks_exact(N)) {
                *m = row
                    .iter()
                    .enumerate()
                    .fold(0u16, |bits, (x, v)| bits | ((*v < 0.0) as u16) << x);
            }
            let base = key.map(|k| k * BRICK);
            let Scratch { block, rows, out } = sc;
            out.slots.clear();
            out.positions.clear();
            out.normals.clear();
            out.shared.clear();
            out.shared_positions.clear();
            out.triangles.clear();
            out.feature_triangles.clear();
            let (block, rows) = (&*block, &*rows);
            let mut sink = PieceSink {
                base,
                step: self.step,
                exact,
                inv_step: 1.0 / self.step,
                block,
                rows,
                out,
            };
            sink.edge_vertices();
            // Per (y, z) row of cells: the cells whose 8 corners are not
            // all inside or all outside, from the four sample rows' masks.
            for z in 0..B {
                for y in 0..B {
                    let m = [
                        rows[y + N * z],
                        rows[y + 1 + N * z],
                        rows[y + N * (z + 1)],
                        rows[y + 1 + N * (z + 1)],
                    ];
                    let or = m[0] | m[1] | m[2] | m[3];
                    let and = m[0] & m[1] & m[2] & m[3];
                    let mut cells = (or | or >> 1) & !(and & and >> 1) & 0xff;
                    while cells != 0 {
                        let x = cells.trailing_zeros() as usize;
                        cells &= cells - 1;
                        let mut v = [0f32; 8];
                        for (c, o) in super::mc::CORNER_OFFSETS.iter().enumerate() {
                            v[c] = block[(x + o[0] as usize)
                                + N * ((y + o[1] as usize) + N * (z + o[2] as usize))];
                        }
                        // Corner c's sign: bit x (c even) or x + 1 of
                        // sample row c / 2.
                        let config =
                            (0..4).fold(0usize, |c, r| c | ((m[r] >> x & 3) as usize) << (2 * r));
                        let cell = [base[0] + x as i32, base[1] + y as i32, base[2] + z as i32];
                        polygonize_config(cell, &v, config, self.step, &mut sink);
                    }
                }
            }
            sink.finish()
        })
    }
}
