//! Resolution adaptation of a frame's region (paper §5.3): recursive
//! longest-edge bisection of the triangles at reshaped vertices whose
//! longest edge exceeds the max length, then up to three passes of
//! shortest-edge collapses at those vertices (the primitives and their
//! safety checks are in [`super::adapt`]).
//!
//! Most triangles of the region need neither, so both phases first test
//! every candidate in parallel (read-only, fixed chunks, results in order)
//! and then walk the candidates sequentially in the order a sequential scan
//! would, editing the mesh. A candidate whose test may have been changed by
//! an earlier edit of the same walk is tested again at its turn:
//! - a split writes only triangles that then contain a vertex it created,
//!   so the triangles around created vertices are stamped "dirty";
//! - a collapse changes edge lengths only at the kept vertex and its
//!   neighbours, so those are stamped "dirty".
//!
//! Hence the walk makes exactly the edits of the plain sequential scan, on
//! any number of threads.
//!
//! Splitting stops once the mesh has the sculptor's face limit
//! ([`super::budget::MAX_TRIANGLES`]) and flags the sculptor over budget
//! (the stroke then fails; the count is deterministic, so replays agree).

use glam::DVec3;

use super::halfedge::{FaceId, VertId};
use super::par;
use super::sculptor::{FrameStats, Limits, Sculptor};

impl Sculptor {
    /// Whether face `f` is split this frame: it is alive, its longest edge
    /// exceeds the max length, and it changed shape (a corner moved) or it
    /// was reached through a new vertex and lies in the frame's box.
    pub(super) fn wants_split(&self, f: FaceId, max2: f64, lo: DVec3, hi: DVec3) -> bool {
        if !self.mesh.face_alive(f) {
            return false;
        }
        let vs = self.mesh.face_verts(f);
        let p = vs.map(|v| self.mesh.position(v));
        let longest2 = p[0]
            .distance_squared(p[1])
            .max(p[1].distance_squared(p[2]))
            .max(p[2].distance_squared(p[0]));
        if longest2 <= max2 {
            return false;
        }
        // Triangles at a moved vertex changed shape: always adapt them.
        // Triangles reached only through new vertices adapt inside the
        // region's box, so a coarse base never refines far away.
        if vs.iter().any(|&v| self.moved(v)) {
            return true;
        }
        if !vs.iter().any(|&v| self.in_frame(v)) {
            return false;
        }
        let c = (p[0] + p[1] + p[2]) / 3.0;
        !(c.cmplt(lo).any() || c.cmpgt(hi).any())
    }

    /// Whether `v` is alive with an edge shorter than `min2.sqrt()`.
    pub(super) fn has_short(&self, v: VertId, min2: f64) -> bool {
        let mut any = false;
        if self.mesh.vert_alive(v) {
            self.mesh
                .for_each_out(v, |h| any |= self.mesh.edge_len2(h) < min2);
        }
        any
    }

    /// Sets `short_mark` of `v` to [`Self::has_short`].
    fn update_short(&mut self, v: VertId, min2: f64) {
        let s = self.has_short(v, min2);
        if let Some(m) = self.short_mark.get_mut(v.0 as usize) {
            *m = if s { self.frame_stamp } else { 0 };
        }
    }

    /// Splits the longest edge of `face` (recursively conforming), indexes
    /// and marks the new vertices, stamps the triangles around them with
    /// `dirty` and appends those triangles to `queue`.
    fn split_face(
        &mut self,
        face: FaceId,
        dirty: u32,
        created: &mut Vec<(VertId, bool)>,
        queue: &mut Vec<FaceId>,
        stats: &mut FrameStats,
    ) {
        let l = self.mesh.longest_edge(face);
        created.clear();
        self.mesh.split_conforming(l, created);
        stats.splits += created.len();
        for &(m, _) in created.iter() {
            self.split_new.push(m);
            self.grid.insert(m, self.mesh.position(m));
            self.mark(m, true);
            self.note_changed(m);
        }
        // Stamp after the whole conforming split: every triangle it wrote
        // contains one of the vertices it created.
        for &(m, _) in created.iter() {
            self.stamp_faces(m, dirty);
            self.mesh.for_each_out(m, |h| queue.push(h.face()));
        }
    }

