//! [`SparseGrid`]: the scene SDF as a sparse set of 8³-sample bricks over an
//! unbounded integer lattice (paper 2 §5.1's global Φ, made sparse).
//!
//! Sample `(i, j, k)` (any `i32`) sits at `step * (i, j, k)`; brick `B`
//! holds samples `8B .. 8B + 8`. Values are clamped to `[-band, band]`.
//! A brick is either dense (512 samples) or uniform (all samples `±band`,
//! far from the surface); a missing brick is uniform `+band` (outside), so
//! the scene has no fixed extent and memory follows the surface. Inside a
//! big solid, far from its surface, bricks are uniform `-band`: one value
//! per brick. Clamping commutes with min, max and negation, so CSG on
//! clamped fields gives exactly the clamped CSG result.

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;

use super::mc::{polygonize, MeshSink, VertKey};

/// Samples per brick edge.
pub const BRICK: i32 = 8;
/// Samples per brick.
pub const BRICK_LEN: usize = 512;

/// A brick's coordinates (brick `B` holds samples `8B .. 8B + 8`).
pub type BrickKey = [i32; 3];

/// A brick's samples.
#[derive(Clone, Debug, PartialEq)]
pub enum Brick {
    /// Every sample is this value (`+band` or `-band`).
    Uniform(f32),
    /// 512 samples, x fastest.
    Dense(Arc<Vec<f32>>),
}

impl Brick {
    /// The sample at local index `l` (0..512).
    #[inline]
    pub fn get(&self, l: usize) -> f32 {
        match self {
            Brick::Uniform(v) => *v,
            Brick::Dense(d) => d[l],
        }
    }

    /// Collapses a dense brick whose samples all equal `±band`.
    pub fn normalized(self, band: f32) -> Brick {
        if let Brick::Dense(d) = &self {
            for u in [band, -band] {
                if d.iter().all(|x| *x == u) {
                    return Brick::Uniform(u);
                }
            }
        }
        self
    }

    /// Whether every sample is inside, every sample outside, or mixed.
    fn sign_class(&self) -> u8 {
        match self {
            Brick::Uniform(v) => (*v < 0.0) as u8,
            Brick::Dense(d) => {
                let neg = d.iter().filter(|x| **x < 0.0).count();
                match neg {
                    0 => 0,
                    BRICK_LEN => 1,
                    _ => 2,
                }
            }
        }
    }
}

/// Local index of a sample within its brick.
#[inline]
pub fn local_index(x: i32, y: i32, z: i32) -> usize {
    (x + BRICK * (y + BRICK * z)) as usize
}

/// The sparse scene grid.
#[derive(Clone, Debug, PartialEq)]
pub struct SparseGrid {
    /// Grid spacing in model units.
    pub step: f64,
    /// Clamp magnitude of stored values.
    pub band: f32,
    /// Stored bricks; absent bricks are uniform `+band`.
    pub bricks: BTreeMap<BrickKey, Brick>,
}

/// The triangles extracted from the cells of one brick, with vertices
/// named by their grid edge so that pieces stitch by key.
///
/// The first `owned` vertices are the brick's own (their edge's lower
/// corner, or their cell, lies in the brick), sorted by key; the others lie
/// on edges starting in a +x/+y/+z neighbour brick, which owns them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piece {
    pub(crate) keys: Vec<VertKey>,
    pub(crate) positions: Vec<[f64; 3]>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) owned: usize,
}

impl Piece {
    /// Puts the owned vertices first, sorted by key (see [`Piece`]).
    fn order_owned_first(&mut self, base: [i32; 3]) {
        let n = self.keys.len();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let owned = |k: &VertKey| (0..3).all(|a| k.at[a] - base[a] < BRICK);
        order.sort_unstable_by(|&a, &b| {
            let (ka, kb) = (&self.keys[a as usize], &self.keys[b as usize]);
            match (owned(ka), owned(kb)) {
                (true, true) => ka.cmp(kb),
                (true, false) => std::cmp::Ordering::Less,
                (false, true) => std::cmp::Ordering::Greater,
                (false, false) => a.cmp(&b),
            }
        });
        let mut new_of_old = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_of_old[old as usize] = new as u32;
        }
        self.keys = order.iter().map(|&o| self.keys[o as usize]).collect();
        self.positions = order.iter().map(|&o| self.positions[o as usize]).collect();
        for t in &mut self.triangles {
            *t = t.map(|i| new_of_old[i as usize]);
        }
        self.owned = self.keys.iter().take_while(|k| owned(k)).count();
    }
}

impl SparseGrid {
    /// An empty grid (everything outside).
    pub fn new(step: f64, band: f32) -> Self {
        Self {
            step,
            band,
            bricks: BTreeMap::new(),
        }
    }

    /// The brick at `key` (absent ones are uniform `+band`).
    #[inline]
    pub fn brick(&self, key: BrickKey) -> Brick {
        self.bricks
            .get(&key)
            .cloned()
            .unwrap_or(Brick::Uniform(self.band))
    }

