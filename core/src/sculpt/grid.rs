//! [`VertexGrid`]: a uniform hash grid over vertex positions, updated
//! incrementally as vertices move, appear and disappear, so a frame finds
//! the vertices near the brush without a pass over the whole mesh.
//!
//! Cells are keyed by integer coordinates in a `HashMap`; each vertex
//! remembers its cell and slot, so moves are O(1). Queries return ids
//! sorted, so results never depend on hash or insertion order.

use crate::math::fm::DetMath as _;
use std::collections::HashMap;

use glam::DVec3;

use super::halfedge::{HalfEdgeMesh, VertId, INVALID};
use super::par::sort_by_u32;

/// Vertex ids bucketed by cell.
#[derive(Clone, Debug)]
pub struct VertexGrid {
    cell: f64,
    cells: HashMap<[i32; 3], Vec<u32>>,
    /// Per vertex: its cell and slot in it (slot INVALID when absent).
    where_: Vec<([i32; 3], u32)>,
}

impl VertexGrid {
    /// A grid with cell size `cell` holding every live vertex of `mesh`,
    /// with room for vertex ids up to `capacity` without reallocating.
    pub fn build(mesh: &HalfEdgeMesh, cell: f64, capacity: usize) -> Self {
        let n = mesh.vertex_capacity() as usize;
        let mut where_ = Vec::with_capacity(capacity.max(n));
        where_.resize(n, ([0; 3], INVALID));
        let mut g = Self {
            cell,
            cells: HashMap::new(),
            where_,
        };
        for v in mesh.vertices() {
            g.insert(v, mesh.position(v));
        }
        g
    }

    /// The cell size.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    #[inline]
    fn key(&self, p: DVec3) -> [i32; 3] {
        let q = (p / self.cell).floor();
        // Saturating casts keep absurd coordinates in (clamped) cells.
        [q.x as i32, q.y as i32, q.z as i32]
    }

    /// Adds vertex `v` at `p`.
    pub fn insert(&mut self, v: VertId, p: DVec3) {
        let i = v.0 as usize;
        if i >= self.where_.len() {
            self.where_.resize(i + 1, ([0; 3], INVALID));
        }
        let k = self.key(p);
        let bucket = self.cells.entry(k).or_default();
        self.where_[i] = (k, bucket.len() as u32);
        bucket.push(v.0);
    }

    /// Removes vertex `v`.
    pub fn remove(&mut self, v: VertId) {
        let Some(&(k, slot)) = self.where_.get(v.0 as usize) else {
            return;
        };
        if slot == INVALID {
            return;
        }
        if let Some(bucket) = self.cells.get_mut(&k) {
            bucket.swap_remove(slot as usize);
            if let Some(&moved) = bucket.get(slot as usize) {
                self.where_[moved as usize].1 = slot;
            }
            if bucket.is_empty() {
                self.cells.remove(&k);
            }
        }
        self.where_[v.0 as usize].1 = INVALID;
    }

    /// Records that vertex `v` moved to `p`.
    pub fn update(&mut self, v: VertId, p: DVec3) {
        let k = self.key(p);
        match self.where_.get(v.0 as usize) {
            Some(&(old, slot)) if slot != INVALID && old == k => {}
            _ => {
                self.remove(v);
                self.insert(v, p);
            }
        }
    }

    /// Fills `out` with every vertex whose cell meets the ball of `radius`
    /// around `center` (a superset of the vertices inside the ball), sorted
    /// by id; `scratch` is sorting space. Against [`Self::query`] on the
    /// ball's box this leaves out the cells in the box's corners: for a
    /// brush on a flat patch of surface, the square around its disc holds
    /// 4/π as many vertices as the disc, and every candidate costs a
    /// position load and a slot in the sort.
    pub fn query_ball(
        &self,
        center: DVec3,
        radius: f64,
        out: &mut Vec<VertId>,
        scratch: &mut Vec<VertId>,
    ) {
        out.clear();
        self.for_cells_in_ball(center, radius, |bucket| {
            out.extend(bucket.iter().map(|&v| VertId(v)))
        });
        sort_by_u32(out, scratch, |v| v.0);
    }

    /// How many vertices [`Self::query_ball`] would return, without
    /// listing them (a pass over the cells only: what a stroke's time
    /// estimate reads, see [`super::budget`]).
    pub fn count_ball(&self, center: DVec3, radius: f64) -> usize {
        let mut n = 0;
        self.for_cells_in_ball(center, radius, |bucket| n += bucket.len());
        n
    }