    /// Adapts the frame's region: splits, then collapses (see the module
    /// doc). `lo`/`hi` bound the frame's moves (padded by the max length).
    pub(super) fn adapt(
        &mut self,
        lim: &Limits,
        tests: Option<Vec<(FaceId, bool)>>,
        stats: &mut FrameStats,
    ) {
        // The fold guard's first pass took the split tests when they still
        // hold (and then marked the region's vertices with short edges).
        let fused = tests.is_some();
        self.split_region(lim, tests, stats);
        self.collapse_region(lim, fused, stats);
    }

    /// The split phase of [`Self::adapt`]: the region's triangles whose
    /// longest edge is too long, then the triangles around new vertices.
    fn split_region(
        &mut self,
        lim: &Limits,
        tests: Option<Vec<(FaceId, bool)>>,
        stats: &mut FrameStats,
    ) {
        let Limits { max2, lo, hi, .. } = *lim;
        // The region is in ascending id order here, so a triangle first
        // appears (scanning the region's fans in order) at its smallest
        // corner in the region: that corner tests it.
        debug_assert!(self.region.windows(2).all(|w| w[0] < w[1]));
        let initial = tests.unwrap_or_else(|| {
            let this = &*self;
            par::flat_map_chunks(&self.region, |_, chunk, out| {
                for &v in chunk {
                    this.mesh.for_each_out(v, |h| {
                        let f = h.face();
                        let vs = this.mesh.face_verts(f);
                        let owner = vs.iter().filter(|&&w| this.in_frame(w)).min();
                        if owner == Some(&v) {
                            out.push((f, this.wants_split(f, max2, lo, hi)));
                        }
                    });
                }
            })
        });
        self.split_new.clear();
        let dirty = self.next_face_stamp();
        let mut queue = std::mem::take(&mut self.queue);
        queue.clear();
        let mut created = Vec::new();
        for &(face, want) in &initial {
            let need = if self.face_mark.get(face.0 as usize) == Some(&dirty) {
                self.wants_split(face, max2, lo, hi)
            } else {
                want
            };
            if need {
                if self.mesh.face_count() > self.face_limit {
                    self.stopped_at = self.mesh.face_count();
                    self.over_budget = true;
                    break;
                }
                self.split_face(face, dirty, &mut created, &mut queue, stats);
            }
        }
        // Triangles around new vertices, in the order they appeared.
        let mut i = 0;
        while i < queue.len() {
            let face = queue[i];
            i += 1;
            if self.over_budget {
                break;
            }
            if self.wants_split(face, max2, lo, hi) {
                if self.mesh.face_count() > self.face_limit {
                    self.stopped_at = self.mesh.face_count();
                    self.over_budget = true;
                    break;
                }
                self.split_face(face, dirty, &mut created, &mut queue, stats);
            }
        }
        self.queue = queue;
    }

