//! Watertight marching cubes (paper 2 §5.1, "extract the zero level set").
//!
//! Our own implementation, because the isosurface crates we tried do not
//! give closed 2-manifolds on noisy fields (see FIELD-NOTES). The cell
//! polygons are not read from the classic 256-case table; they are built by
//! walking the cube's faces, which makes every guarantee local and provable:
//!
//! - **Signs.** A sample is *inside* when `v < 0`; `0` and positive values
//!   are outside. Every cell sharing a sample sees the same sign.
//! - **Vertices per grid edge.** A crossing vertex lies on a grid edge whose
//!   corners differ in sign. Its position depends only on the edge's global
//!   index and its two samples (interpolated from the lower corner), so every
//!   cell (and every brick) computes the same bits. The interpolation
//!   parameter is clamped to `[EDGE_EPS, 1 - EDGE_EPS]`: a sample of exactly
//!   zero puts the vertex just beside the corner, never on it, so vertices of
//!   different edges never coincide and no triangle collapses.
//! - **Faces.** On each cube face the crossings are joined by segments, as
//!   marching squares does. A face with four crossings is ambiguous; it is
//!   decided by the asymptotic decider (the sign of the bilinear saddle),
//!   computed as `inside_a * inside_b > outside_a * outside_b` on the exact
//!   `f64` products of the `f32` samples. The products commute exactly, so
//!   the two cells sharing the face make the same choice, bit for bit.
//!   Segments are directed so that the inside lies on their left seen from
//!   outside the cube, hence the neighbour cell uses each segment reversed.
//! - **Cells.** Each crossing vertex has one outgoing and one incoming
//!   segment per cell, so the segments form disjoint directed loops; each
//!   loop bounds one disk of surface. A loop of three is one triangle. A
//!   longer loop is fanned from an apex whose diagonals never join two edges
//!   of one cube face (such a diagonal could be repeated by the neighbour
//!   cell, making a 4-triangle edge). When no apex qualifies, or a fan
//!   triangle is nearly degenerate, the loop is fanned around an extra
//!   vertex at its centroid instead (owned by the cell, so never shared).
//!
//! Every mesh edge is then either a face segment (used by exactly the two
//! cells beside the face, in opposite directions) or an interior diagonal or
//! spoke (two triangles of one loop), and the triangles around a crossing
//! vertex form one fan around its grid edge: the output is a closed,
//! oriented 2-manifold whenever the inside region is bounded. Cube-interior
//! ambiguities (MC33's tunnels) are resolved as separate disks; that is a
//! valid manifold, merely not always the trilinear topology.

use std::sync::OnceLock;

/// How close to a grid corner a crossing vertex may lie, as a fraction of
/// the step.
pub const EDGE_EPS: f64 = 1.0 / 256.0;

/// A fan triangle with twice its area below this times step² counts as
/// nearly degenerate and triggers the centroid fan.
pub(crate) const MIN_TWICE_AREA_REL: f64 = 1e-5;

// A loop of three is emitted without the degeneracy check (see
// `polygonize`): that needs √3·EDGE_EPS² > MIN_TWICE_AREA_REL.
const _: () = assert!(
    3.0 * EDGE_EPS * EDGE_EPS * EDGE_EPS * EDGE_EPS > MIN_TWICE_AREA_REL * MIN_TWICE_AREA_REL
);

/// Corner `c` of a cell sits at offset `(c & 1, c >> 1 & 1, c >> 2 & 1)`.
pub(crate) const CORNER_OFFSETS: [[i32; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
];

/// Edge `e`: (lower corner, axis). Edges 0..4 run along x, 4..8 along y,
/// 8..12 along z.
pub(crate) const EDGES: [(u8, u8); 12] = [
    (0, 0),
    (2, 0),
    (4, 0),
    (6, 0),
    (0, 1),
    (1, 1),
    (4, 1),
    (5, 1),
    (0, 2),
    (1, 2),
    (2, 2),
    (3, 2),
];

fn edge_of(a: u8, b: u8) -> u8 {
    let (lo, hi) = (a.min(b), a.max(b));
    let axis = (lo ^ hi).trailing_zeros() as u8;
    EDGES
        .iter()
        .position(|&(c, ax)| c == lo && ax == axis)
        .expect("corners differ in one bit") as u8
}

/// The 6 faces, each as 4 corners counter-clockwise seen from outside.
fn faces() -> [[u8; 4]; 6] {
    let mut out = [[0u8; 4]; 6];
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2u8 {
            let base = side << axis;
            let quad = [0u8, 1 << u, (1 << u) | (1 << v), 1 << v].map(|c| c | base);
            out[axis * 2 + side as usize] = if side == 1 {
                quad
            } else {
                [quad[0], quad[3], quad[2], quad[1]]
            };
        }
    }
    out
}

