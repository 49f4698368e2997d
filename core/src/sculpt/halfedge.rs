//! [`HalfEdgeMesh`]: a compact index-based split-edge (half-edge) triangle
//! mesh with O(1) adjacency (paper §5.1).
//!
//! Layout: faces are triangles whose three half-edges are stored together,
//! so half-edge `h` belongs to face `h / 3`, `next(h)` and `prev(h)` are
//! index arithmetic, and only the target vertex and the twin (the paper's
//! "sibling") are stored per half-edge: 8 bytes per half-edge, plus 28 per
//! vertex. Removed faces and vertices go to free lists and are reused in
//! LIFO order, so the structure after any sequence of edits is a pure
//! function of that sequence (bit-identical replay).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::SculptError;
use crate::mesh::{validate, TriMesh, ValidationSettings};

/// Marks a removed vertex, face or a missing link.
pub const INVALID: u32 = u32::MAX;

/// A vertex id.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertId(pub u32);
/// A half-edge id; half-edge `3f + i` is corner `i` of face `f`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct HalfEdgeId(pub u32);
/// A face (triangle) id.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceId(pub u32);

impl HalfEdgeId {
    /// The face the half-edge bounds.
    #[inline]
    pub fn face(self) -> FaceId {
        FaceId(self.0 / 3)
    }
    /// The next half-edge around its face.
    #[inline]
    pub fn next(self) -> Self {
        let b = self.0 - self.0 % 3;
        Self(b + (self.0 % 3 + 1) % 3)
    }
    /// The previous half-edge around its face.
    #[inline]
    pub fn prev(self) -> Self {
        let b = self.0 - self.0 % 3;
        Self(b + (self.0 % 3 + 2) % 3)
    }
}

impl FaceId {
    /// The face's first half-edge.
    #[inline]
    pub fn half_edge(self, corner: u32) -> HalfEdgeId {
        HalfEdgeId(self.0 * 3 + corner)
    }
}

/// A closed, oriented, 2-manifold triangle mesh as a split-edge structure.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HalfEdgeMesh {
    /// Vertex positions (entries of removed vertices are kept, unused).
    pub(crate) pos: Vec<[f64; 3]>,
    /// One outgoing half-edge per vertex, or [`INVALID`] when removed.
    pub(crate) vert_he: Vec<u32>,
    /// Target vertex per half-edge; [`INVALID`] for half-edges of removed faces.
    pub(crate) he_to: Vec<u32>,
    /// Opposite half-edge per half-edge.
    pub(crate) he_twin: Vec<u32>,
    /// Removed vertex ids, reused last-in first-out.
    pub(crate) free_verts: Vec<u32>,
    /// Removed face ids, reused last-in first-out.
    pub(crate) free_faces: Vec<u32>,
}

