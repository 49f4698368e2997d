//! Self-intersection detection: a bounding-volume hierarchy over the
//! triangles and exact predicates (Shewchuk's adaptive `orient3d` and
//! `orient2d` from the `robust` crate) for every pair whose boxes touch.
//!
//! A closed oriented 2-manifold can still pass through itself (a GC whose
//! spine bends tighter than its sections, a warp that folds a surface, a
//! union whose rounding to float32 flips a sliver). A slicer then sees two
//! solids where there is one, or none where there is one, so printable
//! means embedded: two triangles may meet only in what they share (a
//! common vertex or a common edge), nothing more.
//!
//! Choices:
//! - **Exact, closed tests.** Two triangles intersect when their closed
//!   point sets meet outside their shared vertices; touching counts (a
//!   vertex resting on another sheet is a zero-thickness contact that a
//!   slicer cannot print either). The predicates are exact for coordinates
//!   whose products neither overflow nor underflow (Shewchuk's predicates
//!   assume both; the float filter in front of them allows for underflow,
//!   [`O3_ABS`]), so the verdict is the same for the same bits on every
//!   machine and thread count. Coordinates beyond
//!   [`MAX_EXACT_COORDINATE`] are not judged (the caller reports them as out
//!   of range first).
//! - **Shared vertices by position**, not index: vertices with identical
//!   coordinates are one vertex here (what a slicer welding an STL sees).
//! - **Pairs by what they share**: an edge (intersect only when folded flat
//!   onto each other), a vertex (the edge opposite the shared vertex of one
//!   meets the other triangle, a short argument in [`shares_vertex`]), or
//!   nothing (one of the six edges meets the other triangle).
//! - **BVH**: median split on the longest axis of the centroid box, down
//!   to leaves of up to [`LEAF`] triangles. The tree is
//!   walked against itself (each overlapping pair of nodes once) in
//!   tasks on rayon's pool, each pair of triangles tested by one task,
//!   and the pairs found are sorted, so the report does not depend on
//!   the thread count.
//! - **Fast, exact signs**: a triangle's plane is set up once per pair and
//!   each corner's side of it is a dot product checked against
//!   Shewchuk's error bound; only what that cannot settle runs the
//!   adaptive predicate ([`Plane`]).
//!
//! Written here rather than taken from `manifold-rust`'s robust engine
//! (`Manifold::has_self_intersections`), which answers yes/no for a whole
//! manifold it has accepted; printing needs the pairs (to name the objects
//! they came from) and a verdict on meshes Manifold refuses.

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;
use robust::{orient2d, orient3d, Coord, Coord3D};

use super::TriMesh;

/// Triangles per BVH leaf.
const LEAF: usize = 4;

/// Largest coordinate magnitude judged exactly (the predicates multiply
/// three differences; beyond this they could overflow).
pub const MAX_EXACT_COORDINATE: f64 = 1e90;

/// Pairs of triangles that intersect, as found by [`self_intersections`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SelfIntersections {
    /// Every intersecting pair `(i, j)`, `i < j`, sorted.
    pub pairs: Vec<(u32, u32)>,
    /// False when the mesh could not be judged (a non-finite or huge
    /// coordinate, an out-of-range index); `pairs` is then empty.
    pub checked: bool,
}

impl SelfIntersections {
    /// True when the mesh was judged and no pair intersects.
    pub fn is_clear(&self) -> bool {
        self.checked && self.pairs.is_empty()
    }
}

/// Finds every pair of triangles of `mesh` that meet outside the vertices
/// they share. Degenerate triangles (collinear corners) take part as the
/// segments they are.
pub fn self_intersections(mesh: &TriMesh) -> SelfIntersections {
    let n = mesh.positions.len();
    let usable = mesh
        .positions
        .iter()
        .flatten()
        .all(|x| x.is_finite() && x.abs() <= MAX_EXACT_COORDINATE)
        && mesh.triangles.iter().flatten().all(|&i| (i as usize) < n);
    if !usable {
        return SelfIntersections::default();
    }
    if mesh.triangles.len() < 2 {
        return SelfIntersections {
            pairs: Vec::new(),
            checked: true,
        };
    }
    let mut pairs = Ctx::new(mesh).within_par(0);
    pairs.sort_unstable();
    pairs.dedup();
    SelfIntersections {
        pairs,
        checked: true,
    }
}

/// Maps each vertex to the first vertex with bit-identical coordinates.
fn canonical_vertices(pos: &[[f64; 3]]) -> Vec<u32> {
    // The keys sorted with their vertices (keying through `pos` inside
    // the comparison fetched coordinates at random).
    let mut keyed: Vec<([u64; 3], u32)> = pos
        .par_iter()
        .enumerate()
        .map(|(i, p)| (p.map(|x| (x + 0.0).to_bits()), i as u32))
        .collect();
    keyed.par_sort_unstable();
    let mut canon: Vec<u32> = (0..pos.len() as u32).collect();
    for run in keyed.chunk_by(|a, b| a.0 == b.0) {
        let first = run[0].1;
        for &(_, i) in &run[1..] {
            canon[i as usize] = first;
        }
    }
    canon
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    fn of(p: [DVec3; 3]) -> Self {
        Self {
            lo: p[0].min(p[1]).min(p[2]),
            hi: p[0].max(p[1]).max(p[2]),
        }
    }

    fn empty() -> Self {
        Self {
            lo: DVec3::splat(f64::INFINITY),
            hi: DVec3::splat(f64::NEG_INFINITY),
        }
    }

    fn join(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Closed boxes: touching counts.
    fn overlaps(&self, o: &Self) -> bool {
        self.lo.x <= o.hi.x
            && o.lo.x <= self.hi.x
            && self.lo.y <= o.hi.y
            && o.lo.y <= self.hi.y
            && self.lo.z <= o.hi.z
            && o.lo.z <= self.hi.z
    }
}

/// A node, in preorder: an inner node `n` has `count == 0` and children
/// `n + 1` and `first`; a leaf holds `order[first..first + count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
}

