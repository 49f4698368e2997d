//! Strokes (paper §4.1, §6): 6-DOF samples with pressure applied frame by
//! frame by a [`Sculptor`], which owns the surface, the vertex hash grid and
//! the per-frame scratch, so a frame costs time proportional to the
//! vertices near the brush, never a pass over the whole mesh.
//!
//! A brush reaches the vertices within its bound radius (scaled) plus `h`
//! of its origin; beyond that the weight is 0 by definition (for the exact
//! fields this is implied by `d >= h`; for the ellipsoid bound and grid
//! fields it makes the region explicit).

use glam::{DQuat, DVec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::brush::{check_finite, positive, BrushPose, BrushShape};
use super::grid::VertexGrid;
use super::halfedge::{FaceId, HalfEdgeMesh, VertId};
use super::warp::{DragIncrement, Falloff, Warp};
use super::SculptError;

/// Candidate count from which a frame's warp is evaluated in parallel
/// (below it, thread hand-off costs more than it saves).
const PARALLEL_MIN: usize = 8192;
/// Candidates per parallel chunk (fixed, so the split never depends on the
/// thread count; the results are appended in order either way).
const PARALLEL_CHUNK: usize = 2048;

/// One tracker sample: brush position, orientation and pressure.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrokeSample {
    /// Brush position (world space).
    pub position: [f64; 3],
    /// Brush orientation quaternion `[x, y, z, w]` (normalized on use).
    pub rotation: [f64; 4],
    /// Pressure in [0, 1].
    pub pressure: f64,
}

impl StrokeSample {
    /// Checks the sample is finite, has a rotation and a pressure in [0, 1].
    pub fn validate(&self, index: usize) -> Result<(), SculptError> {
        check_finite(&format!("samples[{index}].position"), &self.position)?;
        check_finite(&format!("samples[{index}].rotation"), &self.rotation)?;
        check_finite(&format!("samples[{index}].pressure"), &[self.pressure])?;
        if DQuat::from_array(self.rotation).length() < 1e-9 {
            return Err(SculptError::ZeroRotation {
                field: format!("samples[{index}].rotation"),
            });
        }
        if !(0.0..=1.0).contains(&self.pressure) {
            return Err(SculptError::OutOfRange {
                field: format!("samples[{index}].pressure"),
                value: self.pressure,
                range: "[0, 1]",
            });
        }
        Ok(())
    }
}

/// Everything about a stroke except its path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StrokeSettings {
    /// Brush shape (distance field in the brush frame).
    pub brush: BrushShape,
    /// Brush scale, separate from the model's scale.
    pub brush_scale: f64,
    /// Influence size `h`: weights fall to 0 at distance `h` from the brush.
    pub influence: f64,
    /// Weight falloff.
    pub falloff: Falloff,
    /// Warp operator.
    pub warp: Warp,
    /// Max edge length as a fraction of the brush size (scaled bound
    /// radius of the brush shape).
    pub max_edge_rel: f64,
    /// Min edge length as a fraction of the brush size; must be below half
    /// of `max_edge_rel`, so a bisected edge is never collapsed again.
    pub min_edge_rel: f64,
}

impl StrokeSettings {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), SculptError> {
        self.brush.validate()?;
        positive("brush_scale", self.brush_scale)?;
        positive("influence", self.influence)?;
        positive("max_edge_rel", self.max_edge_rel)?;
        positive("min_edge_rel", self.min_edge_rel)?;
        if let Warp::Explode { delta } = self.warp {
            check_finite("warp.delta", &[delta])?;
        }
        if self.min_edge_rel * 2.0 >= self.max_edge_rel {
            return Err(SculptError::OutOfRange {
                field: "min_edge_rel".into(),
                value: self.min_edge_rel,
                range: "below max_edge_rel / 2",
            });
        }
        Ok(())
    }

    /// Brush size in the brush's scaled units.
    pub fn brush_size(&self) -> f64 {
        self.brush.bound_radius() * self.brush_scale
    }
}

/// One frame's input, in model space.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    /// Brush shape.
    pub shape: &'a BrushShape,
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
    /// Vertices moved by the warp.
    pub moved: usize,
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
}

