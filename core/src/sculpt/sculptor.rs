//! [`Sculptor`]: a surface under sculpting with its vertex hash grid and
//! per-frame scratch; one call of [`Sculptor::apply_frame`] is one frame of
//! paper §4.1 (warp, §4.4) followed by resolution adaptation (§5.3, in
//! `sculpt::region_adapt`).
//!
//! A frame costs time proportional to the vertices the brush reaches,
//! never a pass over the whole mesh: the reach is found in the hash grid,
//! every mark is a stamp compared with the frame's (no clearing), and
//! scratch buffers are kept between frames.
//!
//! The read-only passes over the reached vertices run in parallel over
//! fixed chunks (`sculpt::par`): the warp of each vertex, the fold test of
//! each changed triangle, the normals of [`Sculptor::sync_render`] and the
//! split and collapse candidate tests. A triangle is tested by exactly one
//! of its corners (the smallest id among the corners that qualify), so no
//! shared "seen" marks are needed. The passes that edit the mesh stay
//! sequential and visit the candidates in the same order as a sequential
//! scan would, so a frame gives the same bits on any number of threads and
//! the same bits as before these passes went parallel (the fixture hashes
//! of the sculpt scripts did not change).
//!
//! A brush reaches the vertices within its bound radius (scaled) plus `h`
//! of its origin; beyond that the weight is 0 by definition (for the exact
//! fields this is implied by `d >= h`; for the ellipsoid bound and grid
//! fields it makes the region explicit).

use glam::DVec3;
use rayon::prelude::*;

use super::brush::{BrushPose, BrushShape};
use super::grid::VertexGrid;
use super::halfedge::{FaceId, HalfEdgeMesh, VertId};
use super::par;
use super::render::{to_ranges, vertex_normal, DirtySlots, RenderBuffers};
use super::warp::{DragIncrement, Falloff, Warp};

/// Candidate count from which a frame's warp is evaluated in parallel
/// (below it, thread hand-off costs more than it saves).
const PARALLEL_MIN: usize = 8192;
/// Candidates per parallel chunk (fixed, so the split never depends on the
/// thread count; the results are appended in order either way).
const PARALLEL_CHUNK: usize = 2048;

/// One frame's input, in model space.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    /// Brush shape.
    pub shape: &'a BrushShape,
    /// The shape's [`BrushShape::bound_radius`] (a pass over a grid
    /// brush's samples: computed once per stroke, see
    /// [`BrushShape::extent`]).
    pub bound: f64,
    /// Brush pose at the previous sample (equal to `pose` on the first).
    pub prev: BrushPose,
    /// Brush pose at this sample.
    pub pose: BrushPose,
    /// Pressure in [0, 1].
    pub pressure: f64,
    /// Influence size `h`.
    pub influence: f64,
    /// Weight falloff.
    pub falloff: Falloff,
    /// Warp.
    pub warp: Warp,
    /// Max edge length.
    pub max_len: f64,
    /// Min edge length.
    pub min_len: f64,
}

/// What one frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Vertices the frame looked at (those in the cells its reach meets).
    pub visited: usize,
    /// Vertices moved by the warp.
    pub moved: usize,
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Triangles the crossing guard searched (each search over the
    /// triangles near the frame's moves counts them all; see
    /// [`super::budget::GUARD_UNITS`]).
    pub guard_faces: usize,
}

impl std::ops::AddAssign for FrameStats {
    fn add_assign(&mut self, o: Self) {
        self.visited += o.visited;
        self.moved += o.moved;
        self.splits += o.splits;
        self.collapses += o.collapses;
        self.guard_faces += o.guard_faces;
    }
}

/// One vertex move of a frame: vertex, old and new position, and whether
/// it moves rigidly with every neighbour (its triangles keep their shape).
pub(super) type Move = (VertId, DVec3, DVec3, bool);

/// A frame's adaptation limits: squared max and min edge lengths and the
/// box of its moves (padded by the max length).
pub(super) struct Limits {
    pub(super) max2: f64,
    pub(super) min2: f64,
    pub(super) lo: DVec3,
    pub(super) hi: DVec3,
}

