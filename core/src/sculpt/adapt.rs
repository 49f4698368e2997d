//! Resolution adaptation (paper §5.3): recursive longest-edge bisection
//! above the max edge length, shortest-edge collapse below the min edge
//! length, both only in the region a frame touched.
//!
//! Choices:
//! - **Conforming splits.** An edge is split only when it is also the
//!   longest edge of the triangle on its other side; otherwise that edge is
//!   split first (Rivara's LEPP), so no hanging nodes appear and triangles
//!   keep their shape classes. Edges are ordered by (squared length, vertex
//!   ids), a strict total order, so the recursion always terminates.
//! - **Safe collapses.** A collapse is refused unless the link condition
//!   holds (the two endpoints share exactly the two opposite vertices),
//!   both opposite vertices keep degree >= 3, no surrounding triangle flips
//!   (normal turns by more than 60 degrees) or folds onto a triangle it
//!   shares a vertex with (the fold guard's rule, `super::fold_guard`),
//!   becomes degenerate or badly shaped (quality below [`MIN_QUALITY`] and
//!   worse than before), and no new edge exceeds the max length (so
//!   collapses and splits never ping-pong).
//! - **Only movable vertices move.** A collapse removes a vertex the stroke
//!   already moved or created; if both endpoints are movable they meet at
//!   the midpoint, otherwise the movable one goes to the fixed one. So a
//!   vertex no brush reached keeps its exact bits.

use glam::DVec3;

use super::fold_guard::folds_after;
use super::halfedge::{FaceId, HalfEdgeId, HalfEdgeMesh, VertId};

/// Collapses never create triangles with a quality (`4√3·area / Σ edge²`,
/// 1 for equilateral) below this, unless the triangle was already worse.
pub const MIN_QUALITY: f64 = 0.15;

/// No edit leaves a triangle of a quality below this: a sliver whose
/// height is about a millionth of its edges (the print's validator calls
/// such triangles degenerate once the model is a few hundred edges wide,
/// and float32 rounding flattens them).
pub const MIN_FACE_QUALITY: f64 = 1e-6;

/// Squared edge key: a strict total order on edges.
#[inline]
fn edge_key(m: &HalfEdgeMesh, h: HalfEdgeId) -> (f64, u32, u32) {
    let (a, b) = (m.from(h).0, m.to(h).0);
    (m.edge_len2(h), a.min(b), a.max(b))
}

#[inline]
fn key_gt(x: (f64, u32, u32), y: (f64, u32, u32)) -> bool {
    match x.0.total_cmp(&y.0) {
        std::cmp::Ordering::Greater => true,
        std::cmp::Ordering::Less => false,
        std::cmp::Ordering::Equal => (x.1, x.2) > (y.1, y.2),
    }
}

/// Triangle quality `4√3·area / (a² + b² + c²)`: 1 for equilateral, 0 for
/// degenerate.
#[inline]
pub fn quality(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let s = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    if s <= 0.0 {
        return 0.0;
    }
    2.0 * 3f64.sqrt() * (b - a).cross(c - a).length() / s
}

impl HalfEdgeMesh {
    /// The longest half-edge of face `f` (by the strict edge order).
    pub fn longest_edge(&self, f: FaceId) -> HalfEdgeId {
        let mut best = f.half_edge(0);
        let mut bk = edge_key(self, best);
        for i in 1..3 {
            let h = f.half_edge(i);
            let k = edge_key(self, h);
            if key_gt(k, bk) {
                best = h;
                bk = k;
            }
        }
        best
    }

    /// The half-edge from `a` to `b`, if the edge exists.
    pub fn find_half_edge(&self, a: VertId, b: VertId) -> Option<HalfEdgeId> {
        if !self.vert_alive(a) {
            return None;
        }
        let mut found = None;
        self.for_each_out(a, |h| {
            if found.is_none() && self.to(h) == b {
                found = Some(h);
            }
        });
        found
    }

