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
//!   [`super::tri_meet`]), so the verdict is the same for the same bits on every
//!   machine and thread count. Coordinates beyond
//!   [`MAX_EXACT_COORDINATE`] are not judged (the caller reports them as out
//!   of range first).
//! - **Shared vertices by position**, not index: vertices with identical
//!   coordinates are one vertex here (what a slicer welding an STL sees).
//! - **Pairs by what they share**: an edge (intersect only when folded flat
//!   onto each other), a vertex (the edge opposite the shared vertex of one
//!   meets the other triangle, a short argument in [`super::tri_meet`]), or
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
//!   adaptive predicate ([`super::tri_meet`]).
//!
//! Written here rather than taken from `manifold-rust`'s robust engine
//! (`Manifold::has_self_intersections`), which answers yes/no for a whole
//! manifold it has accepted; printing needs the pairs (to name the objects
//! they came from) and a verdict on meshes Manifold refuses.

use std::collections::HashMap;

use super::tri_meet::{folded_onto, shares_vertex, triangles_meet};
use glam::DVec3;
use rayon::prelude::*;

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
        triangles_cross(self.tris[a], self.corners[a], self.tris[b], self.corners[b])
    }
}

/// Whether two triangles of one mesh (vertex indices `ta`, `tb`, corner
/// positions `pa`, `pb`) meet outside the vertices they share: the pair
/// test of [`self_intersections`], for callers that pick the pairs
/// themselves (the sculptor's collapse check).
pub(crate) fn triangles_cross(ta: [u32; 3], pa: [DVec3; 3], tb: [u32; 3], pb: [DVec3; 3]) -> bool {
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

    #[test]
    fn same_result_on_one_and_two_threads() {
        let m = two_spheres(40, 0.7, [0.9, 0.3, 0.1]);
        let run = |threads| on_threads(threads, || self_intersections(&m));
        let (a, b) = (run(1), run(2));
        assert!(!a.pairs.is_empty());
        assert_eq!(a, b);
    }
}
