//! [`VertexGrid`]: a uniform hash grid over vertex positions, updated
//! incrementally as vertices move, appear and disappear, so a frame finds
//! the vertices near the brush without a pass over the whole mesh.
//!
//! Cells are keyed by integer coordinates in a `HashMap`; each vertex
//! remembers its cell and slot, so moves are O(1). Queries return ids
//! sorted, so results never depend on hash or insertion order.

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

    /// Fills `out` with every vertex whose cell meets the box `[lo, hi]`
    /// (a superset of the vertices inside the box), sorted by id so the
    /// result never depends on bucket order; `scratch` is sorting space.
    pub fn query(&self, lo: DVec3, hi: DVec3, out: &mut Vec<VertId>, scratch: &mut Vec<VertId>) {
        out.clear();
        let a = self.key(lo);
        let b = self.key(hi);
        let ncell = (0..3)
            .map(|i| (b[i] as i64 - a[i] as i64 + 1).max(0) as u64)
            .fold(1u64, |acc, s| acc.saturating_mul(s));
        if ncell as usize > self.cells.len() {
            // Fewer occupied cells than cells in the box: scan buckets.
            for (k, bucket) in &self.cells {
                if (0..3).all(|i| k[i] >= a[i] && k[i] <= b[i]) {
                    out.extend(bucket.iter().map(|&v| VertId(v)));
                }
            }
        } else {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        if let Some(bucket) = self.cells.get(&[x, y, z]) {
                            out.extend(bucket.iter().map(|&v| VertId(v)));
                        }
                    }
                }
            }
        }
        sort_by_u32(out, scratch, |v| v.0);
    }
}