/// A surface under sculpting, with its spatial index and scratch.
#[derive(Clone, Debug)]
pub struct Sculptor {
    pub(super) mesh: HalfEdgeMesh,
    pub(super) grid: VertexGrid,
    pub(super) stroke_mark: Vec<u32>,
    pub(super) stroke_stamp: u32,
    pub(super) frame_mark: Vec<u32>,
    pub(super) moved_mark: Vec<u32>,
    pub(super) rigid_mark: Vec<u32>,
    /// Per vertex: `frame_stamp` when it may have an edge below the min
    /// length (a superset of those that do; see `region_adapt`).
    pub(super) short_mark: Vec<u32>,
    /// Per vertex: its position before this frame's warp, valid where
    /// `old_mark` is `frame_stamp` (the fold guard compares creases with
    /// how they were).
    pub(super) old_pos: Vec<DVec3>,
    pub(super) old_mark: Vec<u32>,
    pub(super) frame_stamp: u32,
    cand: Vec<VertId>,
    pub(super) cand_scratch: Vec<VertId>,
    /// The collapse phase's candidates (scratch).
    pub(super) collapse_cands: Vec<VertId>,
    /// Vertices the frame's splits created (scratch).
    pub(super) split_new: Vec<VertId>,
    /// A vertex ring or list of stamped vertices (scratch).
    pub(super) ring: Vec<VertId>,
    moves: Vec<Move>,
    pub(super) face_mark: Vec<u32>,
    pub(super) face_stamp: u32,
    /// Vertices whose neighbourhood changed shape this frame, in the order
    /// they were marked (ascending ids from the warp, then new vertices).
    pub(super) region: Vec<VertId>,
    pub(super) queue: Vec<FaceId>,
    /// Per vertex: stamp of the last collapse that changed its edges.
    pub(super) dirty_mark: Vec<u32>,
    pub(super) dirty_stamp: u32,
    /// Vertices moved, created or re-linked since the last `sync_render`
    /// (each once), with their stamp per slot.
    changed: Vec<VertId>,
    changed_mark: Vec<u32>,
    change_stamp: u32,
    /// Faces removed since the last `sync_render`.
    pub(super) removed_faces: Vec<FaceId>,
    id_scratch: Vec<u32>,
    /// Faces past which refinement stops and the stroke fails
    /// ([`super::budget::MAX_TRIANGLES`] unless set).
    pub(super) face_limit: usize,
    /// Whether a frame stopped refining at `face_limit`.
    pub(super) over_budget: bool,
    /// The face count when refinement stopped (above `face_limit`).
    pub(super) stopped_at: usize,
}

impl Sculptor {
    /// Takes `mesh` and indexes its vertices in cells of size `cell`
    /// (about the brush size plus `h` is a good choice).
    pub fn new(mut mesh: HalfEdgeMesh, cell: f64) -> Self {
        // Headroom for refinement: the first split of a stroke must not
        // reallocate (and page in) every array of a large mesh.
        let n = mesh.vertex_capacity() as usize;
        let extra = (n / 4).max(1024);
        mesh.reserve(extra);
        let grid = VertexGrid::build(&mesh, cell, n + extra);
        let marks = || {
            let mut v = Vec::with_capacity(n + extra);
            v.resize(n, 0u32);
            v
        };
        let mut face_mark = Vec::with_capacity(mesh.face_capacity() as usize + 2 * extra);
        face_mark.resize(mesh.face_capacity() as usize, 0);
        Self {
            mesh,
            grid,
            stroke_mark: marks(),
            stroke_stamp: 1,
            frame_mark: marks(),
            moved_mark: marks(),
            rigid_mark: marks(),
            short_mark: marks(),
            old_pos: {
                let mut v = Vec::with_capacity(n + extra);
                v.resize(n, DVec3::ZERO);
                v
            },
            old_mark: marks(),
            face_mark,
            face_stamp: 0,
            frame_stamp: 1,
            cand: Vec::new(),
            cand_scratch: Vec::new(),
            collapse_cands: Vec::new(),
            split_new: Vec::new(),
            ring: Vec::new(),
            moves: Vec::new(),
            region: Vec::new(),
            queue: Vec::new(),
            dirty_mark: marks(),
            dirty_stamp: 0,
            changed: Vec::new(),
            changed_mark: marks(),
            change_stamp: 1,
            removed_faces: Vec::new(),
            id_scratch: Vec::new(),
            face_limit: super::budget::MAX_TRIANGLES,
            over_budget: false,
            stopped_at: 0,
        }
    }

    /// Sets the face count past which refinement stops (see
    /// [`super::budget`]); a frame that reaches it leaves
    /// [`Self::over_budget`] set.
    pub fn set_face_limit(&mut self, faces: usize) {
        self.face_limit = faces;
    }