struct Bvh {
    nodes: Vec<Node>,
    /// Triangles below each node (`size[n]`), to split work by it.
    size: Vec<u32>,
    order: Vec<u32>,
}

impl Bvh {
    /// Median split on the longest axis of the box centres, down to leaves
    /// of up to [`LEAF`]; each node's box is the join of its children's.
    /// The split works on (centre, triangle) pairs moved in place, so each
    /// level reads memory in order, and the two halves of a big node are
    /// built in parallel into their own ranges of the preorder node array
    /// (a subtree's node count depends only on its triangle count, so the
    /// layout does not depend on the threads). It used to select through
    /// centres fetched at random on one thread: 40% of the search on a
    /// 1M-triangle sphere (issue 37).
    fn build(boxes: &[Aabb]) -> Self {
        let mut items: Vec<(DVec3, u32)> = boxes
            .par_iter()
            .enumerate()
            .map(|(i, b)| ((b.lo + b.hi) * 0.5, i as u32))
            .collect();
        let mut counts = HashMap::new();
        let total = tree_nodes(items.len(), &mut counts);
        let blank = Node {
            bounds: Aabb::empty(),
            first: 0,
            count: 0,
        };
        let mut nodes = vec![blank; total];
        let mut size = vec![0u32; total];
        let at = Subtree {
            base: 0,
            start: 0,
            counts: &counts,
            boxes,
        };
        at.build(&mut nodes, &mut size, &mut items);
        let order = items.into_iter().map(|(_, i)| i).collect();
        Self { nodes, size, order }
    }

    /// Of two nodes, not both leaves: the one to split (the bigger, an
    /// inner node before a leaf) and the other.
    fn bigger(&self, m: u32, n: u32) -> (u32, u32) {
        let (a, b) = (self.nodes[m as usize], self.nodes[n as usize]);
        if b.count > 0 || (a.count == 0 && self.size[m as usize] >= self.size[n as usize]) {
            (m, n)
        } else {
            (n, m)
        }
    }

    /// The children of inner node `n`.
    fn kids(&self, n: u32) -> (u32, u32) {
        (n + 1, self.nodes[n as usize].first)
    }
}

/// Nodes in a tree over `n` triangles (halving down to [`LEAF`]),
/// memoized in `counts` for every size met on the way.
fn tree_nodes(n: usize, counts: &mut HashMap<usize, usize>) -> usize {
    if n <= LEAF {
        return 1;
    }
    if let Some(&c) = counts.get(&n) {
        return c;
    }
    let c = 1 + tree_nodes(n / 2, counts) + tree_nodes(n - n / 2, counts);
    counts.insert(n, c);
    c
}

/// Where a subtree goes: its root's index in the node array and its first
/// triangle's in the order.
#[derive(Clone, Copy)]
struct Subtree<'a> {
    base: usize,
    start: usize,
    counts: &'a HashMap<usize, usize>,
    boxes: &'a [Aabb],
}

/// Above this many triangles the two halves of a node build in parallel.
const PARALLEL_BUILD: usize = 16_384;

impl Subtree<'_> {
    /// Fills `nodes` (this subtree's range, root first) for `items` and
    /// returns the root's box.
    fn build(self, nodes: &mut [Node], size: &mut [u32], items: &mut [(DVec3, u32)]) -> Aabb {
        let n = items.len();
        size[0] = n as u32;
        if n <= LEAF {
            let bounds = items.iter().fold(Aabb::empty(), |acc, &(_, t)| {
                acc.join(self.boxes[t as usize])
            });
            nodes[0] = Node {
                bounds,
                first: self.start as u32,
                count: n as u32,
            };
            return bounds;
        }
        let (lo, hi) = items.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &(c, _)| (lo.min(c), hi.max(c)),
        );
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = n / 2;
        items.select_nth_unstable_by(mid, |a, b| {
            a.0[axis].total_cmp(&b.0[axis]).then(a.1.cmp(&b.1))
        });
        let left_nodes = if mid <= LEAF { 1 } else { self.counts[&mid] };
        let (root, rest) = nodes.split_at_mut(1);
        let (ln, rn) = rest.split_at_mut(left_nodes);
        let (_, rest_size) = size.split_at_mut(1);
        let (ls, rs) = rest_size.split_at_mut(left_nodes);
        let (li, ri) = items.split_at_mut(mid);
        let left = Subtree {
            base: self.base + 1,
            ..self
        };
        let right = Subtree {
            base: self.base + 1 + left_nodes,
            start: self.start + mid,
            ..self
        };
        let (lb, rb) = if n > PARALLEL_BUILD {
            rayon::join(|| left.build(ln, ls, li), || right.build(rn, rs, ri))
        } else {
            (left.build(ln, ls, li), right.build(rn, rs, ri))
        };
        let bounds = lb.join(rb);
        root[0] = Node {
            bounds,
            first: right.base as u32,
            count: 0,
        };
        bounds
    }
}

