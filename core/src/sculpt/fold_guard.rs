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
use super::halfedge::{FaceId, HalfEdgeId, HalfEdgeMesh, VertId};
use super::par;
use super::sculptor::{Limits, Move, Sculptor};

/// A triangle of a vertex's fan, as the fold guard reads it.
pub(super) struct FanFace {
    /// The half-edge out of the vertex on this triangle.
    h: HalfEdgeId,
    f: FaceId,
    verts: [VertId; 3],
    /// Area vector and its length.
    n: DVec3,
    len: f64,
    /// The least of its vertices that moved this frame, if any.
    owner: Option<VertId>,
}

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
                    let (mut fan, mut rim_fan) = (Vec::new(), Vec::new());
                    let mut folding = Vec::new();
                    for &(v, _, _, rigid) in chunk {
                        if rigid {
                            continue;
                        }
                        debug_assert!(this.in_frame(v) && this.moved(v));
                        this.fan(v, &mut fan);
                        let mut any_short = false;
                        for t in &fan {
                            any_short |= this.mesh.edge_len2(t.h) < lim.min2;
                            if t.owner == Some(v) {
                                if this.face_degenerate(t.f) {
                                    bad.extend(t.verts.iter().filter(|&&w| this.moved(w)));
                                }
                                split.push((t.f, this.wants_split(t.f, lim.max2, lim.lo, lim.hi)));
                            }
                        }
                        if any_short {
                            short.push(v);
                        }
                        // The fans of the moved vertex and of the unmoved
                        // neighbours it is the least moved neighbour of:
                        // every vertex of a moved triangle, once.
                        this.fan_folds(&fan, &mut folding);
                        for t in &fan {
                            let u = this.mesh.to(t.h);
                            if !this.moved(u) && this.least_moved_neighbour(u) == Some(v) {
                                this.fan(u, &mut rim_fan);
                                this.fan_folds(&rim_fan, &mut folding);
                            }
                        }
                    }
                    for f in folding {
                        bad.extend(this.mesh.face_verts(f).iter().filter(|&&w| this.moved(w)));
                    }
                    (bad, split, short)
                });
                #[cfg(test)]
                self.check_fold_pass(moves, parts.iter().flat_map(|p| p.0.iter().copied()));
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

    /// In the unit tests, every first round: the offenders the pass over
    /// the fans found are those [`Self::face_folds`] finds, triangle by
    /// triangle (the definition the pass computes with fewer area
    /// vectors).
    #[cfg(test)]
    fn check_fold_pass(&self, moves: &[Move], found: impl Iterator<Item = VertId>) {
        let mut expected: Vec<VertId> = Vec::new();
        for &(v, _, _, rigid) in moves {
            if rigid {
                continue;
            }
            self.mesh.for_each_out(v, |h| {
                let vs = self.mesh.face_verts(h.face());
                let owner = vs.iter().copied().filter(|&w| self.moved(w)).min();
                if owner == Some(v) && self.face_folds(h.face()) {
                    expected.extend(vs.iter().filter(|&&w| self.moved(w)));
                }
            });
        }
        let mut found: Vec<VertId> = found.collect();
        for s in [&mut expected, &mut found] {
            s.sort_unstable();
            s.dedup();
        }
        assert_eq!(found, expected, "the fold pass and face_folds disagree");
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

    /// True when face `f` is degenerate (quality below
    /// [`MIN_FACE_QUALITY`]).
    fn face_degenerate(&self, f: FaceId) -> bool {
        let [a, b, c] = self.mesh.face_verts(f).map(|v| self.mesh.position(v));
        let q = quality(a, b, c);
        q.is_nan() || q < MIN_FACE_QUALITY
    }

    /// The least neighbour of `u` that moved non-rigidly this frame.
    fn least_moved_neighbour(&self, u: VertId) -> Option<VertId> {
        let mut least: Option<VertId> = None;
        self.mesh.for_each_out(u, |h| {
            let w = self.mesh.to(h);
            if self.moved(w) && least.is_none_or(|l| w < l) {
                least = Some(w);
            }
        });
        least
    }

    /// The triangles at `w` (`out`, cleared first), in fan order.
    fn fan(&self, w: VertId, out: &mut Vec<FanFace>) {
        out.clear();
        self.mesh.for_each_out(w, |h| {
            let f = h.face();
            let verts = self.mesh.face_verts(f);
            let n = self.mesh.face_area_vec(f);
            let owner = verts.iter().copied().filter(|&x| self.moved(x)).min();
            out.push(FanFace {
                h,
                f,
                verts,
                n,
                len: n.length(),
                owner,
            });
        });
    }

    /// Appends to `out` the triangles of `fan` (the triangles at a vertex)
    /// with a moved vertex that fold onto another of them
    /// ([`folds_after`]), testing each pair once with each area vector and
    /// its length computed once. Over the fans of every vertex of the
    /// moved triangles this finds what [`Self::face_folds`] finds for each
    /// of them, with about a fifth of the area vectors: the test is
    /// symmetric (bit for bit), so a pair need not be seen from both sides.
    fn fan_folds(&self, fan: &[FanFace], out: &mut Vec<FaceId>) {
        for (i, a) in fan.iter().enumerate() {
            for b in &fan[i + 1..] {
                let (ma, mb) = (a.owner.is_some(), b.owner.is_some());
                if (ma || mb)
                    && folds_after_with(a.n, a.len, b.n, b.len, || {
                        (self.area_before(a.f), self.area_before(b.f))
                    })
                {
                    if ma {
                        out.push(a.f);
                    }
                    if mb {
                        out.push(b.f);
                    }
                }
            }
        }
    }

    /// True when face `f` is degenerate or folds onto a face it shares a
    /// vertex with (see the module doc).
    pub(super) fn face_folds(&self, f: FaceId) -> bool {
        if self.face_degenerate(f) {
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
    folds_after_with(n, n.length(), m, m.length(), before)
}

/// [`folds_after`] with the lengths of `n` and `m` given. The same bits
/// with `n` and `m` swapped (every product and sum in it commutes).
#[inline]
fn folds_after_with(
    n: DVec3,
    ln: f64,
    m: DVec3,
    lm: f64,
    before: impl FnOnce() -> (DVec3, DVec3),
) -> bool {
    let l = ln * lm;
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
        for &v in verts {
            push_unmarked_faces(&self.mesh, &mut self.face_mark, stamp, v, &mut faces);
        }
        faces
    }
}

/// Appends to `out` the triangles at `v` that `marks` does not hold at
/// `stamp`, marking them: over many vertices, each triangle once.
pub(super) fn push_unmarked_faces(
    mesh: &HalfEdgeMesh,
    marks: &mut [u32],
    stamp: u32,
    v: VertId,
    out: &mut Vec<FaceId>,
) {
    mesh.for_each_out(v, |h| {
        let f = h.face();
        if marks[f.0 as usize] != stamp {
            marks[f.0 as usize] = stamp;
            out.push(f);
        }
    });
}