/// A surface under sculpting, with its spatial index and scratch.
#[derive(Clone, Debug)]
pub struct Sculptor {
    mesh: HalfEdgeMesh,
    grid: VertexGrid,
    stroke_mark: Vec<u32>,
    stroke_stamp: u32,
    frame_mark: Vec<u32>,
    moved_mark: Vec<u32>,
    rigid_mark: Vec<u32>,
    frame_stamp: u32,
    cand: Vec<VertId>,
    moves: Vec<(VertId, DVec3, DVec3, bool)>,
    face_mark: Vec<u32>,
    face_stamp: u32,
    region: Vec<VertId>,
    queue: Vec<FaceId>,
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
            face_mark,
            face_stamp: 0,
            frame_stamp: 1,
            cand: Vec::new(),
            moves: Vec::new(),
            region: Vec::new(),
            queue: Vec::new(),
        }
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
        self.stroke_stamp = self.stroke_stamp.wrapping_add(1).max(1);
        if self.stroke_stamp == 1 {
            self.stroke_mark.fill(0);
        }
    }

    /// Live vertices the current stroke moved or created, in id order.
    pub fn stroke_touched(&self) -> Vec<VertId> {
        self.mesh
            .vertices()
            .filter(|v| self.stroke_mark.get(v.0 as usize) == Some(&self.stroke_stamp))
            .collect()
    }

    /// Marks `v` as touched by the stroke and, when its neighbourhood
    /// changed shape (`reshaped`), as part of this frame's region.
    fn mark(&mut self, v: VertId, reshaped: bool) {
        let i = v.0 as usize;
        if i >= self.stroke_mark.len() {
            self.stroke_mark.resize(i + 1, 0);
            self.frame_mark.resize(i + 1, 0);
            self.moved_mark.resize(i + 1, 0);
            self.rigid_mark.resize(i + 1, 0);
        }
        self.stroke_mark[i] = self.stroke_stamp;
        if reshaped && self.frame_mark[i] != self.frame_stamp {
            self.frame_mark[i] = self.frame_stamp;
            self.region.push(v);
        }
    }

    /// A fresh stamp for de-duplicating faces.
    fn next_face_stamp(&mut self) -> u32 {
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

    /// Pushes the faces around `v` not yet stamped with `stamp`.
    fn push_faces(&mut self, v: VertId, stamp: u32, out: &mut Vec<FaceId>) {
        let cap = self.mesh.face_capacity() as usize;
        if self.face_mark.len() < cap {
            self.face_mark.resize(cap, 0);
        }
        let mesh = &self.mesh;
        let marks = &mut self.face_mark;
        mesh.for_each_out(v, |h| {
            let f = h.face();
            if marks[f.0 as usize] != stamp {
                marks[f.0 as usize] = stamp;
                out.push(f);
            }
        });
    }

    #[inline]
    fn in_frame(&self, v: VertId) -> bool {
        self.frame_mark.get(v.0 as usize) == Some(&self.frame_stamp)
    }

    #[inline]
    fn in_stroke(&self, v: VertId) -> bool {
        self.stroke_mark.get(v.0 as usize) == Some(&self.stroke_stamp)
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
    pub fn apply_frame(&mut self, f: &FrameInput) -> FrameStats {
        self.frame_stamp = self.frame_stamp.wrapping_add(1).max(1);
        if self.frame_stamp == 1 {
            self.frame_mark.fill(0);
            self.moved_mark.fill(0);
            self.rigid_mark.fill(0);
        }
        self.region.clear();
        let eval_pose = if f.warp == Warp::Drag { f.prev } else { f.pose };
        let reach = f.shape.bound_radius() * eval_pose.scale + f.influence;
        let r = DVec3::splat(reach);
        let mut cand = std::mem::take(&mut self.cand);
        self.grid
            .query(eval_pose.position - r, eval_pose.position + r, &mut cand);
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
        self.cand = cand;
        let mut stats = FrameStats {
            moved: moves.len(),
            ..Default::default()
        };
        // A rigidly moved vertex with a neighbour that did not move with it
        // (moved otherwise, or not at all) sits on the rim of the rigid
        // region: its triangles change shape, so it counts as reshaped.
        for &(v, _, _, rigid) in &moves {
            if rigid {
                self.rigid_mark[v.0 as usize] = self.frame_stamp;
            }
        }
        for m in moves.iter_mut() {
            if m.3 {
                let mut interior = true;
                self.mesh.for_each_out(m.0, |h| {
                    interior &= self.rigid_mark[self.mesh.to(h).0 as usize] == self.frame_stamp;
                });
                m.3 = interior;
            }
        }
        for &(v, _, x2, rigid) in &moves {
            self.mark(v, !rigid);
            if !rigid {
                self.moved_mark[v.0 as usize] = self.frame_stamp;
            }
            self.mesh.set_position(v, x2);
        }
        self.prevent_folds(&mut moves);
        for &(v, _, _, _) in &moves {
            let x = self.mesh.position(v);
            self.grid.update(v, x);
        }
        self.moves = moves;
        if stats.moved > 0 {
            let pad = DVec3::splat(f.max_len);
            self.adapt(f.max_len, f.min_len, lo - pad, hi + pad, &mut stats);
        }
        stats
    }

    /// Fold guard: a warp step that would fold a triangle onto a
    /// neighbour (normals more than 120 degrees apart) or make it
    /// degenerate is halved for that triangle's moved vertices, up to three
    /// times, then undone for them. Converging warps (collapse onto a small
    /// brush) would otherwise crumple the surface within a few frames.
    fn prevent_folds(&mut self, moves: &mut [(VertId, DVec3, DVec3, bool)]) {
        let mut faces = Vec::new();
        let mut bad_verts = Vec::new();
        let mut round = 0;
        loop {
            // Only triangles at a non-rigidly moved vertex can fold (two
            // rigidly moved neighbours keep their dihedral angle).
            faces.clear();
            let stamp = self.next_face_stamp();
            for &(v, _, _, rigid) in moves.iter() {
                if !rigid {
                    self.push_faces(v, stamp, &mut faces);
                }
            }
            bad_verts.clear();
            for &f in &faces {
                if self.face_folds(f) {
                    for v in self.mesh.face_verts(f) {
                        if self.moved_mark[v.0 as usize] == self.frame_stamp {
                            bad_verts.push(v);
                        }
                    }
                }
            }
            if bad_verts.is_empty() {
                return;
            }
            bad_verts.sort_unstable();
            bad_verts.dedup();
            // Halve three times, then undo; undoing stops once every
            // offending vertex is back where it was (each undo round
            // restores at least one vertex, so this terminates).
            let mut changed = false;
            for (v, old, new, rigid) in moves.iter_mut() {
                if !*rigid && bad_verts.binary_search(v).is_ok() && *new != *old {
                    *new = if round >= 3 {
                        *old
                    } else {
                        *old + (*new - *old) * 0.5
                    };
                    self.mesh.set_position(*v, *new);
                    changed = true;
                }
            }
            if !changed {
                return;
            }
            round += 1;
        }
    }

    /// True when face `f` is degenerate or folds onto a neighbour.
    fn face_folds(&self, f: FaceId) -> bool {
        let n = self.mesh.face_area_vec(f);
        let nl = n.length();
        let [a, b, c] = self.mesh.face_verts(f).map(|v| self.mesh.position(v));
        let scale = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
        if nl.is_nan() || nl <= 1e-12 * scale {
            return true;
        }
        (0..3).any(|i| {
            let g = self.mesh.twin(f.half_edge(i)).face();
            let m = self.mesh.face_area_vec(g);
            n.dot(m) <= -0.5 * nl * m.length()
        })
    }

    fn adapt(&mut self, max_len: f64, min_len: f64, lo: DVec3, hi: DVec3, stats: &mut FrameStats) {
        let max2 = max_len * max_len;
        let min2 = min_len * min_len;
        // Split phase: every triangle at a touched vertex.
        let mut queue = std::mem::take(&mut self.queue);
        queue.clear();
        let stamp = self.next_face_stamp();
        for i in 0..self.region.len() {
            let v = self.region[i];
            self.push_faces(v, stamp, &mut queue);
        }
        let mut created = Vec::new();
        let mut i = 0;
        while i < queue.len() {
            let face = queue[i];
            i += 1;
            if !self.mesh.face_alive(face) {
                continue;
            }
            let l = self.mesh.longest_edge(face);
            if self.mesh.edge_len2(l) <= max2 {
                continue;
            }
            // Triangles at a moved vertex changed shape: always adapt them.
            // Triangles reached only through new vertices adapt inside the
            // region's box, so a coarse base never refines far away.
            let vs = self.mesh.face_verts(face);
            let moved = vs
                .iter()
                .any(|&v| self.moved_mark[v.0 as usize] == self.frame_stamp);
            if !moved {
                if !vs.iter().any(|&v| self.in_frame(v)) {
                    continue;
                }
                let c = vs
                    .iter()
                    .fold(DVec3::ZERO, |s, &v| s + self.mesh.position(v))
                    / 3.0;
                if c.cmplt(lo).any() || c.cmpgt(hi).any() {
                    continue;
                }
            }
            created.clear();
            self.mesh.split_conforming(l, &mut created);
            stats.splits += created.len();
            for &(m, _) in &created {
                self.grid.insert(m, self.mesh.position(m));
                self.mark(m, true);
                self.mesh.for_each_out(m, |h| queue.push(h.face()));
            }
        }
        self.queue = queue;
        // Collapse phase: short edges at touched vertices.
        let mut cands: Vec<VertId> = self.region.clone();
        cands.sort_unstable();
        let mut short = Vec::new();
        for _pass in 0..3 {
            let mut any = false;
            for &v in &cands {
                if !self.mesh.vert_alive(v) {
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
                    if self.mesh.try_collapse(h, p, max2) {
                        self.grid.remove(gone);
                        self.grid.update(keep, p);
                        if self.in_stroke(keep) {
                            self.mark(keep, true);
                        }
                        stats.collapses += 1;
                        any = true;
                        break;
                    }
                }
            }
            if !any {
                break;
            }
        }
    }
}

/// Applies a whole stroke of model-space poses and pressures.
pub fn run_stroke(
    sculptor: &mut Sculptor,
    shape: &BrushShape,
    settings: &StrokeSettings,
    model_scale: f64,
    poses: &[(BrushPose, f64)],
) -> FrameStats {
    sculptor.begin_stroke();
    let size = settings.brush_size() / model_scale;
    let mut total = FrameStats::default();
    for (i, &(pose, pressure)) in poses.iter().enumerate() {
        let prev = if i == 0 { pose } else { poses[i - 1].0 };
        let s = sculptor.apply_frame(&FrameInput {
            shape,
            prev,
            pose,
            pressure,
            influence: settings.influence / model_scale,
            falloff: settings.falloff,
            warp: settings.warp,
            max_len: settings.max_edge_rel * size,
            min_len: settings.min_edge_rel * size,
        });
        total.moved += s.moved;
        total.splits += s.splits;
        total.collapses += s.collapses;
    }
    total
}
