//! The crossing guard of a frame ([`Sculptor::apply_frame`]), after the
//! fold guard ([`super::fold_guard`]): a warp step may not make the
//! surface pass through itself.
//!
//! The fold guard judges each triangle against the triangles it shares a
//! vertex with; it cannot see two sheets a few triangles apart meet. Every
//! vertex of a frame follows one warp, which does not fold space for the
//! brushes' step limits, so sheets do not meet while the fold guard takes
//! every step whole. They do once it halves or undoes some steps and not
//! their neighbours': the surface where it pulled back is no longer the
//! warp's image, and pleats of it can pass through each other. That is
//! what mirrored strokes on the headset's presets did (issue 33: two
//! brushes pushing the same crease from both sides of the mirror plane,
//! the fold guard pulling back hundreds of vertices a frame; 4 of 140
//! random stroke-pair sequences crossed themselves, by up to 164 triangle
//! pairs, though no triangle folded onto a neighbour).
//!
//! So in a frame where the fold guard pulled back a step, the triangles
//! around the frame's moves (every triangle at a vertex in the moves' box,
//! padded by the max edge length) are searched for crossing pairs with the
//! exact test of [`crate::mesh::self_intersections`]; the moved corners of
//! each crossing pair go back to where they were before the frame, then
//! the fold guard's test runs again on the triangles around them (a vertex
//! put back can fold against a neighbour that kept its step, which then
//! goes back too), until neither finds anything. Each round puts at least
//! one vertex back, so it ends, at worst at the surface before the frame,
//! which did not cross itself. The search reads positions only and puts
//! vertices back in id order, so a frame gives the same bits on any number
//! of threads.
//!
//! A collapse of the frame's adaptation ([`super::region_adapt`]) moves
//! vertices too, after both guards, by up to a short edge. In the same
//! frames, where steps were pulled back and the surface is crumpled into
//! sheets a short edge apart, its new fan is searched against the
//! triangles near it ([`Sculptor::collapse_crosses`]), and a collapse
//! that would cross is not made: a run of 1,000 mirrored stroke pairs
//! found one, seed 595, 5 crossing pairs left by a collapse in a frame
//! both guards had passed. In other frames the search is not made, a
//! measured trade-off rather than a proof: a crumple an earlier frame
//! left stays where a later frame pulls nothing back, but the 1,000
//! seeds (8,000 strokes) then cross nowhere, while searching on every
//! collapse doubled the bench stroke's frame at 2M vertices (the grid's
//! cells hold hundreds of vertices each).
//!
//! Both searches take the triangles at the vertices within the max edge
//! length of what moved: a triangle with longer edges (the base mesh
//! beyond the stroke's region, which is never split) can cross unseen.

use std::collections::HashMap;

use glam::DVec3;

use super::fold_guard::push_unmarked_faces;
use super::halfedge::{FaceId, HalfEdgeId, VertId};
use super::sculptor::{Limits, Move, Sculptor};
use crate::mesh::{self_intersections, triangles_cross, TriMesh};

impl Sculptor {
    /// Puts back the moves that make the surface cross itself (see the
    /// module doc); returns whether it put any back. Adds the triangles
    /// it searched to `searched` (the stroke's work count).
    pub(super) fn prevent_crossings(
        &mut self,
        moves: &mut [Move],
        lim: &Limits,
        searched: &mut usize,
    ) -> bool {
        let mut any = false;
        loop {
            let mut bad = self.crossing_corners(lim, searched);
            let mut changed = self.put_back(moves, &mut bad);
            if changed.is_empty() {
                return any;
            }
            any = true;
            // Folds against the vertices put back, until there are none.
            while !changed.is_empty() {
                let mut folding = Vec::new();
                for f in self.faces_around(&changed) {
                    if self.face_folds(f) {
                        folding.extend(self.mesh.face_verts(f));
                    }
                }
                changed = self.put_back(moves, &mut folding);
            }
        }
    }

    /// The corners, moved this frame, of the triangles near the frame's
    /// moves that cross another triangle (sorted, deduplicated).
    fn crossing_corners(&mut self, lim: &Limits, searched: &mut usize) -> Vec<VertId> {
        let mut near = Vec::new();
        self.grid
            .query(lim.lo, lim.hi, &mut near, &mut self.cand_scratch);
        let stamp = self.next_face_stamp();
        let mut faces: Vec<FaceId> = Vec::new();
        {
            let (mesh, marks) = (&self.mesh, &mut self.face_mark);
            for &v in &near {
                if mesh.vert_alive(v) {
                    push_unmarked_faces(mesh, marks, stamp, v, &mut faces);
                }
            }
        }
        *searched += faces.len();
        let mut local: HashMap<u32, u32> = HashMap::new();
        let mut sub = TriMesh::default();
        for &f in &faces {
            let t = self.mesh.face_verts(f).map(|v| {
                *local.entry(v.0).or_insert_with(|| {
                    sub.positions.push(self.mesh.position(v).to_array());
                    (sub.positions.len() - 1) as u32
                })
            });
            sub.triangles.push(t);
        }
        let mut bad = Vec::new();
        for (a, b) in self_intersections(&sub).pairs {
            for f in [faces[a as usize], faces[b as usize]] {
                bad.extend(
                    self.mesh
                        .face_verts(f)
                        .into_iter()
                        .filter(|&v| self.moved_this_frame(v)),
                );
            }
        }
        bad
    }

