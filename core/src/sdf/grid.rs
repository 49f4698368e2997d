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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Piece {
    pub(crate) keys: Vec<VertKey>,
    pub(crate) positions: Vec<[f64; 3]>,
    pub(crate) triangles: Vec<[u32; 3]>,
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
            .iter()
            .map(|(k, b)| (*k, b.sign_class()))
            .collect();
        let mut cand: Vec<BrickKey> = Vec::with_capacity(self.bricks.len() * 2);
        for k in self.bricks.keys() {
            for o in super::mc::CORNER_OFFSETS {
                cand.push([k[0] - o[0], k[1] - o[1], k[2] - o[2]]);
            }
        }
        cand.sort_unstable();
        cand.dedup();
        cand.retain(|key| {
            let mut seen = [false; 3];
            for o in super::mc::CORNER_OFFSETS {
                let c = classes
                    .get(&[key[0] + o[0], key[1] + o[1], key[2] + o[2]])
                    .copied()
                    .unwrap_or(0);
                seen[c as usize] = true;
            }
            seen[2] || (seen[0] && seen[1])
        });
        cand
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
        let mut block = [0f32; N * N * N];
        let nb: Vec<Brick> = super::mc::CORNER_OFFSETS
            .iter()
            .map(|o| self.brick([key[0] + o[0], key[1] + o[1], key[2] + o[2]]))
            .collect();
        for z in 0..N {
            for y in 0..N {
                for x in 0..N {
                    let (bx, by, bz) = (x / 8, y / 8, z / 8);
                    let b = &nb[bx | by << 1 | bz << 2];
                    block[x + N * (y + N * z)] =
                        b.get(local_index((x % 8) as i32, (y % 8) as i32, (z % 8) as i32));
                }
            }
        }
        let base = key.map(|k| k * BRICK);
        let mut sink = PieceSink::new(base);
        for z in 0..8 {
            for y in 0..8 {
                for x in 0..8 {
                    let mut v = [0f32; 8];
                    let mut any_in = false;
                    let mut any_out = false;
                    for (c, o) in super::mc::CORNER_OFFSETS.iter().enumerate() {
                        let s = block[(x + o[0] as usize)
                            + N * ((y + o[1] as usize) + N * (z + o[2] as usize))];
                        v[c] = s;
                        if s < 0.0 {
                            any_in = true;
                        } else {
                            any_out = true;
                        }
                    }
                    if any_in && any_out {
                        let cell = [base[0] + x as i32, base[1] + y as i32, base[2] + z as i32];
                        polygonize(cell, &v, self.step, &mut sink);
                    }
                }
            }
        }
        sink.piece
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
/// same key are one vertex.
pub fn assemble<'a>(pieces: impl Iterator<Item = &'a Piece>) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut map: std::collections::HashMap<VertKey, u32, super::mc::BuildKeyHasher> =
        Default::default();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut remap = Vec::new();
    for p in pieces {
        remap.clear();
        for (k, pos) in p.keys.iter().zip(&p.positions) {
            let n = positions.len() as u32;
            let id = *map.entry(*k).or_insert(n);
            if id == n {
                positions.push(*pos);
            }
            remap.push(id);
        }
        triangles.extend(p.triangles.iter().map(|t| t.map(|i| remap[i as usize])));
    }
    (positions, triangles)
}