impl HalfEdgeMesh {
    /// Builds the structure from a closed oriented 2-manifold triangle mesh.
    /// Unreferenced vertices are dropped. Open, non-manifold or
    /// inconsistently oriented input is refused with a typed error.
    pub fn from_trimesh(mesh: &TriMesh, what: &'static str) -> Result<Self, SculptError> {
        let nv = mesh.positions.len();
        for (i, t) in mesh.triangles.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= nv) {
                return Err(SculptError::BadTriangle {
                    what,
                    triangle: i,
                    reason: "index past the end of the positions",
                });
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(SculptError::BadTriangle {
                    what,
                    triangle: i,
                    reason: "repeated vertex index",
                });
            }
        }
        let report = validate(mesh, &ValidationSettings::default());
        if !report.is_closed_manifold() || mesh.triangles.is_empty() {
            return Err(SculptError::NotClosedManifold {
                what,
                problems: if mesh.triangles.is_empty() {
                    "no triangles".into()
                } else {
                    report.problems()
                },
            });
        }
        // Compact referenced vertices, keeping their order.
        let mut remap = vec![INVALID; nv];
        for t in &mesh.triangles {
            for &v in t {
                remap[v as usize] = 0;
            }
        }
        let mut pos = Vec::new();
        for (v, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = pos.len() as u32;
                pos.push(mesh.positions[v]);
            }
        }
        let mut he_to = Vec::with_capacity(mesh.triangles.len() * 3);
        for t in &mesh.triangles {
            // Half-edge 3f+i goes from corner i to corner i+1.
            he_to.push(remap[t[1] as usize]);
            he_to.push(remap[t[2] as usize]);
            he_to.push(remap[t[0] as usize]);
        }
        let nh = he_to.len();
        // Twins by sorting directed edges (deterministic, no hashing).
        let mut keys: Vec<(u32, u32, u32)> = (0..nh as u32)
            .map(|h| {
                let a = he_to[HalfEdgeId(h).prev().0 as usize];
                let b = he_to[h as usize];
                (a.min(b), a.max(b), h)
            })
            .collect();
        keys.sort_unstable();
        let mut he_twin = vec![INVALID; nh];
        for pair in keys.chunks(2) {
            // The validator guaranteed every edge has exactly two opposite uses.
            if pair.len() != 2 || pair[0].0 != pair[1].0 || pair[0].1 != pair[1].1 {
                return Err(SculptError::NotClosedManifold {
                    what,
                    problems: "an edge is not shared by exactly two triangles".into(),
                });
            }
            he_twin[pair[0].2 as usize] = pair[1].2;
            he_twin[pair[1].2 as usize] = pair[0].2;
        }
        let mut vert_he = vec![INVALID; pos.len()];
        for h in 0..nh as u32 {
            let o = he_to[HalfEdgeId(h).prev().0 as usize];
            if vert_he[o as usize] == INVALID {
                vert_he[o as usize] = h;
            }
        }
        let out = Self {
            pos,
            vert_he,
            he_to,
            he_twin,
            free_verts: Vec::new(),
            free_faces: Vec::new(),
        };
        out.check()
            .map_err(|e| SculptError::NotClosedManifold { what, problems: e })?;
        Ok(out)
    }

    /// The live part as a compact [`TriMesh`] (vertices renumbered in id
    /// order, faces in id order), with vertex normals.
    pub fn to_trimesh(&self) -> TriMesh {
        let mut remap = vec![INVALID; self.pos.len()];
        let mut positions = Vec::with_capacity(self.vertex_count());
        for (v, &h) in self.vert_he.iter().enumerate() {
            if h != INVALID {
                remap[v] = positions.len() as u32;
                positions.push(self.pos[v]);
            }
        }
        let mut triangles = Vec::with_capacity(self.face_count());
        for f in 0..self.face_capacity() {
            if self.face_alive(FaceId(f)) {
                let [a, b, c] = self.face_verts(FaceId(f));
                triangles.push([
                    remap[a.0 as usize],
                    remap[b.0 as usize],
                    remap[c.0 as usize],
                ]);
            }
        }
        let mut m = TriMesh::new(positions, triangles);
        m.compute_normals();
        m
    }

    /// Live vertices.
    pub fn vertex_count(&self) -> usize {
        self.vert_he.len() - self.free_verts.len()
    }
    /// Live faces.
    pub fn face_count(&self) -> usize {
        self.he_to.len() / 3 - self.free_faces.len()
    }
    /// Vertex slots (live or free).
    pub fn vertex_capacity(&self) -> u32 {
        self.vert_he.len() as u32
    }
    /// Face slots (live or free).
    pub fn face_capacity(&self) -> u32 {
        (self.he_to.len() / 3) as u32
    }
    /// True when vertex `v` exists.
    #[inline]
    pub fn vert_alive(&self, v: VertId) -> bool {
        self.vert_he
            .get(v.0 as usize)
            .is_some_and(|&h| h != INVALID)
    }
    /// True when face `f` exists.
    #[inline]
    pub fn face_alive(&self, f: FaceId) -> bool {
        self.he_to
            .get(f.0 as usize * 3)
            .is_some_and(|&v| v != INVALID)
    }
    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: VertId) -> DVec3 {
        DVec3::from_array(self.pos[v.0 as usize])
    }
    /// Position of vertex `v` as stored.
    #[inline]
    pub fn position_bits(&self, v: VertId) -> [f64; 3] {
        self.pos[v.0 as usize]
    }
    #[inline]
    pub(crate) fn set_position(&mut self, v: VertId, p: DVec3) {
        self.pos[v.0 as usize] = p.to_array();
    }
    /// The target vertex of `h`.
    #[inline]
    pub fn to(&self, h: HalfEdgeId) -> VertId {
        VertId(self.he_to[h.0 as usize])
    }
    /// The origin vertex of `h`.
    #[inline]
    pub fn from(&self, h: HalfEdgeId) -> VertId {
        VertId(self.he_to[h.prev().0 as usize])
    }
    /// The opposite half-edge of `h`.
    #[inline]
    pub fn twin(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(self.he_twin[h.0 as usize])
    }
    /// One outgoing half-edge of live vertex `v`.
    #[inline]
    pub fn out_half_edge(&self, v: VertId) -> HalfEdgeId {
        HalfEdgeId(self.vert_he[v.0 as usize])
    }
    /// The corners of face `f`, counter-clockwise from outside.
    #[inline]
    pub fn face_verts(&self, f: FaceId) -> [VertId; 3] {
        let b = f.0 as usize * 3;
        [
            VertId(self.he_to[b + 2]),
            VertId(self.he_to[b]),
            VertId(self.he_to[b + 1]),
        ]
    }
    /// Squared length of the edge of `h`.
    #[inline]
    pub fn edge_len2(&self, h: HalfEdgeId) -> f64 {
        self.position(self.to(h))
            .distance_squared(self.position(self.from(h)))
    }
    /// Unnormalized normal (twice the area vector) of face `f`.
    #[inline]
    pub fn face_area_vec(&self, f: FaceId) -> DVec3 {
        let [a, b, c] = self.face_verts(f).map(|v| self.position(v));
        (b - a).cross(c - a)
    }
    /// Calls `visit` with every outgoing half-edge of live vertex `v`, in
    /// clockwise order starting from [`Self::out_half_edge`].
    #[inline]
    pub fn for_each_out(&self, v: VertId, mut visit: impl FnMut(HalfEdgeId)) {
        let start = self.out_half_edge(v);
        let mut h = start;
        loop {
            visit(h);
            h = self.twin(h.prev());
            if h == start {
                break;
            }
        }
    }
    /// Number of edges at live vertex `v`.
    pub fn degree(&self, v: VertId) -> usize {
        let mut n = 0;
        self.for_each_out(v, |_| n += 1);
        n
    }
    /// Live vertex ids in increasing order.
    pub fn vertices(&self) -> impl Iterator<Item = VertId> + '_ {
        (0..self.vertex_capacity())
            .map(VertId)
            .filter(|&v| self.vert_alive(v))
    }
    /// Live face ids in increasing order.
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + '_ {
        (0..self.face_capacity())
            .map(FaceId)
            .filter(|&f| self.face_alive(f))
    }

    /// Reserves room for `verts` more vertices (and about twice as many
    /// faces), so growth does not reallocate in the middle of a frame.
    pub fn reserve(&mut self, verts: usize) {
        self.pos.reserve(verts);
        self.vert_he.reserve(verts);
        self.he_to.reserve(6 * verts);
        self.he_twin.reserve(6 * verts);
    }

    pub(crate) fn new_vertex(&mut self, p: DVec3) -> VertId {
        if let Some(v) = self.free_verts.pop() {
            self.pos[v as usize] = p.to_array();
            VertId(v)
        } else {
            self.pos.push(p.to_array());
            self.vert_he.push(INVALID);
            VertId(self.vert_he.len() as u32 - 1)
        }
    }

    pub(crate) fn new_face(&mut self) -> FaceId {
        if let Some(f) = self.free_faces.pop() {
            FaceId(f)
        } else {
            self.he_to.extend_from_slice(&[INVALID; 3]);
            self.he_twin.extend_from_slice(&[INVALID; 3]);
            FaceId(self.he_to.len() as u32 / 3 - 1)
        }
    }

    /// Sets face `f` to corners `[a, b, c]`; half-edge `3f + i` runs from
    /// corner `i` to corner `i + 1`. Twins are left to the caller.
    #[inline]
    pub(crate) fn write_face(&mut self, f: FaceId, [a, b, c]: [VertId; 3]) {
        let base = f.0 as usize * 3;
        self.he_to[base] = b.0;
        self.he_to[base + 1] = c.0;
        self.he_to[base + 2] = a.0;
    }

    #[inline]
    pub(crate) fn link(&mut self, a: HalfEdgeId, b: HalfEdgeId) {
        self.he_twin[a.0 as usize] = b.0;
        self.he_twin[b.0 as usize] = a.0;
    }

    pub(crate) fn remove_face(&mut self, f: FaceId) {
        let base = f.0 as usize * 3;
        self.he_to[base..base + 3].fill(INVALID);
        self.he_twin[base..base + 3].fill(INVALID);
        self.free_faces.push(f.0);
    }

    pub(crate) fn remove_vertex(&mut self, v: VertId) {
        self.vert_he[v.0 as usize] = INVALID;
        self.free_verts.push(v.0);
    }

    /// Checks every structural invariant: twins are mutual and opposite,
    /// faces have three distinct live corners, every vertex's outgoing
    /// half-edge starts at it and its fan is one closed disc covering all of
    /// its half-edges, free lists name exactly the removed slots, positions
    /// are finite. Returns what is wrong.
    pub fn check(&self) -> Result<(), String> {
        let nh = self.he_to.len();
        if !nh.is_multiple_of(3) || self.he_twin.len() != nh || self.pos.len() != self.vert_he.len()
        {
            return Err("array lengths disagree".into());
        }
        let mut out_count = vec![0u32; self.vert_he.len()];
        for f in 0..self.face_capacity() {
            let f = FaceId(f);
            let base = f.0 as usize * 3;
            let alive = self.he_to[base] != INVALID;
            if !alive {
                if self.he_to[base..base + 3].iter().any(|&v| v != INVALID) {
                    return Err(format!("face {} partly removed", f.0));
                }
                continue;
            }
            let vs = self.face_verts(f);
            if vs.iter().any(|v| !self.vert_alive(*v)) {
                return Err(format!("face {} uses a removed vertex", f.0));
            }
            if vs[0] == vs[1] || vs[1] == vs[2] || vs[0] == vs[2] {
                return Err(format!("face {} repeats a vertex", f.0));
            }
            for i in 0..3 {
                let h = f.half_edge(i);
                let t = self.twin(h);
                if t.0 as usize >= nh || self.he_to[t.0 as usize] == INVALID {
                    return Err(format!("half-edge {} has no live twin", h.0));
                }
                if self.twin(t) != h {
                    return Err(format!("twin of half-edge {} is not mutual", h.0));
                }
                if self.from(t) != self.to(h) || self.to(t) != self.from(h) {
                    return Err(format!("half-edge {} and its twin are not opposite", h.0));
                }
                if t.face() == h.face() {
                    return Err(format!("half-edge {} is its own face's twin", h.0));
                }
                out_count[self.from(h).0 as usize] += 1;
            }
        }
        let mut free_v = 0;
        for v in 0..self.vertex_capacity() {
            let v = VertId(v);
            if !self.vert_alive(v) {
                free_v += 1;
                continue;
            }
            if !DVec3::from_array(self.pos[v.0 as usize]).is_finite() {
                return Err(format!("vertex {} is not finite", v.0));
            }
            let h = self.out_half_edge(v);
            if h.0 as usize >= nh || self.he_to[h.0 as usize] == INVALID || self.from(h) != v {
                return Err(format!("vertex {} has a bad outgoing half-edge", v.0));
            }
            // Walk the fan; it must close and cover every outgoing half-edge.
            let mut n = 0u32;
            let mut ring = Vec::new();
            let mut g = h;
            loop {
                n += 1;
                ring.push(self.to(g));
                if n > out_count[v.0 as usize] {
                    return Err(format!("vertex {} fan does not close", v.0));
                }
                g = self.twin(g.prev());
                if g == h {
                    break;
                }
            }
            if n != out_count[v.0 as usize] {
                return Err(format!(
                    "vertex {} is a pinch point ({} of {} edges in one fan)",
                    v.0, n, out_count[v.0 as usize]
                ));
            }
            if n < 3 {
                return Err(format!("vertex {} has degree {n}", v.0));
            }
            ring.sort_unstable();
            if ring.windows(2).any(|w| w[0] == w[1]) {
                return Err(format!("vertex {} has a doubled edge", v.0));
            }
        }
        if free_v != self.free_verts.len() {
            return Err("free vertex list disagrees with removed vertices".into());
        }
        let dead_f = self.faces_dead();
        if dead_f != self.free_faces.len() {
            return Err("free face list disagrees with removed faces".into());
        }
        Ok(())
    }

    fn faces_dead(&self) -> usize {
        (0..self.face_capacity())
            .filter(|&f| !self.face_alive(FaceId(f)))
            .count()
    }
}