/// The search's inputs, indexed by position in the BVH's order.
struct Ctx {
    /// Corners as canonical vertex indices (shared corners compare equal).
    tris: Vec<[u32; 3]>,
    corners: Vec<[DVec3; 3]>,
    boxes: Vec<Aabb>,
    bvh: Bvh,
}

/// Below this many triangles a traversal runs on one thread (the split
/// into tasks costs more than it gains).
const SEQUENTIAL: u32 = 2048;

impl Ctx {
    /// Sets up the search over `mesh`, whose coordinates are finite and
    /// indices in range.
    fn new(mesh: &TriMesh) -> Self {
        let canon = canonical_vertices(&mesh.positions);
        let corners = |t: &[u32; 3]| t.map(|i| DVec3::from_array(mesh.positions[i as usize]));
        let boxes: Vec<Aabb> = mesh
            .triangles
            .par_iter()
            .map(|t| Aabb::of(corners(t)))
            .collect();
        let bvh = Bvh::build(&boxes);
        drop(boxes);
        // Everything the pair tests read, in the BVH's order: a leaf's
        // triangles and its neighbours' are then near in memory (fetching
        // corners through the index buffer at random bound the search).
        // With the BVH, about 170 bytes a triangle while the search runs
        // on a fine mesh, 190 on a coarse one (130 before issue 37's
        // change), beside the topology's 80 when `validate` runs both.
        let corners: Vec<[DVec3; 3]> = bvh
            .order
            .par_iter()
            .map(|&t| corners(&mesh.triangles[t as usize]))
            .collect();
        Self {
            tris: bvh
                .order
                .par_iter()
                .map(|&t| mesh.triangles[t as usize].map(|i| canon[i as usize]))
                .collect(),
            boxes: corners.par_iter().map(|&c| Aabb::of(c)).collect(),
            corners,
            bvh,
        }
    }

    /// Every intersecting pair of triangles below node `n`: the pairs
    /// within each child, and those between the two. Each unordered pair
    /// of triangles is met exactly once (in the one node where they part,
    /// or in their common leaf), and the tree is walked against itself
    /// (each overlapping pair of nodes visited once), not once per leaf
    /// from the root.
    fn within_par(&self, n: u32) -> Vec<(u32, u32)> {
        let bvh = &self.bvh;
        let node = bvh.nodes[n as usize];
        if node.count > 0 || bvh.size[n as usize] <= SEQUENTIAL {
            let mut out = Vec::new();
            self.within(n, &mut out);
            return out;
        }
        let (l, r) = bvh.kids(n);
        let ((mut a, b), c) = rayon::join(
            || rayon::join(|| self.within_par(l), || self.within_par(r)),
            || self.between_par(l, r),
        );
        a.extend(b);
        a.extend(c);
        a
    }

    /// Every intersecting pair with one triangle below `m`, one below `n`.
    fn between_par(&self, m: u32, n: u32) -> Vec<(u32, u32)> {
        let bvh = &self.bvh;
        let (a, b) = (bvh.nodes[m as usize], bvh.nodes[n as usize]);
        if !a.bounds.overlaps(&b.bounds) {
            return Vec::new();
        }
        if bvh.size[m as usize] + bvh.size[n as usize] <= SEQUENTIAL {
            let mut out = Vec::new();
            self.between(m, n, &mut out);
            return out;
        }
        let (split, other) = bvh.bigger(m, n);
        let (l, r) = bvh.kids(split);
        let (mut x, y) = rayon::join(|| self.between_par(l, other), || self.between_par(r, other));
        x.extend(y);
        x
    }

    fn within(&self, n: u32, out: &mut Vec<(u32, u32)>) {
        let bvh = &self.bvh;
        let node = bvh.nodes[n as usize];
        if node.count > 0 {
            let (first, count) = (node.first as usize, node.count as usize);
            for i in first..first + count {
                for j in i + 1..first + count {
                    self.test(i, j, out);
                }
            }
            return;
        }
        let (l, r) = bvh.kids(n);
        self.within(l, out);
        self.within(r, out);
        self.between(l, r, out);
    }

    fn between(&self, m: u32, n: u32, out: &mut Vec<(u32, u32)>) {
        let bvh = &self.bvh;
        let (a, b) = (bvh.nodes[m as usize], bvh.nodes[n as usize]);
        if !a.bounds.overlaps(&b.bounds) {
            return;
        }
        match (a.count > 0, b.count > 0) {
            (true, true) => {
                let (fa, fb) = (a.first as usize, b.first as usize);
                for i in fa..fa + a.count as usize {
                    for j in fb..fb + b.count as usize {
                        self.test(i, j, out);
                    }
                }
            }
            _ => {
                let (split, other) = bvh.bigger(m, n);
                let (l, r) = bvh.kids(split);
                self.between(l, other, out);
                self.between(r, other, out);
            }
        }
    }

