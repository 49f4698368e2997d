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

/// Samples per brick edge.
pub const BRICK: i32 = 8;
/// Samples per brick.
pub const BRICK_LEN: usize = 512;

/// Sign bit of samples at or above zero (outside).
pub(crate) const SIGN_OUT: u8 = 1;
/// Sign bit of negative samples (inside).
pub(crate) const SIGN_IN: u8 = 2;

/// A brick's coordinates (brick `B` holds samples `8B .. 8B + 8`).
pub type BrickKey = [i32; 3];

/// A brick's samples.
#[derive(Clone, Debug, PartialEq)]
pub enum Brick {
    /// Every sample is this value (`+band` or `-band`).
    Uniform(f32),
    /// 512 samples, x fastest, with their signs per region.
    Dense(Arc<DenseBrick>),
}

/// The samples of a dense brick and, computed once when it is made, the
/// signs that extraction asks about (see `Brick::region_signs`).
#[derive(Clone, Debug, PartialEq)]
pub struct DenseBrick {
    values: Vec<f32>,
    signs: [u8; 8],
}

impl std::ops::Deref for DenseBrick {
    type Target = [f32];
    fn deref(&self) -> &[f32] {
        &self.values
    }
}

impl Brick {
    /// The brick holding `values` (512 samples, x fastest): uniform when
    /// every sample equals `±band`, else dense.
    pub fn dense(values: Vec<f32>, band: f32) -> Brick {
        assert_eq!(values.len(), BRICK_LEN, "a brick has 512 samples");
        // Uniform bricks fail these at once when they are not.
        for u in [band, -band] {
            if values.iter().all(|x| *x == u) {
                return Brick::Uniform(u);
            }
        }
        // Per row of 8, the mask of inside samples.
        let mut rows = [0u8; 64];
        for (row, m) in values.chunks_exact(BRICK as usize).zip(&mut rows) {
            *m = row
                .iter()
                .enumerate()
                .fold(0u8, |bits, (x, v)| bits | ((*v < 0.0) as u8) << x);
        }
        let signs = region_signs_of_rows(&rows);
        Brick::Dense(Arc::new(DenseBrick { values, signs }))
    }

    /// The sample at local index `l` (0..512).
    #[inline]
    pub fn get(&self, l: usize) -> f32 {
        match self {
            Brick::Uniform(v) => *v,
            Brick::Dense(d) => d[l],
        }
    }

    /// The signs (bits [`SIGN_OUT`], [`SIGN_IN`]) of the samples a brick
    /// `key - o` reads from this one, for each corner offset `o` (index as
    /// in `CORNER_OFFSETS`): all of them for `o = 0`, otherwise the low
    /// face, edge or corner sample across which the lower brick's cells
    /// reach.
    pub(crate) fn region_signs(&self) -> [u8; 8] {
        match self {
            Brick::Uniform(v) => [sign_bit(*v); 8],
            Brick::Dense(d) => d.signs,
        }
    }

    /// Whether every sample is outside (0), every sample inside (1), or
    /// mixed (2).
    fn sign_class(&self) -> u8 {
        match self.region_signs()[0] {
            SIGN_OUT => 0,
            SIGN_IN => 1,
            _ => 2,
        }
    }
}

#[inline]
fn sign_bit(v: f32) -> u8 {
    if v < 0.0 {
        SIGN_IN
    } else {
        SIGN_OUT
    }
}