    /// Calls `f` with the bucket of every non-empty cell that meets the
    /// ball (see [`Self::query_ball`]).
    fn for_cells_in_ball(&self, center: DVec3, radius: f64, mut f: impl FnMut(&Vec<u32>)) {
        let r = DVec3::splat(radius);
        let a = self.key(center - r);
        let b = self.key(center + r);
        // In cell units a vertex at `p` is in cell `k = floor(p / cell)`,
        // so `p / cell` lies in [k, k + 1]; a cell is skipped when that box
        // is farther than the radius (plus a margin for the rounding of
        // the divisions) from `center / cell`.
        let c = center / self.cell;
        let rc = radius / self.cell;
        let reach2 = (rc * (1.0 + 1e-9) + 1e-6).fpowi(2);
        let far = |k: &[i32; 3]| {
            let mut d2 = 0.0;
            for i in 0..3 {
                let lo = k[i] as f64;
                let d = (lo - c[i]).max(c[i] - (lo + 1.0)).max(0.0);
                d2 += d * d;
            }
            d2 > reach2
        };
        let ncell = (0..3)
            .map(|i| (b[i] as i64 - a[i] as i64 + 1).max(0) as u64)
            .fold(1u64, |acc, s| acc.saturating_mul(s));
        if ncell as usize > self.cells.len() {
            for (k, bucket) in &self.cells {
                if (0..3).all(|i| k[i] >= a[i] && k[i] <= b[i]) && !far(k) {
                    f(bucket);
                }
            }
        } else {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        let k = [x, y, z];
                        if far(&k) {
                            continue;
                        }
                        if let Some(bucket) = self.cells.get(&k) {
                            f(bucket);
                        }
                    }
                }
            }
        }
    }

    /// Fills `out` with every vertex whose cell meets the box `[lo, hi]`
    /// (a superset of the vertices inside the box), sorted by id so the
    /// result never depends on bucket order; `scratch` is sorting space.
    pub fn query(&self, lo: DVec3, hi: DVec3, out: &mut Vec<VertId>, scratch: &mut Vec<VertId>) {
        out.clear();
        self.for_each_near(lo, hi, |v| out.push(v));
        sort_by_u32(out, scratch, |v| v.0);
    }

    /// Calls `f` with every vertex whose cell meets the box `[lo, hi]`, in
    /// no fixed order (for callers whose answer does not depend on it;
    /// [`Self::query`] sorts).
    pub fn for_each_near(&self, lo: DVec3, hi: DVec3, mut f: impl FnMut(VertId)) {
        let a = self.key(lo);
        let b = self.key(hi);
        let ncell = (0..3)
            .map(|i| (b[i] as i64 - a[i] as i64 + 1).max(0) as u64)
            .fold(1u64, |acc, s| acc.saturating_mul(s));
        if ncell as usize > self.cells.len() {
            // Fewer occupied cells than cells in the box: scan buckets.
            for (k, bucket) in &self.cells {
                if (0..3).all(|i| k[i] >= a[i] && k[i] <= b[i]) {
                    bucket.iter().for_each(|&v| f(VertId(v)));
                }
            }
        } else {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        if let Some(bucket) = self.cells.get(&[x, y, z]) {
                            bucket.iter().for_each(|&v| f(VertId(v)));
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sculpt::base::geodesic_sphere;

    /// The ball query returns, sorted, every vertex inside the ball and
    /// only vertices of the ball's box, for balls at and off the surface,
    /// large and small against the cells, and after vertices moved.
    #[test]
    fn ball_query_covers_the_ball_within_the_box() {
        let mut mesh = HalfEdgeMesh::from_trimesh(&geodesic_sphere(1.0, 24), "t").unwrap();
        let mut grid = VertexGrid::build(&mesh, 0.07, 0);
        let verts: Vec<VertId> = mesh.vertices().collect();
        for (i, &v) in verts.iter().enumerate().filter(|(i, _)| i % 7 == 0) {
            let p = mesh.position(v) * (1.0 + 0.05 * ((i % 5) as f64 - 2.0));
            mesh.set_position(v, p);
            grid.update(v, p);
        }
        let (mut out, mut boxed, mut s) = (Vec::new(), Vec::new(), Vec::new());
        let centers = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.3, -0.2, 0.9),
            DVec3::new(0.7, 0.7, 0.0),
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(-0.0350001, 0.07, -1.0),
        ];
        for c in centers {
            for r in [0.01, 0.07, 0.2, 0.5, 3.0] {
                grid.query_ball(c, r, &mut out, &mut s);
                assert!(out.windows(2).all(|w| w[0] < w[1]), "sorted, no repeats");
                let inside: Vec<VertId> = verts
                    .iter()
                    .copied()
                    .filter(|&v| mesh.position(v).distance_squared(c) <= r * r)
                    .collect();
                for v in &inside {
                    assert!(out.binary_search(v).is_ok(), "{v:?} missed at {c} r {r}");
                }
                grid.query(c - DVec3::splat(r), c + DVec3::splat(r), &mut boxed, &mut s);
                assert!(out.iter().all(|v| boxed.binary_search(v).is_ok()));
                if (0.2..=0.5).contains(&r) && c.length() > 0.5 {
                    assert!(out.len() < boxed.len(), "corner cells skipped at {c} r {r}");
                }
            }
        }
    }
}