/// One polygonization of a cell: loops of crossed edges and how to fan
/// each one.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CellCase {
    /// Number of loops.
    pub n_loops: u8,
    /// Length of each loop.
    pub lens: [u8; 4],
    /// Crossed edges of the loops, concatenated, in loop order.
    pub edges: [u8; 12],
    /// Fan apex (index in the loop) per loop, or `u8::MAX` for the centroid fan.
    pub apex: [u8; 4],
}

struct Tables {
    /// `[config * 64 + face_mask]`.
    cases: Vec<CellCase>,
    /// Per config: the faces that are ambiguous (bit f) and, per face, the
    /// two inside and two outside corners.
    ambiguous: Vec<u8>,
    face_diag: [[u8; 4]; 6],
}

fn tables() -> &'static Tables {
    static T: OnceLock<Tables> = OnceLock::new();
    T.get_or_init(build_tables)
}

fn build_tables() -> Tables {
    let faces = faces();
    // Which faces each edge lies on.
    let mut edge_faces = [0u8; 12];
    for (f, quad) in faces.iter().enumerate() {
        for i in 0..4 {
            edge_faces[edge_of(quad[i], quad[(i + 1) % 4]) as usize] |= 1 << f;
        }
    }
    let mut cases = vec![CellCase::default(); 256 * 64];
    let mut ambiguous = vec![0u8; 256];
    for config in 0..256usize {
        let inside = |c: u8| config >> c & 1 == 1;
        for (f, quad) in faces.iter().enumerate() {
            let s: Vec<bool> = quad.iter().map(|&c| inside(c)).collect();
            if s[0] == s[2] && s[1] == s[3] && s[0] != s[1] {
                ambiguous[config] |= 1 << f;
            }
        }
        for mask in 0..64usize {
            if mask & !(ambiguous[config] as usize) != 0 {
                continue;
            }
            // next[e] = the edge the directed segment from e leads to.
            let mut next = [u8::MAX; 12];
            for (f, quad) in faces.iter().enumerate() {
                let fe: Vec<u8> = (0..4)
                    .map(|i| edge_of(quad[i], quad[(i + 1) % 4]))
                    .collect();
                let ins: Vec<bool> = quad.iter().map(|&c| inside(c)).collect();
                let exits: Vec<usize> = (0..4).filter(|&i| ins[i] && !ins[(i + 1) % 4]).collect();
                let entries: Vec<usize> = (0..4).filter(|&i| !ins[i] && ins[(i + 1) % 4]).collect();
                match exits.len() {
                    0 => {}
                    1 => next[fe[exits[0]] as usize] = fe[entries[0]],
                    _ => {
                        // Alternating signs; exits at i and i+2.
                        let connected = mask >> f & 1 == 1;
                        for &x in &exits {
                            // Inside connected: cut off the outside corner
                            // after the exit (entry at x+1); else close
                            // around the inside corner (entry at x-1).
                            let entry = if connected { (x + 1) % 4 } else { (x + 3) % 4 };
                            next[fe[x] as usize] = fe[entry];
                        }
                    }
                }
            }
            let mut case = CellCase::default();
            let mut used = [false; 12];
            let mut at = 0usize;
            for start in 0..12u8 {
                if next[start as usize] == u8::MAX || used[start as usize] {
                    continue;
                }
                let begin = at;
                let mut e = start;
                while !used[e as usize] {
                    used[e as usize] = true;
                    case.edges[at] = e;
                    at += 1;
                    e = next[e as usize];
                }
                let lp = &case.edges[begin..at];
                let n = lp.len();
                let l = case.n_loops as usize;
                case.lens[l] = n as u8;
                case.apex[l] = if n == 3 {
                    0
                } else {
                    (0..n)
                        .find(|&a| {
                            (2..n - 1).all(|k| {
                                let b = (a + k) % n;
                                edge_faces[lp[a] as usize] & edge_faces[lp[b] as usize] == 0
                            })
                        })
                        .map_or(u8::MAX, |a| a as u8)
                };
                case.n_loops += 1;
            }
            cases[config * 64 + mask] = case;
        }
    }
    let mut face_diag = [[0u8; 4]; 6];
    for (f, quad) in faces.iter().enumerate() {
        face_diag[f] = *quad;
    }
    Tables {
        cases,
        ambiguous,
        face_diag,
    }
}

