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
//!   whose products do not overflow, so the verdict is the same for the
//!   same bits on every machine and thread count. Coordinates beyond
//!   [`MAX_EXACT_COORDINATE`] are not judged (the caller reports them as out
//!   of range first).
//! - **Shared vertices by position**, not index: vertices with identical
//!   coordinates are one vertex here (what a slicer welding an STL sees).
//! - **Pairs by what they share**: an edge (intersect only when folded flat
//!   onto each other), a vertex (the edge opposite the shared vertex of one
//!   meets the other triangle, a short argument in [`shares_vertex`]), or
//!   nothing (one of the six edges meets the other triangle).
//! - **BVH**: median split on the longest axis of the centroid box, leaves
//!   of up to [`LEAF`] triangles; each leaf is queried against the tree
//!   (leaf pairs visited once) on rayon's pool, and the pairs found are
//!   sorted, so the report does not depend on the thread count.
//!
//! Written here rather than taken from `manifold-rust`'s robust engine
//! (`Manifold::has_self_intersections`), which answers yes/no for a whole
//! manifold it has accepted; printing needs the pairs (to name the objects
//! they came from) and a verdict on meshes Manifold refuses.

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
    let canon = canonical_vertices(&mesh.positions);
    let tris: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| canon[i as usize]))
        .collect();
    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|t| Aabb::of(t.map(|i| DVec3::from_array(mesh.positions[i as usize]))))
        .collect();
    let bvh = Bvh::build(&boxes);
    let ctx = Ctx {
        pos: &mesh.positions,
        tris: &tris,
        boxes: &boxes,
        bvh: &bvh,
    };
    let mut pairs: Vec<(u32, u32)> = bvh
        .leaves
        .par_iter()
        .enumerate()
        .flat_map_iter(|(li, &node)| {
            let mut out = Vec::new();
            ctx.query_leaf(li, node, &mut out);
            out
        })
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    SelfIntersections {
        pairs,
        checked: true,
    }
}

/// Maps each vertex to the first vertex with bit-identical coordinates.
fn canonical_vertices(pos: &[[f64; 3]]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..pos.len() as u32).collect();
    let key = |i: u32| pos[i as usize].map(|x| (x + 0.0).to_bits());
    order.par_sort_unstable_by_key(|&i| (key(i), i));
    let mut canon: Vec<u32> = (0..pos.len() as u32).collect();
    let mut k = 0;
    while k < order.len() {
        let first = order[k];
        let mut j = k + 1;
        while j < order.len() && key(order[j]) == key(first) {
            canon[order[j] as usize] = first;
            j += 1;
        }
        k = j;
    }
    canon
}

#[derive(Clone, Copy, Debug)]
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

/// A node: an inner node has `count == 0` and children `first`,
/// `first + 1`; a leaf holds `order[first..first + count]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
}

struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// Leaf node indices in build order (so leaf `k` can skip leaves `< k`).
    leaves: Vec<u32>,
    /// Per node: its leaf rank for leaves, else `u32::MAX`.
    leaf_rank: Vec<u32>,
}

impl Bvh {
    fn build(boxes: &[Aabb]) -> Self {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let centre: Vec<DVec3> = boxes.iter().map(|b| (b.lo + b.hi) * 0.5).collect();
        let mut nodes = vec![Node {
            bounds: Aabb::empty(),
            first: 0,
            count: 0,
        }];
        // (node, start, end) still to split.
        let mut stack = vec![(0usize, 0usize, boxes.len())];
        while let Some((node, start, end)) = stack.pop() {
            let slice = &mut order[start..end];
            let bounds = slice
                .iter()
                .fold(Aabb::empty(), |acc, &t| acc.join(boxes[t as usize]));
            if end - start <= LEAF {
                nodes[node] = Node {
                    bounds,
                    first: start as u32,
                    count: (end - start) as u32,
                };
                continue;
            }
            let cb = slice.iter().fold(Aabb::empty(), |acc, &t| {
                let c = centre[t as usize];
                acc.join(Aabb { lo: c, hi: c })
            });
            let ext = cb.hi - cb.lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = slice.len() / 2;
            slice.select_nth_unstable_by(mid, |&a, &b| {
                centre[a as usize][axis]
                    .total_cmp(&centre[b as usize][axis])
                    .then(a.cmp(&b))
            });
            let left = nodes.len();
            nodes.push(Node {
                bounds: Aabb::empty(),
                first: 0,
                count: 0,
            });
            nodes.push(Node {
                bounds: Aabb::empty(),
                first: 0,
                count: 0,
            });
            nodes[node] = Node {
                bounds,
                first: left as u32,
                count: 0,
            };
            stack.push((left + 1, start + mid, end));
            stack.push((left, start, start + mid));
        }
        let mut leaves = Vec::new();
        let mut leaf_rank = vec![u32::MAX; nodes.len()];
        for (i, n) in nodes.iter().enumerate() {
            if n.count > 0 {
                leaf_rank[i] = leaves.len() as u32;
                leaves.push(i as u32);
            }
        }
        Self {
            nodes,
            order,
            leaves,
            leaf_rank,
        }
    }

