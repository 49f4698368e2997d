//! [`TriMesh`]: positions, normals, triangles and per-triangle source ids as
//! flat arrays (the shape of Manifold's `MeshGL`), so they cross to numpy,
//! Vulkan and USD without conversion loops.

use glam::{DAffine3, DVec3};
use serde::{Deserialize, Serialize};

/// An indexed triangle mesh.
///
/// `normals` is either empty or holds one unit normal per position.
/// `tri_source` is either empty or holds, per triangle, the id of the
/// document object it came from (so a union can be traced back to parts).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Per-vertex unit normals, or empty.
    pub normals: Vec<[f64; 3]>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Per-triangle source object id, or empty.
    pub tri_source: Vec<u32>,
}

impl TriMesh {
    /// A mesh from positions and triangles, without normals or sources.
    pub fn new(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            normals: Vec::new(),
            triangles,
            tri_source: Vec::new(),
        }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Position of vertex `i` as a vector.
    pub fn position(&self, i: u32) -> DVec3 {
        DVec3::from_array(self.positions[i as usize])
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangles[t];
        [self.position(a), self.position(b), self.position(c)]
    }

    /// Signed volume enclosed (positive for outward-facing triangles).
    ///
    /// Accumulated relative to the bounding-box centre, so that meshes far
    /// from the origin do not lose digits.
    pub fn signed_volume(&self) -> f64 {
        let origin = self
            .bbox()
            .map(|(lo, hi)| (lo + hi) * 0.5)
            .unwrap_or(DVec3::ZERO);
        let mut sum = 0.0;
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.corners(t);
            sum += (a - origin).dot((b - origin).cross(c - origin));
        }
        sum / 6.0
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// Axis-aligned bounding box of the positions, or `None` when empty.
    pub fn bbox(&self) -> Option<(DVec3, DVec3)> {
        let mut it = self.positions.iter().map(|p| DVec3::from_array(*p));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Recomputes per-vertex normals as the angle-weighted average of the
    /// incident face normals.
    ///
    /// Each triangle's weighted normals (three `acos`, the cost) are
    /// computed in parallel over fixed blocks of triangles and summed per
    /// vertex in triangle order, as a sequential loop sums them: the same
    /// bits on any number of threads.
    pub fn compute_normals(&mut self) {
        self.normals = self.vertex_normals();
    }

    /// The normals [`Self::compute_normals`] would set, without setting
    /// them.
    pub fn vertex_normals(&self) -> Vec<[f64; 3]> {
        use rayon::prelude::*;
        const BLOCK: usize = 8192;
        let mut acc = vec![DVec3::ZERO; self.positions.len()];
        let positions = &self.positions;
        let mut terms: Vec<[Option<DVec3>; 3]> = Vec::new();
        for block in self.triangles.chunks(BLOCK) {
            block
                .par_iter()
                .map(|tri| corner_normals(positions, tri))
                .collect_into_vec(&mut terms);
            for (tri, t) in block.iter().zip(&terms) {
                for k in 0..3 {
                    if let Some(n) = t[k] {
                        acc[tri[k] as usize] += n;
                    }
                }
            }
        }
        acc.into_iter()
            .map(|n| n.try_normalize().unwrap_or(DVec3::Z).to_array())
            .collect()
    }

    /// Whether the mesh carries one normal per vertex (a non-empty mesh:
    /// a boolean's result has none, see [`super::union`]). What every
    /// "its own normals, else computed" reader asks.
    pub fn has_vertex_normals(&self) -> bool {
        !self.positions.is_empty() && self.normals.len() == self.positions.len()
    }

    /// The mesh's own normals when it has one per vertex, else
    /// [`Self::vertex_normals`]: what a writer that only needs the normals
    /// (USD) takes, without copying the mesh.
    pub fn normals_or_computed(&self) -> std::borrow::Cow<'_, [[f64; 3]]> {
        if self.has_vertex_normals() {
            std::borrow::Cow::Borrowed(&self.normals)
        } else {
            std::borrow::Cow::Owned(self.vertex_normals())
        }
    }