    /// The sample at global index `p`.
    pub fn sample(&self, p: [i32; 3]) -> f32 {
        let key = p.map(|x| x.div_euclid(BRICK));
        let l = p.map(|x| x.rem_euclid(BRICK));
        match self.bricks.get(&key) {
            Some(b) => b.get(local_index(l[0], l[1], l[2])),
            None => self.band,
        }
    }

    /// Stores `b` at `key` (removing it when it is uniform outside).
    pub fn set(&mut self, key: BrickKey, b: Brick) {
        match b {
            Brick::Uniform(v) if v >= self.band => {
                self.bricks.remove(&key);
            }
            b => {
                self.bricks.insert(key, b);
            }
        }
    }

    /// Bytes held by dense bricks (for the memory budget).
    pub fn dense_bytes(&self) -> usize {
        self.bricks
            .values()
            .filter(|b| matches!(b, Brick::Dense(_)))
            .count()
            * BRICK_LEN
            * 4
    }

    /// Bricks whose cells may cross the surface: every brick `B` such that
    /// the 8 bricks `B + {0,1}³` (which its cells read) are not all inside
    /// or all outside. Sorted.
    pub fn extraction_bricks(&self) -> Vec<BrickKey> {
        let classes: std::collections::HashMap<BrickKey, u8, super::mc::BuildKeyHasher> = self
            .bricks
            .par_iter()
            .map(|(k, b)| (*k, b.sign_class()))
            .collect();
        let mut cand: Vec<BrickKey> = Vec::with_capacity(self.bricks.len() * 2);
        for k in self.bricks.keys() {
            for o in super::mc::CORNER_OFFSETS {
                cand.push([k[0] - o[0], k[1] - o[1], k[2] - o[2]]);
            }
        }
        cand.par_sort_unstable();
        cand.dedup();
        // Filtered in parallel; `collect` keeps the sorted order.
        cand.into_par_iter()
            .with_min_len(256)
            .filter(|key| {
                let mut seen = [false; 3];
                for o in super::mc::CORNER_OFFSETS {
                    let c = classes
                        .get(&[key[0] + o[0], key[1] + o[1], key[2] + o[2]])
                        .copied()
                        .unwrap_or(0);
                    seen[c as usize] = true;
                }
                seen[2] || (seen[0] && seen[1])
            })
            .collect()
    }

    /// True when brick `key`'s cells can contain a crossing.
    pub fn needs_extraction(&self, key: BrickKey) -> bool {
        let mut seen = [false; 3];
        for o in super::mc::CORNER_OFFSETS {
            let b = self
                .bricks
                .get(&[key[0] + o[0], key[1] + o[1], key[2] + o[2]]);
            let c = b.map_or(0, Brick::sign_class);
            seen[c as usize] = true;
        }
        seen[2] || (seen[0] && seen[1])
    }

    /// Marching cubes over the 8³ cells whose lower corner lies in brick
    /// `key` (reading one sample layer of the +x/+y/+z neighbours).
    pub fn extract_brick(&self, key: BrickKey) -> Piece {
        const N: usize = BRICK as usize + 1;
        const B: usize = BRICK as usize;
        let mut block = [0f32; N * N * N];
        // The 9³ block: brick `key` plus one sample layer of its +x/+y/+z
        // neighbours, filled region by region (one match per region).
        for o in super::mc::CORNER_OFFSETS.iter() {
            let nb = self
                .bricks
                .get(&[key[0] + o[0], key[1] + o[1], key[2] + o[2]]);
            let range = |a: usize| if o[a] == 0 { 0..B } else { B..N };
            for z in range(2) {
                for y in range(1) {
                    let row = N * (y + N * z);
                    let lrow = (y % B) * B + (z % B) * B * B;
                    for x in range(0) {
                        block[row + x] = match nb {
                            None => self.band,
                            Some(Brick::Uniform(v)) => *v,
                            Some(Brick::Dense(d)) => d[lrow + x % B],
                        };
                    }
                }
            }
        }
        let base = key.map(|k| k * BRICK);
        let mut sink = PieceSink::new(base);
        // Per (y, z) row: inside counts of the 4-sample columns, so a cell's
        // count is the sum of two columns (cells without a crossing are
        // skipped after two loads).
        let mut cols = [0u8; N];
        for z in 0..B {
            for y in 0..B {
                let r = [
                    N * (y + N * z),
                    N * (y + 1 + N * z),
                    N * (y + N * (z + 1)),
                    N * (y + 1 + N * (z + 1)),
                ];
                for (x, c) in cols.iter_mut().enumerate() {
                    *c = r.iter().map(|&r| (block[r + x] < 0.0) as u8).sum();
                }
                for x in 0..B {
                    let s = cols[x] + cols[x + 1];
                    if s == 0 || s == 8 {
                        continue;
                    }
                    let mut v = [0f32; 8];
                    for (c, o) in super::mc::CORNER_OFFSETS.iter().enumerate() {
                        v[c] = block[(x + o[0] as usize)
                            + N * ((y + o[1] as usize) + N * (z + o[2] as usize))];
                    }
                    let cell = [base[0] + x as i32, base[1] + y as i32, base[2] + z as i32];
                    polygonize(cell, &v, self.step, &mut sink);
                }
            }
        }
        let mut piece = sink.piece;
        piece.order_owned_first(base);
        piece
    }
}