/// The cell's inside-corner bitmask.
#[inline]
pub(crate) fn config_of(v: &[f32; 8]) -> usize {
    let mut c = 0usize;
    for (i, x) in v.iter().enumerate() {
        c |= ((*x < 0.0) as usize) << i;
    }
    c
}

/// The polygonization of a cell with samples `v` (config must be 1..=254).
#[inline]
pub(crate) fn cell_case(config: usize, v: &[f32; 8]) -> &'static CellCase {
    let t = tables();
    let amb = t.ambiguous[config];
    let mut mask = 0usize;
    if amb != 0 {
        for f in 0..6 {
            if amb >> f & 1 == 1 {
                let q = t.face_diag[f];
                // q0, q2 share a sign, as do q1, q3.
                let p02 = v[q[0] as usize] as f64 * v[q[2] as usize] as f64;
                let p13 = v[q[1] as usize] as f64 * v[q[3] as usize] as f64;
                let (pin, pout) = if v[q[0] as usize] < 0.0 {
                    (p02, p13)
                } else {
                    (p13, p02)
                };
                if pin > pout {
                    mask |= 1 << f;
                }
            }
        }
    }
    &t.cases[config * 64 + mask]
}

/// The position of the crossing on the grid edge from sample `lo` (global
/// index) along `axis`, with samples `va` (at `lo`) and `vb`.
#[inline]
pub(crate) fn edge_vertex(lo: [i32; 3], axis: usize, va: f32, vb: f32, step: f64) -> [f64; 3] {
    let (a, b) = (va as f64, vb as f64);
    let t = (a / (a - b)).clamp(EDGE_EPS, 1.0 - EDGE_EPS);
    let mut p = [lo[0] as f64, lo[1] as f64, lo[2] as f64];
    p[axis] += t;
    [p[0] * step, p[1] * step, p[2] * step]
}

/// A vertex's identity: a grid edge (`kind` = axis 0..3) or a cell centroid
/// (`kind` = 3 + loop index), at global sample/cell index `at`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct VertKey {
    pub at: [i32; 3],
    pub kind: u8,
}

impl std::hash::Hash for VertKey {
    #[inline]
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        // One word: collisions only cost a probe, equality stays exact.
        let [x, y, z] = self.at.map(|c| c as u32 as u64 & 0x1f_ffff);
        state.write_u64(x | y << 21 | z << 42 | (self.kind as u64) << 61);
    }
}

/// Receives the output of [`polygonize`].
pub(crate) trait MeshSink {
    /// Index of the vertex `key`, created at `pos` if new.
    fn vertex(&mut self, key: VertKey, pos: impl FnOnce() -> [f64; 3]) -> u32;
    /// Index of a fresh vertex (a centroid, owned by one cell).
    fn fresh(&mut self, key: VertKey, pos: [f64; 3]) -> u32;
    /// The position of vertex `id`.
    fn position(&self, id: u32) -> [f64; 3];
    /// Whether [`Self::feature_apex`] may find a feature point (when not,
    /// the loops are not even looked at for one).
    fn keeps_features(&self) -> bool {
        true
    }
    /// The fan vertex for a single-loop cell on a sharp feature (see
    /// [`super::features`]), or `None` for the plain fan.
    fn feature_apex(&mut self, _cell: [i32; 3], _loop_points: &[[f64; 3]]) -> Option<[f64; 3]> {
        None
    }
    /// Emits a triangle of a feature fan (apex first), counter-clockwise
    /// seen from outside.
    fn feature_triangle(&mut self, t: [u32; 3]) {
        self.triangle(t)
    }
    /// Emits a triangle, counter-clockwise seen from outside.
    fn triangle(&mut self, t: [u32; 3]);
}

/// The squared norm of twice the triangle's area vector (compared against
/// the squared threshold: no square root per fan triangle).
fn twice_area_sq(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let x = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
}