    /// Whether a frame stopped refining at the face limit (the surface is
    /// then valid but under-refined: a stroke fails).
    pub fn over_budget(&self) -> bool {
        self.over_budget
    }

    /// The face count where refinement stopped when [`Self::over_budget`]
    /// (more than the face limit).
    pub fn stopped_at(&self) -> usize {
        self.stopped_at
    }

    /// The surface.
    pub fn mesh(&self) -> &HalfEdgeMesh {
        &self.mesh
    }

    /// Gives the surface back.
    pub fn into_mesh(self) -> HalfEdgeMesh {
        self.mesh
    }

    /// Starts a new stroke (resets which vertices count as touched).
    pub fn begin_stroke(&mut self) {
        self.over_budget = false;
        self.stroke_stamp = self.stroke_stamp.wrapping_add(1).max(1);
        if self.stroke_stamp == 1 {
            self.stroke_mark.fill(0);
        }
    }

    /// Live vertices the current stroke moved or created, in id order
    /// (a pass over the whole mesh: for tests and tools, not per frame).
    pub fn stroke_touched(&self) -> Vec<VertId> {
        self.mesh
            .vertices()
            .filter(|v| self.stroke_mark.get(v.0 as usize) == Some(&self.stroke_stamp))
            .collect()
    }

    /// Marks `v` as touched by the stroke and, when its neighbourhood
    /// changed shape (`reshaped`), as part of this frame's region.
    pub(super) fn mark(&mut self, v: VertId, reshaped: bool) {
        let i = v.0 as usize;
        if i >= self.stroke_mark.len() {
            self.stroke_mark.resize(i + 1, 0);
            self.frame_mark.resize(i + 1, 0);
            self.moved_mark.resize(i + 1, 0);
            self.rigid_mark.resize(i + 1, 0);
            self.short_mark.resize(i + 1, 0);
            self.old_pos.resize(i + 1, DVec3::ZERO);
            self.old_mark.resize(i + 1, 0);
            self.dirty_mark.resize(i + 1, 0);
        }
        self.stroke_mark[i] = self.stroke_stamp;
        if reshaped && self.frame_mark[i] != self.frame_stamp {
            self.frame_mark[i] = self.frame_stamp;
            self.region.push(v);
        }
    }

    /// Records that `v` moved, appeared or changed its neighbours, for the
    /// next [`Self::sync_render`].
    #[inline]
    pub(super) fn note_changed(&mut self, v: VertId) {
        let i = v.0 as usize;
        if i >= self.changed_mark.len() {
            self.changed_mark.resize(i + 1, 0);
        }
        if self.changed_mark[i] != self.change_stamp {
            self.changed_mark[i] = self.change_stamp;
            self.changed.push(v);
        }
    }

    /// A fresh stamp for marking faces.
    pub(super) fn next_face_stamp(&mut self) -> u32 {
        let cap = self.mesh.face_capacity() as usize;
        if self.face_mark.len() < cap {
            self.face_mark.resize(cap, 0);
        }
        self.face_stamp = self.face_stamp.wrapping_add(1);
        if self.face_stamp == 0 {
            self.face_mark.fill(0);
            self.face_stamp = 1;
        }
        self.face_stamp
    }

    /// Stamps the faces around `v` with `stamp`.
    pub(super) fn stamp_faces(&mut self, v: VertId, stamp: u32) {
        let cap = self.mesh.face_capacity() as usize;
        if self.face_mark.len() < cap {
            self.face_mark.resize(cap, 0);
        }
        let mesh = &self.mesh;
        let marks = &mut self.face_mark;
        mesh.for_each_out(v, |h| marks[h.face().0 as usize] = stamp);
    }

    #[inline]
    pub(super) fn in_frame(&self, v: VertId) -> bool {
        self.frame_mark.get(v.0 as usize) == Some(&self.frame_stamp)
    }

    #[inline]
    pub(super) fn in_stroke(&self, v: VertId) -> bool {
        self.stroke_mark.get(v.0 as usize) == Some(&self.stroke_stamp)
    }

    /// True when `v` moved non-rigidly (or on the rim of the rigid region)
    /// this frame.
    #[inline]
    pub(super) fn moved(&self, v: VertId) -> bool {
        self.moved_mark.get(v.0 as usize) == Some(&self.frame_stamp)
    }