    /// The collapse phase of [`Self::adapt`]: up to three passes over the
    /// region's vertices (by id) with an edge shorter than the min length.
    /// `fused`: the fold guard marked the short edges before the splits.
    fn collapse_region(&mut self, lim: &Limits, fused: bool, stats: &mut FrameStats) {
        let Limits { max2, min2, .. } = *lim;
        let mut cands = std::mem::take(&mut self.collapse_cands);
        cands.clear();
        cands.extend_from_slice(&self.region);
        par::sort_by_u32(&mut cands, &mut self.cand_scratch, |v| v.0);
        let fs = self.frame_stamp;
        if fused {
            // `short_mark` holds for the region as the warp left it; splits
            // changed edges only at the vertices they created and their
            // rings.
            let mut new = std::mem::take(&mut self.split_new);
            for &m in &new {
                self.update_short(m, min2);
                let mut ring = std::mem::take(&mut self.ring);
                ring.clear();
                self.mesh.for_each_out(m, |h| ring.push(self.mesh.to(h)));
                for &w in &ring {
                    self.update_short(w, min2);
                }
                self.ring = ring;
            }
            new.clear();
            self.split_new = new;
        } else {
            let this = &*self;
            let has_short = par::map(&cands, |&v| this.has_short(v, min2));
            for (&v, s) in cands.iter().zip(has_short) {
                self.short_mark[v.0 as usize] = if s { fs } else { 0 };
            }
        }
        let mut short = Vec::new();
        let mut touched = std::mem::take(&mut self.ring);
        for _pass in 0..3 {
            // `short_mark` now marks every candidate with a short edge (and
            // maybe some without: visiting those does nothing).
            touched.clear();
            self.dirty_stamp = self.dirty_stamp.wrapping_add(1);
            if self.dirty_stamp == 0 {
                self.dirty_mark.fill(0);
                self.dirty_stamp = 1;
            }
            let stamp = self.dirty_stamp;
            let mut any = false;
            for &v in &cands {
                let dirty = self.dirty_mark.get(v.0 as usize) == Some(&stamp);
                let has_short = self.short_mark[v.0 as usize] == fs;
                if !(has_short || dirty) || !self.mesh.vert_alive(v) {
                    continue;
                }
                short.clear();
                self.mesh.for_each_out(v, |h| {
                    let l2 = self.mesh.edge_len2(h);
                    if l2 < min2 {
                        short.push((l2, self.mesh.to(h)));
                    }
                });
                short.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                for &(_, o) in &short {
                    let (mv, mo) = (self.in_stroke(v), self.in_stroke(o));
                    let (keep, gone, p) = match (mv, mo) {
                        (true, true) => {
                            let p = (self.mesh.position(v) + self.mesh.position(o)) * 0.5;
                            (v.min(o), v.max(o), p)
                        }
                        (true, false) => (o, v, self.mesh.position(o)),
                        (false, true) => (v, o, self.mesh.position(v)),
                        (false, false) => continue,
                    };
                    let Some(h) = self.mesh.find_half_edge(keep, gone) else {
                        continue;
                    };
                    let gone_faces = [h.face(), self.mesh.twin(h).face()];
                    // Where the guards pulled steps back (`!fused`), a
                    // collapse may pass through a sheet close by
                    // (`super::crossing_guard`).
                    if self.mesh.collapse_refusal(h, p, max2).is_none()
                        && (fused || !self.collapse_crosses(h, p, lim))
                    {
                        self.mesh.collapse_edge(h, p);
                        self.removed_faces.extend(gone_faces);
                        self.note_changed(keep);
                        self.grid.remove(gone);
                        self.grid.update(keep, p);
                        if self.in_stroke(keep) {
                            self.mark(keep, true);
                        }
                        // Edge lengths changed only at `keep` and its ring.
                        let marks = &mut self.dirty_mark;
                        let mesh = &self.mesh;
                        let mut stamp_vertex = |w: VertId| {
                            if let Some(s) = marks.get_mut(w.0 as usize) {
                                *s = stamp;
                            }
                            touched.push(w);
                        };
                        stamp_vertex(keep);
                        mesh.for_each_out(keep, |g| stamp_vertex(mesh.to(g)));
                        stats.collapses += 1;
                        any = true;
                        break;
                    }
                }
            }
            if !any {
                break;
            }
            // Edge lengths changed only at the stamped vertices.
            for &w in &touched {
                self.update_short(w, min2);
            }
            // A stamped vertex of the stroke outside this frame's region (an
            // earlier frame reached it) may now have a short edge to a
            // vertex outside the stroke: only the stroke's side of that
            // edge can be collapsed, so it joins the candidates.
            let before = cands.len();
            for &w in &touched {
                if self.in_stroke(w) && self.short_mark[w.0 as usize] == fs {
                    cands.push(w);
                }
            }
            if cands.len() > before {
                cands.sort_unstable();
                cands.dedup();
            }
        }
        self.ring = touched;
        self.collapse_cands = cands;
    }
}