    fn leaf_tris(&self, node: &Node) -> &[u32] {
        &self.order[node.first as usize..(node.first + node.count) as usize]
    }
}

struct Ctx<'a> {
    pos: &'a [[f64; 3]],
    tris: &'a [[u32; 3]],
    boxes: &'a [Aabb],
    bvh: &'a Bvh,
}

impl Ctx<'_> {
    /// Every intersecting pair with one triangle in leaf `rank` and the other
    /// in the same leaf or a later one.
    fn query_leaf(&self, rank: usize, node: u32, out: &mut Vec<(u32, u32)>) {
        let bvh = self.bvh;
        let leaf = bvh.nodes[node as usize];
        let mine = bvh.leaf_tris(&leaf);
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let other = bvh.nodes[n as usize];
            if !other.bounds.overlaps(&leaf.bounds) {
                continue;
            }
            if other.count == 0 {
                stack.push(other.first);
                stack.push(other.first + 1);
                continue;
            }
            let other_rank = bvh.leaf_rank[n as usize] as usize;
            if other_rank < rank {
                continue;
            }
            let theirs = bvh.leaf_tris(&other);
            for (a_pos, &a) in mine.iter().enumerate() {
                let skip = if other_rank == rank { a_pos + 1 } else { 0 };
                for &b in &theirs[skip..] {
                    if self.boxes[a as usize].overlaps(&self.boxes[b as usize])
                        && self.pair_intersects(a, b)
                    {
                        out.push((a.min(b), a.max(b)));
                    }
                }
            }
        }
    }

    fn p(&self, i: u32) -> DVec3 {
        DVec3::from_array(self.pos[i as usize])
    }

    fn pair_intersects(&self, a: u32, b: u32) -> bool {
        let ta = self.tris[a as usize];
        let tb = self.tris[b as usize];
        let shared: Vec<(usize, usize)> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .filter(|&(i, j)| ta[i] == tb[j])
            .collect();
        let pa = ta.map(|i| self.p(i));
        let pb = tb.map(|i| self.p(i));
        match shared.len() {
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

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Two triangles sharing the edge `e0 e1`, with other corners `c` and `d`,
/// overlap beyond the edge exactly when they are coplanar and on the same
/// side of it (folded flat onto each other).
fn folded_onto(e0: DVec3, e1: DVec3, c: DVec3, d: DVec3) -> bool {
    if o3(e0, e1, c, d) != 0.0 {
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
    segment_meets_triangle(a1, a2, pb) || segment_meets_triangle(b1, b2, pa)
}

/// Closed triangles with no shared vertex meet exactly when one of the six
/// edges meets the other triangle (the intersection of two triangles, when
/// not empty, has a point on the boundary of one of them inside the other).
fn triangles_meet(pa: [DVec3; 3], pb: [DVec3; 3]) -> bool {
    // Quick rejects: one triangle strictly on one side of the other's plane.
    let side = |t: [DVec3; 3], p: [DVec3; 3]| {
        let s = p.map(|q| sign(o3(t[0], t[1], t[2], q)));
        (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0)
    };
    if side(pa, pb) || side(pb, pa) {
        return false;
    }
    (0..3).any(|k| segment_meets_triangle(pa[k], pa[(k + 1) % 3], pb))
        || (0..3).any(|k| segment_meets_triangle(pb[k], pb[(k + 1) % 3], pa))
}

/// The closed segment `p q` meets the closed triangle `t`.
fn segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let sp = sign(o3(a, b, c, p));
    let sq = sign(o3(a, b, c, q));
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        return coplanar_segment_meets_triangle(p, q, t);
    }
    // The segment reaches the plane; its line passes through the closed
    // triangle exactly when the three edge orientations agree in sign.
    let s1 = sign(o3(p, q, a, b));
    let s2 = sign(o3(p, q, b, c));
    let s3 = sign(o3(p, q, c, a));
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
        let mut m = sphere(1.0, 32);
        let mut other = sphere(1.0, 32);
        other.transform(&DAffine3::from_translation(DVec3::new(1.0, 0.0, 0.0)));
        m.append(&other);
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

    #[test]
    fn same_result_on_one_and_two_threads() {
        let mut m = sphere(1.0, 40);
        let mut other = sphere(0.7, 40);
        other.transform(&DAffine3::from_translation(DVec3::new(0.9, 0.3, 0.1)));
        m.append(&other);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| self_intersections(&m))
        };
        let (a, b) = (run(1), run(2));
        assert!(!a.pairs.is_empty());
        assert_eq!(a, b);
    }
}