    /// Splits the edge of `h` at its midpoint, splitting both adjacent
    /// triangles in two. Returns the new vertex. Does not check shapes:
    /// use [`Self::split_conforming`] for longest-edge bisection.
    pub fn split_edge(&mut self, h: HalfEdgeId) -> VertId {
        let t = self.twin(h);
        let (e1, e2) = (h.next(), h.prev());
        let g1 = t.next();
        let g2 = t.prev();
        let a = self.from(h);
        let b = self.to(h);
        let c = self.to(e1);
        let d = self.to(g1);
        let (t1, t2, u1, u2) = (self.twin(e1), self.twin(e2), self.twin(g1), self.twin(g2));
        let (f0, f1) = (h.face(), t.face());
        let mid = (self.position(a) + self.position(b)) * 0.5;
        let m = self.new_vertex(mid);
        let fa = self.new_face();
        let fb = self.new_face();
        self.write_face(f0, [a, m, c]);
        self.write_face(fa, [m, b, c]);
        self.write_face(f1, [b, m, d]);
        self.write_face(fb, [m, a, d]);
        self.link(f0.half_edge(0), fb.half_edge(0));
        self.link(f0.half_edge(1), fa.half_edge(2));
        self.link(f0.half_edge(2), t2);
        self.link(fa.half_edge(0), f1.half_edge(0));
        self.link(fa.half_edge(1), t1);
        self.link(f1.half_edge(1), fb.half_edge(2));
        self.link(f1.half_edge(2), u2);
        self.link(fb.half_edge(1), u1);
        self.vert_he[a.0 as usize] = f0.half_edge(0).0;
        self.vert_he[b.0 as usize] = fa.half_edge(1).0;
        self.vert_he[c.0 as usize] = f0.half_edge(2).0;
        self.vert_he[d.0 as usize] = f1.half_edge(2).0;
        self.vert_he[m.0 as usize] = f0.half_edge(1).0;
        m
    }

    /// Recursive longest-edge bisection of the edge of `h` (which should be
    /// the longest edge of its face): while the edge is not also the
    /// longest edge of the triangle across it, that triangle's longest edge
    /// is bisected first. New vertices are appended to `created`, each
    /// with whether it bisected the requested edge (`true`) or an edge the
    /// recursion needed (`false`).
    pub fn split_conforming(&mut self, h: HalfEdgeId, created: &mut Vec<(VertId, bool)>) {
        let mut stack = vec![(self.from(h), self.to(h))];
        while let Some(&(a, b)) = stack.last() {
            let Some(h) = self.find_half_edge(a, b) else {
                stack.pop();
                continue;
            };
            let t = self.twin(h);
            let l = self.longest_edge(t.face());
            if l == t {
                let m = self.split_edge(h);
                stack.pop();
                created.push((m, stack.is_empty()));
            } else {
                stack.push((self.from(l), self.to(l)));
            }
        }
    }

    /// Collapses the edge of `h`, removing `to(h)` and moving `from(h)` to
    /// `p`, if that keeps the mesh a valid manifold with no flipped,
    /// degenerate or badly shaped triangle and no edge longer than
    /// `max_len2.sqrt()`. Returns whether it collapsed.
    pub fn try_collapse(&mut self, h: HalfEdgeId, p: DVec3, max_len2: f64) -> bool {
        if self.collapse_refusal(h, p, max_len2).is_some() {
            return false;
        }
        self.collapse_edge(h, p);
        true
    }

    /// Collapses the edge of `h` as [`Self::try_collapse`] does, once
    /// [`Self::collapse_refusal`] allowed it.
    pub(super) fn collapse_edge(&mut self, h: HalfEdgeId, p: DVec3) {
        let t = self.twin(h);
        let u = self.from(h);
        let v = self.to(h);
        let c = self.to(h.next());
        let d = self.to(t.next());
        let (f0, f1) = (h.face(), t.face());
        // Rename v to u on every half-edge entering v.
        let mut incoming = Vec::with_capacity(16);
        self.for_each_out(v, |g| incoming.push(g.prev()));
        for g in incoming {
            self.he_to[g.0 as usize] = u.0;
        }
        let (x, y) = (self.twin(h.next()), self.twin(h.prev()));
        let (z, w) = (self.twin(t.next()), self.twin(t.prev()));
        self.link(x, y);
        self.link(z, w);
        self.vert_he[u.0 as usize] = y.0;
        self.vert_he[c.0 as usize] = x.0;
        self.vert_he[d.0 as usize] = z.0;
        self.remove_face(f0);
        self.remove_face(f1);
        self.remove_vertex(v);
        self.set_position(u, p);
    }