    /// `self` with per-vertex normals ([`Self::normals_or_computed`]):
    /// borrowed when it has them, else a copy with them. What the OBJ and
    /// PLY writers take: a boolean's result has none ([`super::union`]).
    pub fn with_normals(&self) -> std::borrow::Cow<'_, TriMesh> {
        match self.normals_or_computed() {
            std::borrow::Cow::Borrowed(_) => std::borrow::Cow::Borrowed(self),
            std::borrow::Cow::Owned(normals) => std::borrow::Cow::Owned(TriMesh {
                positions: self.positions.clone(),
                normals,
                triangles: self.triangles.clone(),
                tri_source: self.tri_source.clone(),
            }),
        }
    }

    /// Runs [`Self::compute_normals`] when the mesh has not one normal per
    /// vertex (a renderer's smooth shading needs them).
    pub fn ensure_normals(&mut self) {
        if !self.has_vertex_normals() {
            self.compute_normals();
        }
    }

    /// Applies an affine transform to positions (and normals, by the inverse
    /// transpose). A transform with negative determinant flips the triangle
    /// winding so that the mesh stays outward-facing.
    pub fn transform(&mut self, m: &DAffine3) {
        for p in &mut self.positions {
            *p = m.transform_point3(DVec3::from_array(*p)).to_array();
        }
        let normal_m = m.matrix3.inverse().transpose();
        for n in &mut self.normals {
            let v = normal_m * DVec3::from_array(*n);
            *n = v.try_normalize().unwrap_or(DVec3::Z).to_array();
        }
        if m.matrix3.determinant() < 0.0 {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }

    /// Appends `other`, offsetting its indices. Normals and sources are
    /// kept only when both meshes have them.
    pub fn append(&mut self, other: &TriMesh) {
        let base = self.positions.len() as u32;
        let keep_normals = self.normals.len() == self.positions.len()
            && other.normals.len() == other.positions.len();
        let keep_sources = self.tri_source.len() == self.triangles.len()
            && other.tri_source.len() == other.triangles.len();
        self.positions.extend_from_slice(&other.positions);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
        if keep_normals {
            self.normals.extend_from_slice(&other.normals);
        } else {
            self.normals.clear();
        }
        if keep_sources {
            self.tri_source.extend_from_slice(&other.tri_source);
        } else {
            self.tri_source.clear();
        }
    }

    /// Sets every triangle's source id to `id`.
    pub fn set_source(&mut self, id: u32) {
        self.tri_source = vec![id; self.triangles.len()];
    }

    /// Merges vertices whose positions are bit-identical, keeping the first.
    /// Used after reading STL, whose triangles carry their own corners.
    pub fn weld_exact(&mut self) {
        let mut map = std::collections::HashMap::with_capacity(self.positions.len());
        let mut remap = Vec::with_capacity(self.positions.len());
        let mut positions = Vec::with_capacity(self.positions.len());
        for p in &self.positions {
            let key = p.map(f64::to_bits);
            let idx = *map.entry(key).or_insert_with(|| {
                positions.push(*p);
                (positions.len() - 1) as u32
            });
            remap.push(idx);
        }
        for t in &mut self.triangles {
            *t = t.map(|i| remap[i as usize]);
        }
        self.positions = positions;
        self.normals.clear();
    }
}

/// A triangle's unit normal weighted by the angle at each corner (`None`
/// where it adds nothing: a zero-area triangle, a non-finite angle).
fn corner_normals(positions: &[[f64; 3]], tri: &[u32; 3]) -> [Option<DVec3>; 3] {
    let p = tri.map(|i| DVec3::from_array(positions[i as usize]));
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let len = n.length();
    if len <= 0.0 {
        return [None; 3];
    }
    let n = n / len;
    std::array::from_fn(|k| {
        let e1 = p[(k + 1) % 3] - p[k];
        let e2 = p[(k + 2) % 3] - p[k];
        let angle = e1.angle_between(e2);
        angle.is_finite().then(|| n * angle)
    })
}

/// `xs` times `scale` as one little-endian `f64` buffer: what numpy views
/// without copying (`np.frombuffer`) and the bench's peers read.
pub fn f64_le_bytes<'a>(xs: impl IntoIterator<Item = &'a f64>, scale: f64) -> Vec<u8> {
    xs.into_iter()
        .flat_map(|x| (x * scale).to_le_bytes())
        .collect()
}

/// `xs` as one little-endian `u32` buffer (triangle indices, sources).
pub fn u32_le_bytes<'a>(xs: impl IntoIterator<Item = &'a u32>) -> Vec<u8> {
    xs.into_iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solid::{tessellate, SolidShape};

    /// A mesh with normals lends them; one without gets exactly the
    /// normals `compute_normals` sets, and `with_normals` copies nothing
    /// else but them.
    #[test]
    fn normals_or_computed_borrows_or_computes_the_same_bits() {
        let mut m = tessellate(&SolidShape::Sphere { radius: 1.0 }, 16).expect("sphere");
        m.normals.clear();
        let got = m.normals_or_computed().into_owned();
        let w = m.with_normals().into_owned();
        m.compute_normals();
        assert!(!got.is_empty() && got == m.normals && w == m);
        assert!(matches!(
            m.normals_or_computed(),
            std::borrow::Cow::Borrowed(n) if std::ptr::eq(n, m.normals.as_slice())
        ));
        assert!(matches!(m.with_normals(), std::borrow::Cow::Borrowed(b) if std::ptr::eq(b, &m)));
    }

    /// The sequential loop the parallel one replaced.
    fn normals_sequential(m: &TriMesh) -> Vec<[f64; 3]> {
        let mut acc = vec![DVec3::ZERO; m.positions.len()];
        for tri in &m.triangles {
            let p = tri.map(|i| DVec3::from_array(m.positions[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let len = n.length();
            if len <= 0.0 {
                continue;
            }
            let n = n / len;
            for k in 0..3 {
                let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
                if angle.is_finite() {
                    acc[tri[k] as usize] += n * angle;
                }
            }
        }
        acc.into_iter()
            .map(|n| n.try_normalize().unwrap_or(DVec3::Z).to_array())
            .collect()
    }

    #[test]
    fn parallel_normals_are_the_sequential_bits_on_any_threads() {
        // More triangles than one block, a zero-area triangle and an
        // unused vertex.
        let mut m = tessellate(
            &SolidShape::Torus {
                major_radius: 1.0,
                minor_radius: 0.3,
            },
            96,
        )
        .expect("torus");
        assert!(m.triangle_count() > 8192);
        m.positions.push([0.0, 0.0, 0.0]);
        m.triangles.push([0, 0, 1]);
        let want = normals_sequential(&m);
        for threads in [1, 2, 3] {
            let mut got = m.clone();
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool")
                .install(|| got.compute_normals());
            let same = got
                .normals
                .iter()
                .zip(&want)
                .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits));
            assert!(same && got.normals.len() == want.len(), "{threads} threads");
        }
    }
}