    /// Whether collapsing the edge of `h` to `p` (`from(h)` kept and
    /// moved there, `to(h)` removed, as
    /// [`HalfEdgeMesh::collapse_edge`](super::halfedge::HalfEdgeMesh)
    /// does) would make a triangle of the merged vertex's fan cross
    /// another triangle, or another of the fan: the triangles at the
    /// vertices within the max edge length of the fan's box, each tested
    /// against each fan triangle whose box it meets with the exact pair
    /// test of [`crate::mesh::self_intersections`] (which reads shared
    /// corners: two triangles at one vertex may still pass through each
    /// other, which the fold rule's normals do not see).
    pub(super) fn collapse_crosses(&mut self, h: HalfEdgeId, p: DVec3, lim: &Limits) -> bool {
        let (u, v) = (self.mesh.from(h), self.mesh.to(h));
        let gone = [h.face(), self.mesh.twin(h).face()];
        let mut fan: Vec<FaceId> = Vec::new();
        for x in [u, v] {
            self.mesh.for_each_out(x, |g| {
                if !gone.contains(&g.face()) {
                    fan.push(g.face());
                }
            });
        }
        let at = |m: &super::halfedge::HalfEdgeMesh, w: VertId| {
            if w == u || w == v {
                p
            } else {
                m.position(w)
            }
        };
        let (mut lo, mut hi) = (p, p);
        for &f in &fan {
            for w in self.mesh.face_verts(f) {
                lo = lo.min(at(&self.mesh, w));
                hi = hi.max(at(&self.mesh, w));
            }
        }
        let pad = DVec3::splat(lim.max2.sqrt());
        let (lo, hi) = (lo - pad, hi + pad);
        let stamp = self.next_face_stamp();
        let mut faces = fan.clone();
        {
            let (mesh, marks) = (&self.mesh, &mut self.face_mark);
            for &f in fan.iter().chain(&gone) {
                marks[f.0 as usize] = stamp;
            }
            // Whole cells of the grid (hundreds of vertices on a fine
            // mesh): only vertices in the box have triangles that reach
            // the fan. The answer is "any", so the order does not matter.
            self.grid.for_each_near(lo, hi, |w| {
                let x = mesh.position(w);
                if mesh.vert_alive(w) && x.cmpge(lo).all() && x.cmple(hi).all() {
                    push_unmarked_faces(mesh, marks, stamp, w, &mut faces);
                }
            });
        }
        // Each triangle of the fan (`v` merged into `u`) against every
        // other, boxes first.
        let tri = |m: &super::halfedge::HalfEdgeMesh, f: FaceId| {
            let vs = m.face_verts(f);
            let idx = vs.map(|w| if w == v { u.0 } else { w.0 });
            let pos = vs.map(|w| at(m, w));
            let lo = pos[0].min(pos[1]).min(pos[2]);
            let hi = pos[0].max(pos[1]).max(pos[2]);
            (idx, pos, lo, hi)
        };
        let fan: Vec<_> = fan.iter().map(|&f| tri(&self.mesh, f)).collect();
        // The fan's own pairs, then the fan against the others.
        faces.iter().enumerate().skip(1).any(|(j, &g)| {
            let (tb, pb, lb, hb) = tri(&self.mesh, g);
            fan[..j.min(fan.len())].iter().any(|&(ta, pa, la, ha)| {
                la.cmple(hb).all() && lb.cmple(ha).all() && triangles_cross(ta, pa, tb, pb)
            })
        })
    }

    /// Whether `v` is one of this frame's moves.
    #[inline]
    fn moved_this_frame(&self, v: VertId) -> bool {
        self.old_mark.get(v.0 as usize) == Some(&self.frame_stamp)
    }

    /// Puts the moves of `bad` back where they were before the frame;
    /// returns the vertices that changed position, in id order. A rigid
    /// move put back no longer moves with its neighbours: its triangles
    /// change shape, so it joins the frame's region.
    fn put_back(&mut self, moves: &mut [Move], bad: &mut Vec<VertId>) -> Vec<VertId> {
        bad.sort_unstable();
        bad.dedup();
        let mut changed = Vec::new();
        if bad.is_empty() {
            return changed;
        }
        for (v, old, new, rigid) in moves.iter_mut() {
            if *new != *old && bad.binary_search(v).is_ok() {
                *new = *old;
                self.mesh.set_position(*v, *old);
                if *rigid {
                    *rigid = false;
                    self.moved_mark[v.0 as usize] = self.frame_stamp;
                    self.mark(*v, true);
                }
                changed.push(*v);
            }
        }
        changed
    }
}