/// The region signs (see [`Brick::region_signs`]) from the inside masks
/// of the 64 rows (row `y + 8 z`, bit `x` set for an inside sample).
fn region_signs_of_rows(rows: &[u8; 64]) -> [u8; 8] {
    // Or and and of the masks over all rows, the rows with y = 0 and the
    // rows with z = 0.
    let (mut or_all, mut and_all) = (0u8, 0xffu8);
    let (mut or_y0, mut and_y0) = (0u8, 0xffu8);
    let (mut or_z0, mut and_z0) = (0u8, 0xffu8);
    for (r, &m) in rows.iter().enumerate() {
        or_all |= m;
        and_all &= m;
        if r % BRICK as usize == 0 {
            or_y0 |= m;
            and_y0 &= m;
        }
        if r < BRICK as usize {
            or_z0 |= m;
            and_z0 &= m;
        }
    }
    // The samples of bits `mask` of those rows: inside if any is set,
    // outside if any is clear.
    let sign = |or: u8, and: u8, mask: u8| {
        (if or & mask != 0 { SIGN_IN } else { 0 }) | (if and & mask != mask { SIGN_OUT } else { 0 })
    };
    let r00 = rows[0];
    // Offset bit a set: only the low layer along axis a (x = bit 0).
    [
        sign(or_all, and_all, 0xff),
        sign(or_all, and_all, 0x01),
        sign(or_y0, and_y0, 0xff),
        sign(or_y0, and_y0, 0x01),
        sign(or_z0, and_z0, 0xff),
        sign(or_z0, and_z0, 0x01),
        sign(r00, r00, 0xff),
        sign(r00, r00, 0x01),
    ]
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
    ///
    /// When the stored bricks fill their bounding box reasonably (any
    /// single compact model does), the sign classes go into a dense array
    /// over the box and every candidate is tested with 8 array reads;
    /// otherwise through a hash map of the stored bricks' classes.
    pub fn extraction_bricks(&self) -> Vec<BrickKey> {
        let Some((lo, dims)) = self.candidate_box() else {
            return self.extraction_bricks_sparse();
        };
        let volume = dims[0] * dims[1] * dims[2];
        let index = |k: [i32; 3]| -> usize {
            let l = [0, 1, 2].map(|a| (k[a] - lo[a]) as usize);
            (l[0] * dims[1] + l[1]) * dims[2] + l[2]
        };
        let stored: Vec<(&BrickKey, &Brick)> = self.bricks.iter().collect();
        let classes: Vec<u8> = stored.iter().map(|(_, b)| b.sign_class()).collect();
        let mut class = vec![0u8; volume];
        for ((k, _), c) in stored.iter().zip(classes) {
            class[index(**k)] = c;
        }
        // x-major order, as `BrickKey`s sort.
        (0..dims[0])
            .into_par_iter()
            .flat_map_iter(|x| {
                let class = &class;
                (0..dims[1]).flat_map(move |y| {
                    (0..dims[2]).filter_map(move |z| {
                        let mut seen = 0u8;
                        for o in super::mc::CORNER_OFFSETS {
                            let l = [x + o[0] as usize, y + o[1] as usize, z + o[2] as usize];
                            let c = if l[0] < dims[0] && l[1] < dims[1] && l[2] < dims[2] {
                                class[(l[0] * dims[1] + l[1]) * dims[2] + l[2]]
                            } else {
                                0
                            };
                            seen |= 1 << c;
                        }
                        (seen & 4 != 0 || seen == 3).then_some([
                            lo[0] + x as i32,
                            lo[1] + y as i32,
                            lo[2] + z as i32,
                        ])
                    })
                })
            })
            .collect()
    }

    fn extraction_bricks_sparse(&self) -> Vec<BrickKey> {
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

    /// The box of candidate bricks (one below the stored ones) as its
    /// lowest key and size, when the stored bricks fill it well enough for
    /// a dense index (any single compact model does); `None` otherwise.
    pub(crate) fn candidate_box(&self) -> Option<([i32; 3], [usize; 3])> {
        let first = *self.bricks.keys().next()?;
        let (mut lo, mut hi) = (first, first);
        for k in self.bricks.keys() {
            for a in 0..3 {
                lo[a] = lo[a].min(k[a]);
                hi[a] = hi[a].max(k[a]);
            }
        }
        let lo = lo.map(|c| c - 1);
        let dims = [0, 1, 2].map(|a| (hi[a] - lo[a] + 1) as usize);
        let volume = dims[0] * dims[1] * dims[2];
        (volume <= 64 * self.bricks.len() + 4096).then_some((lo, dims))
    }
}