/// Polygonizes the cell whose lower corner is global sample `cell`, with
/// corner samples `v`. Does nothing for cells without a crossing.
#[inline]
pub(crate) fn polygonize<S: MeshSink>(cell: [i32; 3], v: &[f32; 8], step: f64, sink: &mut S) {
    let config = config_of(v);
    if config == 0 || config == 255 {
        return;
    }
    polygonize_config(cell, v, config, step, sink)
}

/// [`polygonize`] given the cell's inside-corner bitmask (1..=254), as a
/// caller that classified the cells already knows it.
#[inline]
pub(crate) fn polygonize_config<S: MeshSink>(
    cell: [i32; 3],
    v: &[f32; 8],
    config: usize,
    step: f64,
    sink: &mut S,
) {
    debug_assert_eq!(config, config_of(v));
    let case = cell_case(config, v);
    let mut ids = [0u32; 12];
    let mut pos = [[0.0f64; 3]; 12];
    for (k, &e) in case.edges[..case.lens[..case.n_loops as usize]
        .iter()
        .map(|&l| l as usize)
        .sum::<usize>()]
        .iter()
        .enumerate()
    {
        let (c, axis) = EDGES[e as usize];
        let off = CORNER_OFFSETS[c as usize];
        let lo = [cell[0] + off[0], cell[1] + off[1], cell[2] + off[2]];
        let (va, vb) = (v[c as usize], v[(c | (1 << axis)) as usize]);
        // Computed only by the first cell that meets the vertex.
        let id = sink.vertex(VertKey { at: lo, kind: axis }, || {
            edge_vertex(lo, axis as usize, va, vb, step)
        });
        ids[k] = id;
    }
    let min_area = MIN_TWICE_AREA_REL * step * step;
    let min_area_sq = min_area * min_area;
    // Loops across a bent field may sit on a sharp feature: each is fanned
    // around its feature point when the sink finds one. With several loops
    // (two sheets in one cell, as on a thin wall's rim) each point must be
    // nearer its own loop than any other, so the fans stay apart.
    let mut apex: [Option<[f64; 3]>; 4] = [None; 4];
    if sink.keeps_features() && super::features::nonlinear(v, step) {
        let mut centroids = [[0.0f64; 3]; 4];
        let mut begin = 0usize;
        for l in 0..case.n_loops as usize {
            let n = case.lens[l] as usize;
            for (k, &id) in ids[begin..begin + n].iter().enumerate() {
                pos[k] = sink.position(id);
            }
            let c = pos[..n]
                .iter()
                .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
            centroids[l] = c.map(|x| x / n as f64);
            apex[l] = sink.feature_apex(cell, &pos[..n]);
            begin += n;
        }
        let d2 =
            |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum::<f64>();
        for l in 0..case.n_loops as usize {
            if let Some(x) = apex[l] {
                let own = d2(x, centroids[l]);
                if (0..case.n_loops as usize).any(|m| m != l && d2(x, centroids[m]) <= own) {
                    apex[l] = None;
                }
            }
        }
    }
    let mut begin = 0usize;
    for (l, feature) in apex.iter().enumerate().take(case.n_loops as usize) {
        let n = case.lens[l] as usize;
        let lid = &ids[begin..begin + n];
        // Triangles are emitted against the loop direction: loops run
        // counter-clockwise around the inside seen from outside the cube,
        // so reversing makes the normals point out of the solid.
        if let Some(x) = *feature {
            fan_around(sink, cell, l, lid, x, true);
            begin += n;
            continue;
        }
        if n == 3 {
            // A loop of three cuts off one corner: its vertices lie on the
            // corner's three edges at least EDGE_EPS from it, so twice its
            // area is at least √3·EDGE_EPS² step² (2.6e-5 step²), above
            // the degeneracy threshold: no check needed.
            sink.triangle([lid[0], lid[2], lid[1]]);
            begin += n;
            continue;
        }
        for (k, &id) in lid.iter().enumerate() {
            pos[k] = sink.position(id);
        }
        let lp = &pos[..n];
        let mut fanned = false;
        if case.apex[l] != u8::MAX {
            let a = case.apex[l] as usize;
            let ok = (1..n - 1)
                .all(|k| twice_area_sq(lp[a], lp[(a + k) % n], lp[(a + k + 1) % n]) > min_area_sq);
            if ok {
                for k in 1..n - 1 {
                    sink.triangle([lid[a], lid[(a + k + 1) % n], lid[(a + k) % n]]);
                }
                fanned = true;
            }
        }
        if !fanned {
            let mut c = [0.0; 3];
            for p in lp {
                for d in 0..3 {
                    c[d] += p[d];
                }
            }
            fan_around(sink, cell, l, lid, c.map(|x| x / n as f64), false);
        }
        begin += n;
    }
}