    fn centroid_of_neighbours(&self, v: VertId) -> DVec3 {
        let mut s = DVec3::ZERO;
        let mut n = 0.0;
        self.mesh.for_each_out(v, |h| {
            s += self.mesh.position(self.mesh.to(h));
            n += 1.0;
        });
        s / n
    }

    /// Applies one frame: warps the vertices within `h` of the brush, then
    /// adapts the resolution in the touched region.
    ///
    /// The frame runs inside rayon's pool as one job: its parallel passes
    /// are then joins between pool threads, where a chunk no other thread
    /// has taken is run by the thread that queued it. Called from outside
    /// the pool, each pass would instead queue its work and block until a
    /// pool thread woke up to take it: a handful of thread hand-offs per
    /// frame, each a scheduler wake-up that on a busy machine (cores shared
    /// with the renderer and other processes) costs up to a time slice,
    /// the frame-time spikes of the bench stroke. The chunks and their
    /// order do not change, so neither do the bits.
    pub fn apply_frame(&mut self, f: &FrameInput) -> FrameStats {
        if rayon::current_thread_index().is_some() {
            return self.frame_in_pool(f);
        }
        rayon::scope(|_| self.frame_in_pool(f))
    }

    /// [`Self::apply_frame`]'s work, on a pool thread.
    fn frame_in_pool(&mut self, f: &FrameInput) -> FrameStats {
        self.frame_stamp = self.frame_stamp.wrapping_add(1).max(1);
        if self.frame_stamp == 1 {
            self.frame_mark.fill(0);
            self.moved_mark.fill(0);
            self.rigid_mark.fill(0);
            self.short_mark.fill(0);
            self.old_mark.fill(0);
        }
        self.region.clear();
        let eval_pose = if f.warp == Warp::Drag { f.prev } else { f.pose };
        let reach = f.bound * eval_pose.scale + f.influence;
        let mut cand = std::mem::take(&mut self.cand);
        // The cells the reach's ball meets: the warp below skips every
        // vertex outside the ball, so leaving out the other cells of its
        // box changes no move.
        self.grid
            .query_ball(eval_pose.position, reach, &mut cand, &mut self.cand_scratch);
        let inc = DragIncrement {
            from: f.prev.position,
            to: f.pose.position,
            rotation: (f.pose.rotation * f.prev.rotation.inverse()).normalize(),
        };
        let mut moves = std::mem::take(&mut self.moves);
        moves.clear();
        let reach2 = reach * reach;
        let this = &*self;
        let warp_vertex = |&v: &VertId| {
            let x = this.mesh.position(v);
            // Beyond the bound radius plus h the weight is 0.
            if x.distance_squared(eval_pose.position) > reach2 {
                return None;
            }
            let (d, g) = eval_pose.eval(f.shape, x);
            let w = f.falloff.weight(d, f.influence, f.pressure);
            if w.is_nan() || w <= 0.0 {
                return None;
            }
            // A fully weighted drag moves the vertex rigidly with the brush:
            // its triangles keep their shape unless a neighbour moved
            // differently, and that neighbour puts them in the region.
            let rigid = f.warp == Warp::Drag && w == 1.0;
            let x2 = match f.warp {
                Warp::Drag if rigid => inc.apply(x),
                Warp::Drag => x + w * (inc.apply(x) - x),
                Warp::Explode { delta } => x + w * (g * (f.influence * delta)),
                Warp::Whittle => x + w * (this.centroid_of_neighbours(v) - x),
            };
            (x2 != x && x2.is_finite()).then_some((v, x, x2, rigid))
        };
        // Each vertex's warp reads only positions from before the frame, so
        // evaluating fixed chunks in parallel and appending them in order
        // gives the same moves, bit for bit, on any number of threads.
        if cand.len() >= PARALLEL_MIN {
            moves.par_extend(
                cand.par_chunks(PARALLEL_CHUNK)
                    .flat_map_iter(|c| c.iter().filter_map(warp_vertex)),
            );
        } else {
            moves.extend(cand.iter().filter_map(warp_vertex));
        }
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for &(_, x, x2, _) in &moves {
            lo = lo.min(x).min(x2);
            hi = hi.max(x).max(x2);
        }
        let mut stats = FrameStats {
            visited: cand.len(),
            moved: moves.len(),
            ..Default::default()
        };
        self.cand = cand;
        // A rigidly moved vertex with a neighbour that did not move with it
        // (moved otherwise, or not at all) sits on the rim of the rigid
        // region: its triangles change shape, so it counts as reshaped.
        for &(v, _, _, rigid) in &moves {
            if rigid {
                self.rigid_mark[v.0 as usize] = self.frame_stamp;
            }
        }
        let this = &*self;
        let interior = par::map(&moves, |m| {
            let mut interior = m.3;
            if interior {
                this.mesh.for_each_out(m.0, |h| {
                    interior &= this.rigid_mark[this.mesh.to(h).0 as usize] == this.frame_stamp;
                });
            }
            interior
        });
        for (m, interior) in moves.iter_mut().zip(interior) {
            m.3 = interior;
        }
        for &(v, x, x2, rigid) in &moves {
            self.mark(v, !rigid);
            if !rigid {
                self.moved_mark[v.0 as usize] = self.frame_stamp;
            }
            self.old_pos[v.0 as usize] = x;
            self.old_mark[v.0 as usize] = self.frame_stamp;
            self.mesh.set_position(v, x2);
        }
        let pad = DVec3::splat(f.max_len);
        let lim = Limits {
            max2: f.max_len * f.max_len,
            min2: f.min_len * f.min_len,
            lo: lo - pad,
            hi: hi + pad,
        };
        let tests = self.prevent_folds(&mut moves, &lim);
        // Only a step the fold guard pulled back can make sheets meet
        // (see `super::crossing_guard`).
        // A rigid move it put back joins the region after the others:
        // `adapt` reads the region in id order.
        if tests.is_none() && self.prevent_crossings(&mut moves, &lim, &mut stats.guard_faces) {
            self.region.sort_unstable();
        }
        for &(v, _, _, _) in &moves {
            let x = self.mesh.position(v);
            self.grid.update(v, x);
            self.note_changed(v);
        }
        self.moves = moves;
        if stats.moved > 0 {
            self.adapt(&lim, tests, &mut stats);
        }
        stats
    }