    /// Tests the triangles at positions `i` and `j` of the BVH's order.
    #[inline]
    /// The pair is judged with the lower original index first, whatever
    /// the order the walk met them in: a verdict then depends on the mesh
    /// alone, not on the tree (a collinear case's float test of where a
    /// corner lies along the shared edge is not symmetric).
    fn test(&self, i: usize, j: usize, out: &mut Vec<(u32, u32)>) {
        if self.boxes[i].overlaps(&self.boxes[j]) {
            let (a, b) = (self.bvh.order[i], self.bvh.order[j]);
            let hit = if a < b {
                self.pair_intersects(i, j)
            } else {
                self.pair_intersects(j, i)
            };
            if hit {
                out.push((a.min(b), a.max(b)));
            }
        }
    }

    /// Triangles at positions `a` and `b` of the BVH's order.
    fn pair_intersects(&self, a: usize, b: usize) -> bool {
        let ta = self.tris[a];
        let tb = self.tris[b];
        // The corners the two share, as (corner of a, corner of b).
        let mut shared = [(0usize, 0usize); 9];
        let mut count = 0;
        for (i, va) in ta.iter().enumerate() {
            for (j, vb) in tb.iter().enumerate() {
                if va == vb {
                    shared[count] = (i, j);
                    count += 1;
                }
            }
        }
        let (pa, pb) = (self.corners[a], self.corners[b]);
        match count {
            0 => triangles_meet(pa, pb),
            1 => {
                let (i, j) = shared[0];
                shares_vertex(pa, i, pb, j)
            }
            // Two shared corners on distinct corners of both: a shared edge.
            2 if shared[0].0 != shared[1].0 && shared[0].1 != shared[1].1 => {
                // The corners not on the shared edge.
                let ia = 3 - shared[0].0 - shared[1].0;
                let ib = 3 - shared[0].1 - shared[1].1;
                let (e0, e1) = (pa[shared[0].0], pa[shared[1].0]);
                folded_onto(e0, e1, pa[ia], pb[ib])
            }
            // The same triangle twice, or a degenerate one repeating a
            // vertex (found by the mesh-reader fuzz test: two shared pairs
            // on one corner): coincident sheets.
            _ => true,
        }
    }
}

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