/// Fans loop `l` of `cell` (vertex ids `lid`) around a new vertex at `x`
/// owned by the cell: its centroid, or its feature point (`feature`).
fn fan_around<S: MeshSink>(
    sink: &mut S,
    cell: [i32; 3],
    l: usize,
    lid: &[u32],
    x: [f64; 3],
    feature: bool,
) {
    let key = VertKey {
        at: cell,
        kind: 3 + l as u8,
    };
    let ci = sink.fresh(key, x);
    let n = lid.len();
    for k in 0..n {
        let t = [ci, lid[(k + 1) % n], lid[k]];
        if feature {
            sink.feature_triangle(t);
        } else {
            sink.triangle(t);
        }
    }
}

/// A mesh under construction with vertices deduplicated by [`VertKey`].
#[derive(Default)]
pub(crate) struct KeyedMesh {
    pub map: std::collections::HashMap<VertKey, u32, BuildKeyHasher>,
    pub keys: Vec<VertKey>,
    pub positions: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl MeshSink for KeyedMesh {
    #[inline]
    fn vertex(&mut self, key: VertKey, pos: impl FnOnce() -> [f64; 3]) -> u32 {
        let n = self.positions.len() as u32;
        let id = *self.map.entry(key).or_insert(n);
        if id == n {
            self.keys.push(key);
            self.positions.push(pos());
        }
        id
    }
    fn fresh(&mut self, key: VertKey, pos: [f64; 3]) -> u32 {
        let n = self.positions.len() as u32;
        self.map.insert(key, n);
        self.keys.push(key);
        self.positions.push(pos);
        n
    }
    #[inline]
    fn position(&self, id: u32) -> [f64; 3] {
        self.positions[id as usize]
    }
    #[inline]
    fn triangle(&mut self, t: [u32; 3]) {
        self.triangles.push(t);
    }
}

/// A small, fixed (hence deterministic) hasher for [`VertKey`]s.
#[derive(Clone, Copy, Default)]
pub(crate) struct BuildKeyHasher;

impl std::hash::BuildHasher for BuildKeyHasher {
    type Hasher = KeyHasher;
    fn build_hasher(&self) -> KeyHasher {
        KeyHasher(0)
    }
}

/// FxHash-style multiply-rotate hasher.
pub(crate) struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(*b as u64);
        }
    }
    #[inline]
    fn write_u8(&mut self, i: u8) {
        self.write_u64(i as u64);
    }
    #[inline]
    fn write_i32(&mut self, i: i32) {
        self.write_u64(i as u32 as u64);
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        let x = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        self.0 = x ^ (x >> 32);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

/// Extracts the zero level set of a dense grid of `dims` samples
/// (x fastest) at spacing `step`, sample `(i, j, k)` at
/// `origin + step * (i, j, k)`. Samples beyond the grid count as outside,
/// so the result is always closed. Returns positions and triangles.
pub fn extract_dense(
    values: &[f32],
    dims: [usize; 3],
    origin: [f64; 3],
    step: f64,
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    assert_eq!(values.len(), dims[0] * dims[1] * dims[2], "dims mismatch");
    let get = |i: i32, j: i32, k: i32| -> f32 {
        if i < 0
            || j < 0
            || k < 0
            || i as usize >= dims[0]
            || j as usize >= dims[1]
            || k as usize >= dims[2]
        {
            f32::MAX
        } else {
            values[i as usize + dims[0] * (j as usize + dims[1] * k as usize)]
        }
    };
    let mut m = KeyedMesh::default();
    for k in -1..dims[2] as i32 {
        for j in -1..dims[1] as i32 {
            for i in -1..dims[0] as i32 {
                let mut v = [0f32; 8];
                for (c, o) in CORNER_OFFSETS.iter().enumerate() {
                    v[c] = get(i + o[0], j + o[1], k + o[2]);
                }
                polygonize([i, j, k], &v, step, &mut m);
            }
        }
    }
    let positions = m
        .positions
        .iter()
        .map(|p| [p[0] + origin[0], p[1] + origin[1], p[2] + origin[2]])
        .collect();
    (positions, m.triangles)
}