    /// Brings `out` (built by [`RenderBuffers::from_mesh`] from this
    /// sculptor's mesh) up to date with every frame applied since the last
    /// call, touching only what changed: positions of moved and new
    /// vertices, normals of those and their neighbours, corners of the
    /// faces around them and of removed faces. Returns the slot ranges
    /// rewritten, for the host to upload (see [`super::render`]).
    pub fn sync_render(&mut self, out: &mut RenderBuffers) -> DirtySlots {
        let capacity_grew = out.fit(&self.mesh);
        // Normals change at changed vertices and their neighbours; mark
        // those with the next stamp so each is written once (stamps stay
        // below u32::MAX - 2, so `next` never wraps).
        let next = self.change_stamp + 1;
        let mut verts: Vec<u32> = Vec::with_capacity(self.changed.len() * 3);
        let mut faces: Vec<u32> = Vec::with_capacity(self.changed.len() * 2);
        let fstamp = self.next_face_stamp();
        for i in 0..self.changed.len() {
            let v = self.changed[i];
            if !self.mesh.vert_alive(v) {
                continue;
            }
            let mesh = &self.mesh;
            let marks = &mut self.changed_mark;
            let fmarks = &mut self.face_mark;
            let mut visit = |w: VertId| {
                let slot = &mut marks[w.0 as usize];
                if *slot != next {
                    *slot = next;
                    verts.push(w.0);
                }
            };
            visit(v);
            mesh.for_each_out(v, |h| {
                visit(mesh.to(h));
                let f = h.face();
                if fmarks[f.0 as usize] != fstamp {
                    fmarks[f.0 as usize] = fstamp;
                    faces.push(f.0);
                }
            });
        }
        let mesh = &self.mesh;
        let normals = par::map(&verts, |&w| vertex_normal(mesh, VertId(w)));
        for (&w, n) in verts.iter().zip(normals) {
            out.write_vertex(mesh, VertId(w), n);
        }
        for f in self.removed_faces.drain(..) {
            faces.push(f.0);
        }
        for &f in &faces {
            out.write_face(mesh, FaceId(f));
        }
        self.changed.clear();
        // Both stamps are now used; the next round starts after them.
        self.change_stamp = next + 1;
        if self.change_stamp >= u32::MAX - 2 {
            self.changed_mark.fill(0);
            self.change_stamp = 1;
        }
        DirtySlots {
            vertices: to_ranges(&mut verts, &mut self.id_scratch),
            triangles: to_ranges(&mut faces, &mut self.id_scratch),
            capacity_grew,
        }
    }
}