/// Builds one brick's piece; edge vertices are found through a table
/// indexed by the edge's position in the 9³ block instead of a hash map.
struct PieceSink {
    base: [i32; 3],
    slots: Vec<u32>,
    piece: Piece,
}

impl PieceSink {
    fn new(base: [i32; 3]) -> Self {
        Self {
            base,
            slots: vec![u32::MAX; 9 * 9 * 9 * 3],
            piece: Piece::default(),
        }
    }
}

impl MeshSink for PieceSink {
    #[inline]
    fn vertex(&mut self, key: VertKey, pos: impl FnOnce() -> [f64; 3]) -> u32 {
        let l = [0, 1, 2].map(|a| (key.at[a] - self.base[a]) as usize);
        let slot = ((l[0] + 9 * (l[1] + 9 * l[2])) * 3) + key.kind as usize;
        let id = self.slots[slot];
        if id != u32::MAX {
            return id;
        }
        let n = self.piece.positions.len() as u32;
        self.slots[slot] = n;
        self.piece.keys.push(key);
        self.piece.positions.push(pos());
        n
    }
    fn fresh(&mut self, key: VertKey, pos: [f64; 3]) -> u32 {
        let n = self.piece.positions.len() as u32;
        self.piece.keys.push(key);
        self.piece.positions.push(pos);
        n
    }
    #[inline]
    fn triangle(&mut self, t: [u32; 3]) {
        self.piece.triangles.push(t)
    }
}

/// Stitches pieces (in key order) into one indexed mesh: vertices with the
/// same key are one vertex. Each vertex is numbered once, by the piece
/// that owns it (pieces in key order, owned vertices in key order); a
/// piece finds the vertices it shares with a +x/+y/+z neighbour by binary
/// search in that neighbour's owned keys. Pieces are remapped in parallel
/// and concatenated in order, so the result does not depend on threads.
pub fn assemble(pieces: &BTreeMap<BrickKey, Arc<Piece>>) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let list: Vec<(BrickKey, &Piece)> = pieces.iter().map(|(k, p)| (*k, p.as_ref())).collect();
    let mut offsets = Vec::with_capacity(list.len());
    let mut positions = Vec::with_capacity(list.iter().map(|(_, p)| p.owned).sum());
    for (_, p) in &list {
        offsets.push(positions.len() as u32);
        positions.extend_from_slice(&p.positions[..p.owned]);
    }
    // A shared vertex not found in its owner (a piece set that is not
    // closed under the extraction rule) gets u32::MAX and is numbered below.
    let find = |key: &VertKey, brick: BrickKey| -> u32 {
        let owner = [0, 1, 2].map(|a| brick[a] + (key.at[a] - brick[a] * BRICK >= BRICK) as i32);
        list.binary_search_by(|(k, _)| k.cmp(&owner))
            .ok()
            .and_then(|o| {
                let p = list[o].1;
                p.keys[..p.owned]
                    .binary_search(key)
                    .ok()
                    .map(|i| offsets[o] + i as u32)
            })
            .unwrap_or(u32::MAX)
    };
    let remapped: Vec<Vec<[u32; 3]>> = list
        .par_iter()
        .enumerate()
        .with_min_len(8)
        .map(|(o, (brick, p))| {
            let remap: Vec<u32> = (0..p.keys.len())
                .map(|i| {
                    if i < p.owned {
                        offsets[o] + i as u32
                    } else {
                        find(&p.keys[i], *brick)
                    }
                })
                .collect();
            p.triangles
                .iter()
                .map(|t| {
                    t.map(|i| match remap[i as usize] {
                        u32::MAX => u32::MAX - 1 - i,
                        id => id,
                    })
                })
                .collect()
        })
        .collect();
    let mut triangles = Vec::with_capacity(remapped.iter().map(Vec::len).sum());
    let mut orphans: std::collections::HashMap<VertKey, u32, super::mc::BuildKeyHasher> =
        Default::default();
    for ((_, p), tris) in list.iter().zip(remapped) {
        for mut t in tris {
            for i in &mut t {
                if *i as usize >= positions.len() {
                    let local = (u32::MAX - 1 - *i) as usize;
                    let n = positions.len() as u32;
                    *i = *orphans.entry(p.keys[local]).or_insert(n);
                    if *i == n {
                        positions.push(p.positions[local]);
                    }
                }
            }
            triangles.push(t);
        }
    }
    (positions, triangles)
}
