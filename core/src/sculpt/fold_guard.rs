//! The fold guard of a frame ([`Sculptor::apply_frame`]): what a warp
//! step may not do to the surface, and how a step that does is taken back.
//!
//! A step may not make a triangle degenerate (quality below
//! [`MIN_FACE_QUALITY`]) or fold it onto a triangle it shares a vertex
//! with: their normals more than 120 degrees apart, or more than 90 and
//! further apart than before the step. Checking only the three edge
//! neighbours at 120 degrees (what this guard did before issue 33) let a
//! vertex's fan fold over itself and let pleats of three or four
//! triangles pass, each crease within the limit: the surface then crossed
//! itself within a few millimetres, in about one stroke pair in eight of
//! mirrored strokes on the headset's presets (17 of 140 random
//! sequences; none with this rule, and none of 140 without the mirror).
//! "Than before" keeps creases the surface already has (a box base's
//! edges, an imported part's rims) movable: a step may not sharpen them.
//! The collapses of [`super::adapt`] obey the same rule.

use glam::DVec3;

use super::adapt::{quality, MIN_FACE_QUALITY};
use super::halfedge::{FaceId, VertId};
use super::par;
use super::sculptor::{Limits, Move, Sculptor};

impl Sculptor {
    /// Fold guard: a warp step that would fold a triangle onto a triangle
    /// it shares a vertex with, or make it degenerate ([`Self::face_folds`])
    /// is halved for that triangle's moved vertices, up to three times,
    /// then undone for them. Converging warps (collapse onto a small
    /// brush) would otherwise crumple the surface within a few frames.
    ///
    /// The first round's pass over the region also takes, for
    /// [`Self::adapt`], each triangle's split test and marks the vertices
    /// with a short edge (`short_mark`): the region's fans and triangle
    /// owners are the same ones (every reshaped vertex moved, and only
    /// those). Returns the split tests when they still hold (no vertex was
    /// pulled back), `None` otherwise.
    pub(super) fn prevent_folds(
        &mut self,
        moves: &mut [Move],
        lim: &Limits,
    ) -> Option<Vec<(FaceId, bool)>> {
        let mut round = 0;
        let mut changed: Vec<VertId> = Vec::new();
        loop {
            if round == 0 {
                let this = &*self;
                let parts = par::map_chunks(moves, |_, chunk| {
                    let mut bad: Vec<VertId> = Vec::new();
                    let mut split: Vec<(FaceId, bool)> = Vec::new();
                    let mut short: Vec<VertId> = Vec::new();
                    for &(v, _, _, rigid) in chunk {
                        if rigid {
                            continue;
                        }
                        debug_assert!(this.in_frame(v) && this.moved(v));
                        let mut any_short = false;
                        this.mesh.for_each_out(v, |h| {
                            any_short |= this.mesh.edge_len2(h) < lim.min2;
                            let f = h.face();
                            let vs = this.mesh.face_verts(f);
                            let owner = vs.iter().filter(|&&w| this.moved(w)).min();
                            if owner == Some(&v) {
                                if this.face_folds(f) {
                                    bad.extend(vs.iter().filter(|&&w| this.moved(w)));
                                }
                                split.push((f, this.wants_split(f, lim.max2, lim.lo, lim.hi)));
                            }
                        });
                        if any_short {
                            short.push(v);
                        }
                    }
                    (bad, split, short)
                });
                let mut bad_verts = Vec::new();
                let mut split = Vec::with_capacity(parts.iter().map(|p| p.1.len()).sum());
                for (b, sp, sh) in parts {
                    bad_verts.extend(b);
                    split.extend(sp);
                    for v in sh {
                        self.short_mark[v.0 as usize] = self.frame_stamp;
                    }
                }
                if bad_verts.is_empty() {
                    return Some(split);
                }
                changed = self.pull_back(moves, &mut bad_verts, round);
                if changed.is_empty() {
                    return Some(split);
                }
                round += 1;
                continue;
            }
            // Only triangles at a vertex pulled back in the last round can
            // have changed their verdict (the verdict of a triangle reads
            // the triangles it shares a vertex with, and a pull-back moves
            // only the triangles at the vertex): each is tested once; the
            // corners of folding ones that moved are the offenders. (The
            // same offenders as a pass over every moved vertex: a triangle
            // still folding from before kept its corners, so its corners
            // were pulled back already, or are back where they were.)
            let faces = self.faces_around(&changed);
            let this = &*self;
            let mut bad_verts: Vec<VertId> = par::flat_map_chunks(&faces, |_, chunk, out| {
                for &f in chunk {
                    if this.face_folds(f) {
                        out.extend(this.mesh.face_verts(f).iter().filter(|&&w| this.moved(w)));
                    }
                }
            });
            if bad_verts.is_empty() {
                return None;
            }
            changed = self.pull_back(moves, &mut bad_verts, round);
            if changed.is_empty() {
                return None;
            }
            round += 1;
        }
    }