    /// Why collapsing the edge of `h` (removing `to(h)`, moving `from(h)`
    /// to `p`) is refused, or `None` when it is allowed.
    pub fn collapse_refusal(
        &self,
        h: HalfEdgeId,
        p: DVec3,
        max_len2: f64,
    ) -> Option<CollapseRefusal> {
        let t = self.twin(h);
        let u = self.from(h);
        let v = self.to(h);
        let c = self.to(h.next());
        let d = self.to(t.next());
        if c == d || self.degree(c) <= 3 || self.degree(d) <= 3 {
            return Some(CollapseRefusal::Degree);
        }
        // Link condition: common neighbours of u and v are exactly c and d.
        let mut nu: [u32; 64] = [0; 64];
        let mut nn = 0usize;
        let mut overflow = false;
        self.for_each_out(u, |g| {
            if nn < 64 {
                nu[nn] = self.to(g).0;
                nn += 1;
            } else {
                overflow = true;
            }
        });
        if overflow {
            return Some(CollapseRefusal::Degree);
        }
        let mut ok = true;
        self.for_each_out(v, |g| {
            let w = self.to(g);
            if w != c && w != d && w != u && nu[..nn].contains(&w.0) {
                ok = false;
            }
        });
        if !ok {
            return Some(CollapseRefusal::Link);
        }
        // Geometry of every triangle that survives and changes.
        let (f0, f1) = (h.face(), t.face());
        // Normal of face `f` after the collapse.
        let new_normal = |m: &HalfEdgeMesh, f: FaceId| -> DVec3 {
            let n = m
                .face_verts(f)
                .map(|w| if w == u || w == v { p } else { m.position(w) });
            (n[1] - n[0]).cross(n[2] - n[0])
        };
        let folds = |a: DVec3, b: DVec3| a.dot(b) <= -0.5 * a.length() * b.length();
        let check = |m: &HalfEdgeMesh, x: VertId| -> Option<CollapseRefusal> {
            let mut why = None;
            m.for_each_out(x, |g| {
                if why.is_some() {
                    return;
                }
                let f = g.face();
                if f == f0 || f == f1 {
                    return;
                }
                let vs = m.face_verts(f);
                let old = vs.map(|w| m.position(w));
                let new = vs.map(|w| if w == u || w == v { p } else { m.position(w) });
                let n_old = (old[1] - old[0]).cross(old[2] - old[0]);
                let n_new = (new[1] - new[0]).cross(new[2] - new[0]);
                let q_new = quality(new[0], new[1], new[2]);
                let q_old = quality(old[0], old[1], old[2]);
                // Every triangle sharing a vertex with this one, as the
                // fold guard checks a warp step.
                let mut fold_with_neighbour = false;
                for w in vs {
                    // After the collapse `u` and `v` are one vertex.
                    let merged = w == u || w == v;
                    let fans = if merged { [u, v] } else { [w, w] };
                    for &x in &fans[..if merged { 2 } else { 1 }] {
                        m.for_each_out(x, |k| {
                            let g = k.face();
                            if fold_with_neighbour || g == f || g == f0 || g == f1 {
                                return;
                            }
                            fold_with_neighbour = folds_after(n_new, new_normal(m, g), || {
                                (n_old, m.face_area_vec(g))
                            });
                        });
                    }
                }
                if n_new.dot(n_old) <= 0.5 * n_new.length() * n_old.length() || fold_with_neighbour
                {
                    why = Some(CollapseRefusal::Flip);
                } else if q_new < MIN_QUALITY.min(q_old)
                    || q_new.is_nan()
                    || q_new < MIN_FACE_QUALITY
                {
                    why = Some(CollapseRefusal::Shape);
                }
                let far = m.to(g);
                if why.is_none()
                    && far != u
                    && far != v
                    && m.position(far).distance_squared(p) > max_len2
                {
                    why = Some(CollapseRefusal::TooLong);
                }
            });
            why
        };
        check(self, u).or_else(|| check(self, v)).or_else(|| {
            // The faces that become neighbours across the merged edges.
            let pairs = [
                (self.twin(h.next()).face(), self.twin(h.prev()).face()),
                (self.twin(t.next()).face(), self.twin(t.prev()).face()),
            ];
            pairs
                .iter()
                .any(|&(a, b)| folds(new_normal(self, a), new_normal(self, b)))
                .then_some(CollapseRefusal::Flip)
        })
    }
}

/// Why a collapse was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CollapseRefusal {
    /// An opposite vertex would be left with degree 2 (or a fan is huge).
    Degree,
    /// The endpoints share a neighbour besides the two opposite vertices.
    Link,
    /// A surrounding triangle would turn by more than 60 degrees.
    Flip,
    /// A surrounding triangle would become degenerate or badly shaped.
    Shape,
    /// A new edge would exceed the max length.
    TooLong,
}