fn o3(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

/// `sign(orient3d(a, b, c, d))`, exactly, settled in line by the float
/// filter of [`Plane::side`] when it can be.
#[inline]
fn o3_sign(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i8 {
    Plane::of([a, b, c]).side(d)
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Shewchuk's error bound for the first, floating-point stage of
/// `orient3d`: `(7 + 56ε)ε` with ε = 2⁻⁵³ ("Adaptive Precision
/// Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997,
/// §4.3; the `robust` crate's `o3derrboundA`).
const O3_ERR: f64 = (7.0 + 56.0 * (f64::EPSILON / 2.0)) * (f64::EPSILON / 2.0);

/// What underflow can add to that bound, which assumes none (as
/// Shewchuk's does). A 2×2 product of the plane's edge vectors that
/// underflows is off by up to 2⁻¹⁰⁷⁵ absolutely, not relatively, and is
/// then multiplied by a component of `q − a`, up to 2·[`MAX_EXACT_COORDINATE`]:
/// six such products add at most 6 · 2⁻¹⁰⁷⁵ · 2e90 ≈ 3e-233, and the
/// later products' own underflow far less. A value within this of zero
/// goes to the adaptive predicate (the review of issue 37's change found
/// the plane (0, 2⁻⁵⁴⁰, 0), (1, 0, 0.75·2⁻⁵³⁵) through the origin and the
/// point (2²⁸⁰, 0, 2⁻²⁵⁶), whose sign a relative bound alone gets wrong).
const O3_ABS: f64 = 1e-220;

/// A triangle's plane, set up once per pair so that each side test is a
/// dot product: the sign of `orient3d(a, b, c, q)`, exact.
///
/// `orient3d(a, b, c, q) = (a − q)·((b − q) × (c − q)) = −(q − a)·((b − a) ×
/// (c − a))`, and the right-hand form has the structure Shewchuk's bound is
/// proved for (three differences of inputs, the 2×2 minors of two of them,
/// each times a component of the third, summed), so [`O3_ERR`] times its
/// permanent bounds its rounding error as it bounds `orient3d`'s first
/// stage, and [`O3_ABS`] what underflow adds. Only a test the float value cannot settle (a point on or within
/// rounding of the plane) runs the adaptive predicate; on a printable
/// mesh that is almost none (issue 37: `orient3d`'s call, with its cross
/// product recomputed for every point, was a quarter of the search).
struct Plane {
    t: [DVec3; 3],
    /// `(b − a) × (c − a)`, rounded.
    n: DVec3,
    /// The absolute 2×2 minors: `|u_y v_z| + |u_z v_y|`, …
    m: DVec3,
}

impl Plane {
    fn of(t: [DVec3; 3]) -> Self {
        let u = t[1] - t[0];
        let v = t[2] - t[0];
        Self {
            t,
            n: DVec3::new(
                u.y * v.z - u.z * v.y,
                u.z * v.x - u.x * v.z,
                u.x * v.y - u.y * v.x,
            ),
            m: DVec3::new(
                (u.y * v.z).abs() + (u.z * v.y).abs(),
                (u.z * v.x).abs() + (u.x * v.z).abs(),
                (u.x * v.y).abs() + (u.y * v.x).abs(),
            ),
        }
    }

    /// `sign(orient3d(a, b, c, q))`, exactly.
    #[inline]
    fn side(&self, q: DVec3) -> i8 {
        let w = q - self.t[0];
        let det = w.x * self.n.x + w.y * self.n.y + w.z * self.n.z;
        let perm = w.x.abs() * self.m.x + w.y.abs() * self.m.y + w.z.abs() * self.m.z;
        let bound = O3_ERR * perm + O3_ABS;
        if det > bound {
            return -1;
        }
        if -det > bound {
            return 1;
        }
        // Four points with one coordinate equal lie in that axis plane:
        // exactly zero, which the adaptive predicate reaches only through
        // its exact stage (a GC mesh's flat caps and rims: 58,484 such
        // calls in the teapot's search, every one of them zero).
        if (0..3).any(|k| self.t.iter().all(|p| p[k] == q[k])) {
            return 0;
        }
        sign(o3(self.t[0], self.t[1], self.t[2], q))
    }
}

/// Two triangles sharing the edge `e0 e1`, with other corners `c` and `d`,
/// overlap beyond the edge exactly when they are coplanar and on the same
/// side of it (folded flat onto each other).
fn folded_onto(e0: DVec3, e1: DVec3, c: DVec3, d: DVec3) -> bool {
    if o3_sign(e0, e1, c, d) != 0 {
        return false;
    }
    let (u, v) = project_axes(e0, e1, c)
        .or_else(|| project_axes(e0, e1, d))
        .unwrap_or((0, 1));
    let s = |p: DVec3| sign(orient2d(c2(e0, u, v), c2(e1, u, v), c2(p, u, v)));
    let (sc, sd) = (s(c), s(d));
    // A degenerate triangle (its corner on the edge's line) overlaps the
    // other along the edge when that corner lies inside the edge.
    if sc == 0 || sd == 0 {
        let inside = |p: DVec3| {
            let t = (p - e0).dot(e1 - e0);
            t > 0.0 && t < (e1 - e0).length_squared()
        };
        return (sc == 0 && inside(c)) || (sd == 0 && inside(d));
    }
    sc == sd
}

/// Triangles `pa` and `pb` sharing exactly the corner `pa[i] == pb[j]`.
///
/// Their intersection is convex and holds the shared vertex `v`; if it holds
/// another point `q`, the ray from `v` through `q` leaves each triangle on
/// the edge opposite `v`, at `p1` and `p2`. The nearer of the two lies on
/// both triangles, so the opposite edge of one meets the other. Conversely
/// such a meeting point is not `v` (it lies on an edge not holding `v`).
fn shares_vertex(pa: [DVec3; 3], i: usize, pb: [DVec3; 3], j: usize) -> bool {
    let (a1, a2) = (pa[(i + 1) % 3], pa[(i + 2) % 3]);
    let (b1, b2) = (pb[(j + 1) % 3], pb[(j + 2) % 3]);
    let (plane_a, plane_b) = (Plane::of(pa), Plane::of(pb));
    segment_meets_triangle(a1, a2, plane_b.side(a1), plane_b.side(a2), &plane_b)
        || segment_meets_triangle(b1, b2, plane_a.side(b1), plane_a.side(b2), &plane_a)
}

/// Closed triangles with no shared vertex meet exactly when one of the six
/// edges meets the other triangle (the intersection of two triangles, when
/// not empty, has a point on the boundary of one of them inside the other).
fn triangles_meet(pa: [DVec3; 3], pb: [DVec3; 3]) -> bool {
    let (plane_a, plane_b) = (Plane::of(pa), Plane::of(pb));
    // Each corner's side of the other's plane, computed once.
    let sa = pa.map(|q| plane_b.side(q));
    let sb = pb.map(|q| plane_a.side(q));
    // Quick rejects: one triangle strictly on one side of the other's plane.
    let apart =
        |s: [i8; 3]| (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
    if apart(sa) || apart(sb) {
        return false;
    }
    (0..3).any(|k| {
        let l = (k + 1) % 3;
        segment_meets_triangle(pa[k], pa[l], sa[k], sa[l], &plane_b)
    }) || (0..3).any(|k| {
        let l = (k + 1) % 3;
        segment_meets_triangle(pb[k], pb[l], sb[k], sb[l], &plane_a)
    })
}

/// The closed segment `p q` meets the closed triangle of `plane`, given
/// the sides `sp`, `sq` of `p` and `q` ([`Plane::side`]).
fn segment_meets_triangle(p: DVec3, q: DVec3, sp: i8, sq: i8, plane: &Plane) -> bool {
    let t = plane.t;
    let [a, b, c] = t;
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        return coplanar_segment_meets_triangle(p, q, t);
    }
    // The segment reaches the plane; its line passes through the closed
    // triangle exactly when the three edge orientations agree in sign.
    let s1 = o3_sign(p, q, a, b);
    let s2 = o3_sign(p, q, b, c);
    let s3 = o3_sign(p, q, c, a);
    let pos = s1 >= 0 && s2 >= 0 && s3 >= 0;
    let neg = s1 <= 0 && s2 <= 0 && s3 <= 0;
    if pos || neg {
        // All three zero: the triangle is degenerate and its line passes
        // through `p q`'s line; judge it as a segment.
        if s1 == 0 && s2 == 0 && s3 == 0 {
            return coplanar_segment_meets_triangle(p, q, t);
        }
        return true;
    }
    false
}

/// Two coordinates of the plane through three points in which they do not
/// project to a line, if any.
fn project_axes(a: DVec3, b: DVec3, c: DVec3) -> Option<(usize, usize)> {
    let n = (b - a).cross(c - a).abs();
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&x, &y| n[y].total_cmp(&n[x]));
    for drop in axes {
        let (u, v) = match drop {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        };
        if orient2d(c2(a, u, v), c2(b, u, v), c2(c, u, v)) != 0.0 {
            return Some((u, v));
        }
    }
    None
}

fn c2(p: DVec3, u: usize, v: usize) -> Coord<f64> {
    Coord { x: p[u], y: p[v] }
}

/// Segment and triangle in one plane (or a degenerate triangle).
fn coplanar_segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let axes = project_axes(a, b, c)
        .or_else(|| project_axes(a, b, p))
        .or_else(|| project_axes(a, b, q))
        .or_else(|| project_axes(b, c, p))
        .or_else(|| project_axes(b, c, q))
        .or_else(|| project_axes(a, c, p))
        .or_else(|| project_axes(a, c, q));
    let Some((u, v)) = axes else {
        // Everything on one line: compare as 1D intervals.
        return collinear_overlap(p, q, t);
    };
    let o = |x: DVec3, y: DVec3, z: DVec3| sign(orient2d(c2(x, u, v), c2(y, u, v), c2(z, u, v)));
    let tri_area = o(a, b, c);
    if tri_area != 0 {
        let inside = |x: DVec3| {
            let (s1, s2, s3) = (o(a, b, x), o(b, c, x), o(c, a, x));
            (s1 * tri_area >= 0) && (s2 * tri_area >= 0) && (s3 * tri_area >= 0)
        };
        if inside(p) || inside(q) {
            return true;
        }
    }
    let seg_meet = |p1: DVec3, p2: DVec3, q1: DVec3, q2: DVec3| {
        let d1 = o(q1, q2, p1);
        let d2 = o(q1, q2, p2);
        let d3 = o(p1, p2, q1);
        let d4 = o(p1, p2, q2);
        if d1 * d2 < 0 && d3 * d4 < 0 {
            return true;
        }
        let on = |x: DVec3, y: DVec3, z: DVec3| {
            let (lo, hi) = (x.min(y), x.max(y));
            z[u] >= lo[u] && z[u] <= hi[u] && z[v] >= lo[v] && z[v] <= hi[v]
        };
        (d1 == 0 && on(q1, q2, p1))
            || (d2 == 0 && on(q1, q2, p2))
            || (d3 == 0 && on(p1, p2, q1))
            || (d4 == 0 && on(p1, p2, q2))
    };
    seg_meet(p, q, a, b) || seg_meet(p, q, b, c) || seg_meet(p, q, c, a)
}

/// All points on one line: the segment's interval meets the triangle's.
fn collinear_overlap(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let pts = [p, q, t[0], t[1], t[2]];
    let lo = pts
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |a, b| a.min(*b));
    let hi = pts
        .iter()
        .fold(DVec3::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
    let ext = hi - lo;
    let k = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let (s0, s1) = (p[k].min(q[k]), p[k].max(q[k]));
    let t0 = t[0][k].min(t[1][k]).min(t[2][k]);
    let t1 = t[0][k].max(t[1][k]).max(t[2][k]);
    s0 <= t1 && t0 <= s1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::tetra;
    use crate::solid::{tessellate, SolidShape};
    use glam::DAffine3;

    fn sphere(r: f64, seg: u32) -> TriMesh {
        tessellate(&SolidShape::Sphere { radius: r }, seg).unwrap()
    }

    /// A unit sphere and a sphere of radius `r` centred at `at`, in one
    /// buffer.
    fn two_spheres(seg: u32, r: f64, at: [f64; 3]) -> TriMesh {
        let mut m = sphere(1.0, seg);
        let mut other = sphere(r, seg);
        other.transform(&DAffine3::from_translation(DVec3::from_array(at)));
        m.append(&other);
        m
    }

    /// `f` run on a pool of `threads` threads.
    fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    #[test]
    fn closed_solids_do_not_intersect_themselves() {
        for m in [
            tetra(),
            sphere(1.0, 48),
            tessellate(
                &SolidShape::Torus {
                    major_radius: 1.0,
                    minor_radius: 0.3,
                },
                40,
            )
            .unwrap(),
            tessellate(
                &SolidShape::Box {
                    size: [1.0, 2.0, 3.0],
                },
                16,
            )
            .unwrap(),
        ] {
            let s = self_intersections(&m);
            assert!(s.is_clear(), "{:?}", &s.pairs[..s.pairs.len().min(5)]);
        }
    }

    /// Found by `mesh_io_fuzz`: a degenerate triangle repeating a vertex
    /// next to one sharing that vertex twice over made the shared-edge
    /// arithmetic underflow. Such a pair is reported, never a panic.
    #[test]
    fn a_triangle_repeating_a_vertex_is_reported_not_a_panic() {
        let m = TriMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            triangles: vec![[1, 2, 2], [3, 4, 2], [0, 0, 1], [0, 3, 4]],
            ..TriMesh::default()
        };
        let s = self_intersections(&m);
        assert!(s.checked);
        assert!(!s.is_clear());
    }

    #[test]
    fn two_overlapping_spheres_in_one_buffer_intersect() {
        let m = two_spheres(32, 1.0, [1.0, 0.0, 0.0]);
        let s = self_intersections(&m);
        assert!(s.checked);
        assert!(!s.pairs.is_empty());
        // Every pair has one triangle from each sphere.
        let half = (m.triangles.len() / 2) as u32;
        assert!(s.pairs.iter().all(|&(a, b)| a < half && b >= half));
    }

    #[test]
    fn disjoint_and_touching_copies() {
        let mut m = tetra();
        let mut far = tetra();
        far.transform(&DAffine3::from_translation(DVec3::new(3.0, 0.0, 0.0)));
        m.append(&far);
        assert!(self_intersections(&m).is_clear());
        // A copy moved so that its corner at the origin rests exactly on
        // the first one's face x + y + z = 1, at (0.5, 0.25, 0.25).
        let mut m = tetra();
        let mut touch = tetra();
        touch.transform(&DAffine3::from_translation(DVec3::new(0.5, 0.25, 0.25)));
        m.append(&touch);
        let s = self_intersections(&m);
        assert!(!s.pairs.is_empty(), "a vertex resting on a face touches");
    }

    #[test]
    fn a_fold_across_an_edge_is_found() {
        // Two triangles sharing edge (0,1), folded flat onto one side.
        let m = TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.3, 1.0, 0.0],
                [0.6, 0.5, 0.0],
            ],
            vec![[0, 1, 2], [1, 0, 3]],
        );
        assert_eq!(self_intersections(&m).pairs, vec![(0, 1)]);
        // Unfolded: the second corner on the other side.
        let mut flat = m.clone();
        flat.positions[3] = [0.6, -0.5, 0.0];
        assert!(self_intersections(&flat).is_clear());
        // Bent out of the plane by the smallest step: clear.
        let mut bent = m.clone();
        bent.positions[3] = [0.6, 0.5, f64::MIN_POSITIVE];
        assert!(self_intersections(&bent).is_clear());
    }

    #[test]
    fn a_vertex_sharing_crossing_is_found() {
        // Fan at the origin: the second triangle pierces the first.
        let m = TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 2.0, 0.0],
                [1.0, 1.0, -1.0],
                [0.2, 0.2, 1.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(self_intersections(&m).pairs, vec![(0, 1)]);
        // Lift the piercing triangle off the plane: clear.
        let mut up = m.clone();
        up.positions[3] = [1.0, 1.0, 0.5];
        assert!(self_intersections(&up).is_clear());
        // Coplanar, overlapping wedges at the shared vertex.
        let m = TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 2.0, 0.0],
                [1.0, 0.2, 0.0],
                [1.0, 0.5, 0.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(self_intersections(&m).pairs, vec![(0, 1)]);
    }

    #[test]
    fn coincident_vertices_count_as_shared() {
        // The tetrahedron with vertex 0 duplicated for the last face: still
        // the same surface, no intersection.
        let mut m = tetra();
        m.positions.push([0.0, 0.0, 0.0]);
        m.triangles[3][0] = 4;
        assert!(self_intersections(&m).is_clear());
    }

    #[test]
    fn a_duplicated_triangle_is_found_and_bad_input_is_not_judged() {
        let mut m = tetra();
        m.triangles.push([1, 2, 3]);
        assert_eq!(self_intersections(&m).pairs, vec![(2, 4)]);
        let mut nan = tetra();
        nan.positions[0][0] = f64::NAN;
        assert!(!self_intersections(&nan).checked);
        let mut oob = tetra();
        oob.triangles[0][0] = 99;
        assert!(!self_intersections(&oob).checked);
    }

    /// A triangle soup of `n` small triangles in the unit cube, corners on
    /// a grid of `grid` steps (so corners are shared and faces coplanar
    /// often, as in a mesh), from a fixed seed.
    fn soup(n: usize, grid: u32, seed: u64) -> TriMesh {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as u32
        };
        let g = f64::from(grid);
        let mut m = TriMesh::default();
        for _ in 0..n {
            let base = [next() % grid, next() % grid, next() % grid];
            let first = m.positions.len() as u32;
            for _ in 0..3 {
                let p = base.map(|b| f64::from((b + next() % 3).min(grid)) / g);
                m.positions.push(p);
            }
            m.triangles.push([first, first + 1, first + 2]);
        }
        m
    }

    /// The tree walked against itself reports exactly the pairs that testing
    /// every pair of triangles reports, on one thread and two, with enough
    /// triangles to split the walk into parallel tasks.
    #[test]
    fn the_tree_walk_meets_every_pair_once() {
        let spheres = two_spheres(40, 0.8, [0.7, 0.2, 0.1]);
        for (name, m) in [
            ("soup", soup(2600, 40, 7)),
            ("coarse soup", soup(600, 6, 11)),
            ("two spheres", spheres),
        ] {
            let n = m.triangles.len();
            assert!(
                n > SEQUENTIAL as usize || name == "coarse soup",
                "{name}: {n}"
            );
            let ctx = Ctx::new(&m);
            let mut every = Vec::new();
            for i in 0..m.triangles.len() {
                for j in i + 1..m.triangles.len() {
                    ctx.test(i, j, &mut every);
                }
            }
            every.sort_unstable();
            assert!(!every.is_empty(), "{name}");
            for threads in [1, 2] {
                // Not deduplicated: a pair met twice would show.
                let mut walked = on_threads(threads, || ctx.within_par(0));
                walked.sort_unstable();
                assert_eq!(walked, every, "{name} on {threads} threads");
                let found = on_threads(threads, || self_intersections(&m));
                assert_eq!(found.pairs, every, "{name} on {threads} threads");
            }
        }
    }

    /// Above [`PARALLEL_BUILD`] triangles the BVH's halves build in
    /// parallel into fixed ranges: the tree is the same on one thread and
    /// two, and the parallel walk finds what one thread's walk finds.
    #[test]
    fn a_big_tree_is_the_same_on_one_and_two_threads() {
        let m = two_spheres(96, 0.8, [0.7, 0.2, 0.1]);
        assert!(m.triangles.len() > PARALLEL_BUILD, "{}", m.triangles.len());
        let on = |threads| {
            on_threads(threads, || {
                let ctx = Ctx::new(&m);
                let mut walked = ctx.within_par(0);
                walked.sort_unstable();
                (ctx, walked)
            })
        };
        let ((one, walked_one), (two, walked_two)) = (on(1), on(2));
        assert_eq!(one.bvh.order, two.bvh.order);
        assert_eq!(one.bvh.size, two.bvh.size);
        assert_eq!(one.bvh.nodes, two.bvh.nodes);
        let mut sequential = Vec::new();
        one.within(0, &mut sequential);
        sequential.sort_unstable();
        assert!(!sequential.is_empty());
        assert_eq!(walked_one, sequential);
        assert_eq!(walked_two, sequential);
    }

    /// Found by the review of issue 37's change: a 2×2 product of the
    /// plane's edges underflows while the point is far away, and the
    /// relative bound alone trusted a float value of the wrong sign.
    #[test]
    fn an_underflowing_plane_is_judged_exactly() {
        let p2 = |e: i32| f64::from_bits(((1023 + e) as u64) << 52);
        let a = DVec3::ZERO;
        let b = DVec3::new(0.0, p2(-540), 0.0);
        let c = DVec3::new(1.0, 0.0, 0.75 * p2(-535));
        let q = DVec3::new(p2(280), 0.0, p2(-256));
        // −1.2e-240 in exact rational arithmetic; the float value of the
        // same expression is +2.4e-240 (one product of the plane's edges
        // rounds to zero).
        assert_eq!(sign(o3(a, b, c, q)), -1, "orient3d's own sign");
        assert_eq!(Plane::of([a, b, c]).side(q), -1);
    }

    proptest::proptest! {
        /// [`Plane::side`] is the exact sign of `orient3d`, also for a point
        /// within rounding of the plane, where the float value alone has
        /// the wrong sign about half the time.
        #[test]
        fn the_filtered_side_is_the_exact_sign(
            corners in proptest::array::uniform9(-1.0f64..1.0),
            s in -2.0f64..2.0,
            t in -2.0f64..2.0,
            lift in proptest::prop_oneof![proptest::strategy::Just(0.0), -1e-15f64..1e-15, -1.0f64..1.0],
            scale_exp in -20i32..20,
            far in proptest::prop_oneof![proptest::strategy::Just(0.0), -1.0f64..1.0],
        ) {
            let k = f64::from_bits(((1023 + scale_exp) as u64) << 52); // 2^scale_exp
            // Away from the origin (up to 2^20 times the triangle's size),
            // so the differences `b − a`, `q − a` round too.
            let c = corners.map(|x| x * k + far * k * 1048576.0);
            let (a, b, cc) = (
                DVec3::new(c[0], c[1], c[2]),
                DVec3::new(c[3], c[4], c[5]),
                DVec3::new(c[6], c[7], c[8]),
            );
            // A point on the plane up to the rounding of its coordinates,
            // lifted off it by `lift` of the triangle's size (or not).
            let n = (b - a).cross(cc - a).normalize_or_zero();
            let d = a + (b - a) * s + (cc - a) * t + n * (lift * k);
            let plane = Plane::of([a, b, cc]);
            proptest::prop_assert_eq!(plane.side(d), sign(o3(a, b, cc, d)));
            for q in [a, b, cc] {
                proptest::prop_assert_eq!(plane.side(q), 0);
            }
        }
    }

    proptest::proptest! {
        /// The axis-plane shortcut answers zero only for a point in the
        /// triangle's axis plane, and the exact sign one float off it.
        #[test]
        fn points_in_and_next_to_an_axis_plane_get_the_exact_sign(
            corners in proptest::array::uniform9(-1.0f64..1.0),
            axis in 0usize..3,
            level in proptest::prop_oneof![proptest::strategy::Just(0.0), -1.0f64..1.0, -1e-300f64..1e-300],
            off in -1i64..=1,
            scale_exp in -20i32..20,
        ) {
            let k = f64::from_bits(((1023 + scale_exp) as u64) << 52);
            let mut p: Vec<DVec3> = corners
                .chunks(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]) * k)
                .collect();
            for q in &mut p {
                q[axis] = level;
            }
            // The fourth point in the plane, or one float above or below.
            let mut d = DVec3::new(corners[0] + corners[4], corners[8], corners[3]) * k;
            d[axis] = match off {
                0 => level,
                1 => level.next_up(),
                _ => level.next_down(),
            };
            let plane = Plane::of([p[0], p[1], p[2]]);
            proptest::prop_assert_eq!(plane.side(d), sign(o3(p[0], p[1], p[2], d)));
        }
    }

    #[test]
    fn same_result_on_one_and_two_threads() {
        let m = two_spheres(40, 0.7, [0.9, 0.3, 0.1]);
        let run = |threads| on_threads(threads, || self_intersections(&m));
        let (a, b) = (run(1), run(2));
        assert!(!a.pairs.is_empty());
        assert_eq!(a, b);
    }
}