    /// Halves (from `round` 3 on: undoes) the step of the offending
    /// vertices `bad_verts`; returns the vertices whose position changed,
    /// in id order.
    fn pull_back(
        &mut self,
        moves: &mut [Move],
        bad_verts: &mut Vec<VertId>,
        round: u32,
    ) -> Vec<VertId> {
        bad_verts.sort_unstable();
        bad_verts.dedup();
        // Halve three times, then undo; undoing stops once every offending
        // vertex is back where it was (each undo round restores at least
        // one vertex, so this terminates).
        let mut changed = Vec::new();
        for (v, old, new, rigid) in moves.iter_mut() {
            if !*rigid && bad_verts.binary_search(v).is_ok() && *new != *old {
                *new = if round >= 3 {
                    *old
                } else {
                    *old + (*new - *old) * 0.5
                };
                self.mesh.set_position(*v, *new);
                changed.push(*v);
            }
        }
        changed.sort_unstable();
        changed
    }

    /// Where `v` was before this frame's warp.
    #[inline]
    fn before(&self, v: VertId) -> DVec3 {
        if self.old_mark.get(v.0 as usize) == Some(&self.frame_stamp) {
            self.old_pos[v.0 as usize]
        } else {
            self.mesh.position(v)
        }
    }

    /// Area vector of face `f` before this frame's warp.
    fn area_before(&self, f: FaceId) -> DVec3 {
        let [a, b, c] = self.mesh.face_verts(f).map(|v| self.before(v));
        (b - a).cross(c - a)
    }

    /// True when face `f` is degenerate or folds onto a face it shares a
    /// vertex with (see the module doc).
    pub(super) fn face_folds(&self, f: FaceId) -> bool {
        let [a, b, c] = self.mesh.face_verts(f).map(|v| self.mesh.position(v));
        let q = quality(a, b, c);
        if q.is_nan() || q < MIN_FACE_QUALITY {
            return true;
        }
        let n = self.mesh.face_area_vec(f);
        let mut bad = false;
        for v in self.mesh.face_verts(f) {
            self.mesh.for_each_out(v, |h| {
                let g = h.face();
                if bad || g == f {
                    return;
                }
                let m = self.mesh.face_area_vec(g);
                bad = folds_after(n, m, || (self.area_before(f), self.area_before(g)));
            });
            if bad {
                return true;
            }
        }
        false
    }
}

/// Whether two triangles with area vectors `n` and `m` (sharing a vertex)
/// fold onto each other: more than 120 degrees apart, or more than 90
/// and further apart than their area vectors `before()` were.
#[inline]
pub(super) fn folds_after(n: DVec3, m: DVec3, before: impl FnOnce() -> (DVec3, DVec3)) -> bool {
    let l = n.length() * m.length();
    let d = n.dot(m);
    // (NaN lengths count as degenerate: `l.is_nan() || l <= 0` is
    // `!(l > 0)`.)
    if l.is_nan() || l <= 0.0 || d <= -0.5 * l {
        return true;
    }
    if d > 0.0 {
        return false;
    }
    let (nb, mb) = before();
    let lb = nb.length() * mb.length();
    // Cosines compared without dividing: d / l < db / lb.
    lb.is_nan() || lb <= 0.0 || d * lb < (nb.dot(mb) - CREASE_TOLERANCE * lb) * l
}

/// Slack on the cosine of a crease that may not sharpen (rounding of a
/// step halved back to nearly nothing).
const CREASE_TOLERANCE: f64 = 1e-9;

impl Sculptor {
    /// The triangles at any of `verts`, each once, in the order met.
    pub(super) fn faces_around(&mut self, verts: &[VertId]) -> Vec<FaceId> {
        let stamp = self.next_face_stamp();
        let mut faces = Vec::new();
        let (mesh, marks) = (&self.mesh, &mut self.face_mark);
        for &v in verts {
            mesh.for_each_out(v, |h| {
                let f = h.face();
                if marks[f.0 as usize] != stamp {
                    marks[f.0 as usize] = stamp;
                    faces.push(f);
                }
            });
        }
        faces
    }
}
