//! Booleans of closed meshes through `manifold-rust` (a pure-Rust port of
//! the Manifold library, verified here to match C++ Manifold 3.5.4 byte
//! for byte). Used for the printable union of a document's objects.
//!
//! Manifold passes a failed operand through silently (a boolean with a
//! broken operand returns NoError and the other operand), so every import's
//! `status()` is checked, and indices are validated before import because
//! `MeshGL::merge` panics on out-of-range indices. The crate's `parallel`
//! feature is on: it parallelises only the sites whose output is identical
//! to the sequential build (manifold-rust's `par.rs`), so results are the
//! same bits on 1 or 2 threads (`tests/suite/union_cache.rs` checks it).
//!
//! [`union_snapped`] and [`snap`] give Manifold a tolerance: imported with
//! `MeshGL::tolerance = t`, a mesh's epsilon becomes `t`, so Manifold's own
//! clean-up (short-edge collapse, degenerate-triangle swaps) removes every
//! edge shorter than `t` and every sliver thinner than it, keeping the
//! result a closed 2-manifold. The printable path uses it to remove the
//! features that rounding to float32 would collapse or fold.
//!
//! Results carry no vertex normals (`normals` empty), as Manifold's
//! `GetMeshGL64` carries none: every caller that draws or writes them
//! computes its own ([`TriMesh::compute_normals`]): the headset host over
//! the whole drawn document, the renderer from faces where they are
//! missing, the OBJ and PLY writers ([`super::MeshFormat::write_named`])
//! and the USD writer (`shapewright-usd`'s mesh prims), each the same
//! bits as before; Blender and the slicer formats never read them. The
//! export used to compute them on every union (three `acos` per
//! triangle: 4% of one boolean step in issue 37's profile, 15% of its
//! excess over C++ Manifold's), for readers that recomputed them or had
//! none.

use std::sync::Arc;

use manifold_rust::cancel::CancelToken;
use manifold_rust::manifold::Manifold;
use manifold_rust::types::{BooleanConfig, Error as ManifoldStatus, MeshGLP, OpType};

use super::TriMesh;

/// Why a boolean could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BooleanError {
    /// An operand has an index past its vertex count or a non-finite
    /// coordinate; nothing was computed.
    #[error("operand {index} is malformed: {reason}")]
    Malformed {
        /// 0-based operand index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// Manifold refused an operand (it is not a closed 2-manifold). Without
    /// this check the union would silently leave the operand out.
    #[error("operand {index} is not a closed 2-manifold (Manifold status {status}); repair or remesh it first")]
    NotManifold {
        /// 0-based operand index.
        index: usize,
        /// Manifold's status.
        status: String,
    },
    /// The boolean itself failed.
    #[error("the boolean failed with Manifold status {0}")]
    Failed(String),
    /// [`BooleanCancel::cancel`] was called; nothing was computed.
    #[error("the boolean was cancelled")]
    Cancelled,
}

/// Stops a running [`union_snapped_with`] from another thread (a host's
/// Esc): Manifold checks it between and inside its pipeline stages, so a
/// union stops within one stage of one step, and a cancelled union never
/// returns a result. Clones share the flag.
#[derive(Clone, Debug, Default)]
pub struct BooleanCancel(CancelToken);

impl BooleanCancel {
    /// A fresh, uncancelled flag.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks every union holding a clone of this flag to stop.
    pub fn cancel(&self) {
        self.0.cancel();
    }

    /// Whether [`Self::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.is_cancelled()
    }
}

/// The union of closed meshes, as one closed mesh. Each output triangle's
/// source is the `tri_source` of the operand triangle it came from (or the
/// operand index when the operand has no sources).
pub fn union(meshes: &[&TriMesh]) -> Result<TriMesh, BooleanError> {
    union_snapped(meshes, 0.0)
}

/// The union of closed meshes, with every edge shorter than `tolerance`
/// collapsed and every sliver thinner than it removed (see the module
/// doc); `0.0` is Manifold's own precision (1e-12 of the box). Sources as
/// for [`union`].
pub fn union_snapped(meshes: &[&TriMesh], tolerance: f64) -> Result<TriMesh, BooleanError> {
    union_snapped_with(meshes, tolerance, None, &|_, _| {})
}

/// [`union_snapped`], stoppable by `cancel` and reporting its steps:
/// `step(done, total)` once per non-empty operand after each group is
/// imported and once after each union step (`total` = 2 x the operands;
/// `done` only grows, and stays below `total`), then `step(total, total)`. The operands are grouped by disjoint boxes
/// ([`super::disjoint_groups`]) and the groups united in the fixed tree of
/// [`super::union_tree_nodes`], the two halves of each node at once, so the
/// result is the same bits on any number of threads; `step` may be called
/// from any of them (one call at a time).
pub fn union_snapped_with(
    meshes: &[&TriMesh],
    tolerance: f64,
    cancel: Option<&BooleanCancel>,
    step: &(dyn Fn(usize, usize) + Sync),
) -> Result<TriMesh, BooleanError> {
    struct Tree<'a> {
        meshes: &'a [&'a TriMesh],
        tolerance: f64,
        token: Option<&'a CancelToken>,
        engine: manifold_rust::types::BooleanEngine,
        done: std::sync::Mutex<usize>,
        step: &'a (dyn Fn(usize, usize) + Sync),
    }
    impl Tree<'_> {
        fn stopped(&self) -> Result<(), BooleanError> {
            match self.token.is_some_and(CancelToken::is_cancelled) {
                true => Err(BooleanError::Cancelled),
                false => Ok(()),
            }
        }
        fn tick(&self) {
            let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
            *done += 1;
            (self.step)(*done, 2 * self.meshes.len());
        }
    }
    impl super::union_tree::UnionTree for Tree<'_> {
        type Value = Manifold;
        type Error = BooleanError;
        fn group(&self, members: &[usize]) -> Result<Option<Arc<Manifold>>, (usize, BooleanError)> {
            self.stopped().map_err(|e| (members[0], e))?;
            let ops: Vec<(usize, &TriMesh)> =
                members.iter().map(|&i| (i, self.meshes[i])).collect();
            let out = import_group(&ops, self.tolerance)?;
            for (_, m) in ops {
                if !m.triangles.is_empty() {
                    self.tick();
                }
            }
            Ok(out.map(Arc::new))
        }
        fn join(&self, a: &Manifold, b: &Manifold) -> Result<Manifold, BooleanError> {
            self.stopped()?;
            let out = a.boolean_with_engine_and_token(b, OpType::Add, self.engine, self.token);
            self.tick();
            Ok(out)
        }
    }
    let tree = Tree {
        meshes,
        tolerance,
        token: cancel.map(|c| &c.0),
        engine: BooleanConfig::default_engine(),
        done: std::sync::Mutex::new(0),
        step,
    };
    // A mesh with triangles but no box (no vertices) overlaps everything:
    // it is an operand alone, and its import says what is wrong with it.
    let everywhere = (glam::DVec3::NEG_INFINITY, glam::DVec3::INFINITY);
    let boxes: Vec<_> = meshes
        .iter()
        .map(|m| (!m.triangles.is_empty()).then(|| m.bbox().unwrap_or(everywhere)))
        .collect();
    let groups = super::union_tree::disjoint_groups(&boxes);
    let Some(united) = super::union_tree::unite_tree(&tree, &groups)? else {
        tree.stopped()?;
        return Ok(TriMesh::default());
    };
    let mut result = Arc::unwrap_or_clone(united);
    if tree.stopped().is_err() || result.status() == ManifoldStatus::Cancelled {
        return Err(BooleanError::Cancelled);
    }
    if tolerance > 0.0 {
        result = result.simplify(0.0);
    }
    if result.status() != ManifoldStatus::NoError {
        return Err(BooleanError::Failed(format!("{:?}", result.status())));
    }
    let total = 2 * meshes.len();
    step(total, total);
    Ok(export(&result))
}

/// A closed mesh re-imported at `tolerance` (edges shorter than it
/// collapsed, slivers thinner than it swapped away), sources kept per run.
pub fn snap(mesh: &TriMesh, tolerance: f64) -> Result<TriMesh, BooleanError> {
    let mf = import_runs(0, mesh, tolerance)?.simplify(0.0);
    if mf.status() != ManifoldStatus::NoError {
        return Err(BooleanError::Failed(format!("{:?}", mf.status())));
    }
    Ok(export(&mf))
}

/// True when Manifold accepts `mesh` as a closed 2-manifold (what
/// `manifold3d.Manifold(mesh).status()` says of the same buffers).
pub fn manifold_accepts(mesh: &TriMesh) -> bool {
    import_tol(0, mesh, 0, 0.0).is_ok()
}

/// `a` minus the union of `cutters` (closed meshes), as one closed mesh;
/// sources as for [`union`] (cutters count from operand index 1).
pub fn difference(a: &TriMesh, cutters: &[&TriMesh]) -> Result<TriMesh, BooleanError> {
    let base = import(0, a, a.tri_source.first().copied().unwrap_or(0))?;
    let mut cuts = Vec::with_capacity(cutters.len());
    for (i, m) in cutters.iter().enumerate() {
        if !m.triangles.is_empty() {
            let source = m.tri_source.first().copied().unwrap_or(i as u32 + 1);
            cuts.push(import(i + 1, m, source)?);
        }
    }
    if cuts.is_empty() {
        return Ok(export(&base));
    }
    let cut = Manifold::batch_boolean(&cuts, OpType::Add);
    let result = base.boolean(&cut, OpType::Subtract);
    if result.status() != ManifoldStatus::NoError {
        return Err(BooleanError::Failed(format!("{:?}", result.status())));
    }
    Ok(export(&result))
}

/// A closed mesh imported into Manifold, an operand or a node of a union
/// tree. [`union`] unites its operands in the tree of
/// [`super::union_tree_nodes`] over the groups of
/// [`super::disjoint_groups`] with these steps (for four operands whose
/// boxes all overlap, `union(&[a, b, c, d])` is
/// `a.union(&b).union(&c.union(&d))` exported, bit for bit, each operand
/// made by [`Self::import_group`] alone; a group of disjoint operands is
/// one [`Self::import_group`]; empty operands are skipped), so a caller
/// that keeps the tree's nodes can re-unite only those over a changed
/// operand ([`crate::assembly::UnionCache`]).
#[derive(Clone)]
pub struct UnionOperand(Manifold);

impl std::fmt::Debug for UnionOperand {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "UnionOperand({} triangles)", self.0.num_tri())
    }
}

impl UnionOperand {
    /// Imports the closed meshes `members` (operand index, mesh; their
    /// boxes pairwise disjoint, or one alone) side by side, as [`union`]
    /// imports a group of its operands (each operand's source: its first
    /// triangle's, else its index). `None` when none has triangles, which
    /// [`union`] skips. On failure, the first member that fails alone.
    pub fn import_group(
        members: &[(usize, &TriMesh)],
    ) -> Result<Option<Self>, (usize, BooleanError)> {
        Ok(import_group(members, 0.0)?.map(Self))
    }

    /// The union of `self` and `next` (one node of the tree).
    pub fn union(&self, next: &Self) -> Self {
        Self(self.0.boolean(&next.0, OpType::Add))
    }

    /// The operand as a mesh, as [`union`] returns its result.
    pub fn to_mesh(&self) -> Result<TriMesh, BooleanError> {
        if self.0.status() != ManifoldStatus::NoError {
            return Err(BooleanError::Failed(format!("{:?}", self.0.status())));
        }
        Ok(export(&self.0))
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.0.num_tri()
    }
}

/// Imports `m`, tagging its triangles with `source` as their original id
/// (our ids, not Manifold's global counter, so output is deterministic).
fn import(index: usize, m: &TriMesh, source: u32) -> Result<Manifold, BooleanError> {
    import_tol(index, m, source, 0.0)
}

fn import_tol(
    index: usize,
    m: &TriMesh,
    source: u32,
    tolerance: f64,
) -> Result<Manifold, BooleanError> {
    let sources = vec![source; m.triangles.len()];
    import_with(index, m, &sources, tolerance)
}

/// Imports the operands `members` (index, mesh) as one Manifold, their
/// meshes side by side (their boxes pairwise disjoint, so this is their
/// union), each operand's triangles tagged with its source (its first
/// triangle's, else its index). `None` when none has triangles. One
/// import, not one per operand and a `Compose` (see
/// [`super::union_tree`]). On failure, the first member that fails alone
/// (index checks first, then Manifold's), as importing them one by one
/// would report.
fn import_group(
    members: &[(usize, &TriMesh)],
    tolerance: f64,
) -> Result<Option<Manifold>, (usize, BooleanError)> {
    let live: Vec<(usize, &TriMesh)> = members
        .iter()
        .copied()
        .filter(|(_, m)| !m.triangles.is_empty())
        .collect();
    let source = |i: usize, m: &TriMesh| m.tri_source.first().copied().unwrap_or(i as u32);
    // What importing the members one by one reports first (only on the
    // way out of a failure: each one's own checks and import).
    let alone = |otherwise: (usize, BooleanError)| {
        for &(i, m) in &live {
            if let Err(e) = import_tol(i, m, source(i, m), tolerance) {
                return (i, e);
            }
        }
        otherwise
    };
    match live.as_slice() {
        [] => return Ok(None),
        &[(i, m)] => {
            return import_tol(i, m, source(i, m), tolerance)
                .map(Some)
                .map_err(|e| (i, e))
        }
        _ => {}
    }
    if let Some(e) = live
        .iter()
        .find_map(|&(i, m)| check_arrays(i, m).err().map(|e| (i, e)))
    {
        return Err(alone(e));
    }
    let mut all = TriMesh::default();
    let mut sources = Vec::new();
    for &(i, m) in &live {
        let offset = all.positions.len() as u32;
        all.positions.extend_from_slice(&m.positions);
        all.triangles
            .extend(m.triangles.iter().map(|t| t.map(|v| v + offset)));
        sources.extend(std::iter::repeat_n(source(i, m), m.triangles.len()));
    }
    // Each member's arrays were checked above.
    import_checked(live[0].0, &all, &sources, tolerance)
        .map(Some)
        .map_err(|e| alone((live[0].0, e)))
}

/// Imports a mesh whose triangles carry their own sources (one run per
/// maximal stretch of equal sources; Manifold keeps runs by original id).
fn import_runs(index: usize, m: &TriMesh, tolerance: f64) -> Result<Manifold, BooleanError> {
    let sources = if m.tri_source.len() == m.triangles.len() {
        m.tri_source.clone()
    } else {
        vec![index as u32; m.triangles.len()]
    };
    import_with(index, m, &sources, tolerance)
}

/// Operand `index`'s arrays can be imported: indices in range, finite
/// coordinates.
fn check_arrays(index: usize, m: &TriMesh) -> Result<(), BooleanError> {
    let n = m.positions.len();
    if let Some(t) = m
        .triangles
        .iter()
        .find(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(BooleanError::Malformed {
            index,
            reason: format!("triangle {t:?} refers past the {n} vertices"),
        });
    }
    if m.positions.iter().flatten().any(|x| !x.is_finite()) {
        return Err(BooleanError::Malformed {
            index,
            reason: "a vertex coordinate is not finite".into(),
        });
    }
    Ok(())
}

fn import_with(
    index: usize,
    m: &TriMesh,
    sources: &[u32],
    tolerance: f64,
) -> Result<Manifold, BooleanError> {
    check_arrays(index, m)?;
    import_checked(index, m, sources, tolerance)
}

/// [`import_with`] of arrays [`check_arrays`] accepted.
fn import_checked(
    index: usize,
    m: &TriMesh,
    sources: &[u32],
    tolerance: f64,
) -> Result<Manifold, BooleanError> {
    // Triangles sorted by source (stable), one run per source.
    let mut order: Vec<usize> = (0..m.triangles.len()).collect();
    order.sort_by_key(|&t| sources[t]);
    let mut run_index = vec![0u64];
    let mut run_original_id = Vec::new();
    for (k, &t) in order.iter().enumerate() {
        if k == 0 || sources[t] != sources[order[k - 1]] {
            if k > 0 {
                run_index.push(3 * k as u64);
            }
            run_original_id.push(sources[t]);
        }
    }
    run_index.push(3 * order.len() as u64);
    let gl = MeshGLP::<f64, u64> {
        num_prop: 3,
        vert_properties: m.positions.iter().flatten().copied().collect(),
        tri_verts: order
            .iter()
            .flat_map(|&t| m.triangles[t])
            .map(|i| i as u64)
            .collect(),
        run_index,
        run_original_id,
        tolerance,
        ..Default::default()
    };
    let mf = Manifold::from_mesh_gl64(&gl);
    if mf.status() != ManifoldStatus::NoError {
        return Err(BooleanError::NotManifold {
            index,
            status: format!("{:?}", mf.status()),
        });
    }
    Ok(mf)
}

fn export(mf: &Manifold) -> TriMesh {
    let gl = mf.get_mesh_gl64(-1);
    let np = gl.num_prop as usize;
    let positions = gl
        .vert_properties
        .chunks_exact(np)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let triangles: Vec<[u32; 3]> = gl
        .tri_verts
        .chunks_exact(3)
        .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
        .collect();
    let mut tri_source = vec![0u32; triangles.len()];
    for r in 0..gl.run_original_id.len() {
        let (start, end) = (
            gl.run_index[r] as usize / 3,
            gl.run_index[r + 1] as usize / 3,
        );
        let src = gl.run_original_id[r];
        for s in &mut tri_source[start.min(triangles.len())..end.min(triangles.len())] {
            *s = src;
        }
    }
    TriMesh {
        positions,
        normals: Vec::new(),
        triangles,
        tri_source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fm::DetMath as _;
    use crate::mesh::validate;
    use crate::solid::{tessellate, SolidShape};
    use glam::{DAffine3, DVec3};

    fn sphere_at(x: f64, r: f64, id: u32) -> TriMesh {
        let mut m = tessellate(&SolidShape::Sphere { radius: r }, 96).unwrap();
        m.transform(&DAffine3::from_translation(DVec3::new(x, 0.0, 0.0)));
        m.set_source(id);
        m
    }

    #[test]
    fn union_of_two_spheres_matches_the_lens_formula() {
        let (r, d) = (1.0, 1.0);
        let a = sphere_at(0.0, r, 7);
        let b = sphere_at(d, r, 9);
        let u = union(&[&a, &b]).unwrap();
        let rep = validate(&u, &Default::default());
        assert!(rep.is_closed_manifold(), "{}", rep.problems());
        assert_eq!(rep.genus, Some(0));
        assert_eq!(rep.components, 1);
        // Union = 2 spheres - lens; lens = pi (4r + d)(2r - d)^2 / 12.
        let sphere = a.signed_volume();
        let lens = std::f64::consts::PI * (4.0 * r + d) * (2.0 * r - d).fpowi(2) / 12.0;
        let want = 2.0 * sphere - lens * (sphere / (4.0 / 3.0 * std::f64::consts::PI));
        assert!(
            (rep.signed_volume - want).abs() / want < 2e-3,
            "{} vs {want}",
            rep.signed_volume
        );
        assert!(u.tri_source.iter().all(|&s| s == 7 || s == 9));
        assert!(u.tri_source.contains(&7) && u.tri_source.contains(&9));
    }

    #[test]
    fn disjoint_union_keeps_both_and_is_deterministic() {
        let a = sphere_at(0.0, 0.5, 1);
        let b = sphere_at(3.0, 0.5, 2);
        let u1 = union(&[&a, &b]).unwrap();
        let u2 = union(&[&a, &b]).unwrap();
        assert_eq!(u1, u2);
        let rep = validate(&u1, &Default::default());
        assert_eq!(rep.components, 2);
        assert!((rep.signed_volume - a.signed_volume() - b.signed_volume()).abs() < 1e-9);
    }

    #[test]
    fn a_broken_operand_is_an_error_not_silently_dropped() {
        let a = sphere_at(0.0, 0.5, 1);
        let mut open = sphere_at(0.2, 0.5, 2);
        open.triangles.pop();
        assert!(matches!(
            union(&[&a, &open]),
            Err(BooleanError::NotManifold { index: 1, .. })
        ));
        let mut bad = sphere_at(0.2, 0.5, 2);
        bad.triangles[0][1] = 1_000_000;
        assert!(matches!(
            union(&[&a, &bad]),
            Err(BooleanError::Malformed { index: 1, .. })
        ));
        let mut nan = sphere_at(0.2, 0.5, 2);
        nan.positions[3][0] = f64::NAN;
        assert!(matches!(
            union(&[&nan]),
            Err(BooleanError::Malformed { index: 0, .. })
        ));
        // Triangles and no vertices: no box, but not empty.
        let mut none = sphere_at(5.0, 0.5, 2);
        none.positions.clear();
        assert!(matches!(
            union(&[&a, &none]),
            Err(BooleanError::Malformed { index: 1, .. })
        ));
        // Of two broken operands in different groups (the far sphere is
        // in `a`'s group), the first in operand order is reported.
        let far = sphere_at(5.0, 0.5, 3);
        assert!(matches!(
            union(&[&a, &open, &far, &bad]),
            Err(BooleanError::NotManifold { index: 1, .. })
        ));
        // Within one group (three disjoint spheres, imported as one mesh):
        // the member that fails alone, and of an open one before one with
        // a bad index, the open one, as one by one.
        let mut open_far = sphere_at(5.0, 0.5, 3);
        open_far.triangles.pop();
        let mut bad_far = sphere_at(10.0, 0.5, 4);
        bad_far.triangles[0][1] = 1_000_000;
        assert!(matches!(
            union(&[&a, &open_far]),
            Err(BooleanError::NotManifold { index: 1, .. })
        ));
        assert!(matches!(
            union(&[&a, &far, &bad_far]),
            Err(BooleanError::Malformed { index: 2, .. })
        ));
        assert!(matches!(
            union(&[&a, &open_far, &bad_far]),
            Err(BooleanError::NotManifold { index: 1, .. })
        ));
    }

    #[test]
    fn progress_only_grows_and_a_cancelled_union_returns_no_mesh() {
        // Two overlapping pairs far apart: {0 2} and {1 3} are each
        // imported as one (disjoint boxes), then one boolean; the empty
        // one is skipped.
        let parts = [
            sphere_at(0.0, 0.5, 1),
            sphere_at(0.6, 0.5, 2),
            sphere_at(10.0, 0.5, 3),
            sphere_at(10.6, 0.5, 4),
            TriMesh::default(),
        ];
        let refs: Vec<&TriMesh> = parts.iter().collect();
        let seen = std::sync::Mutex::new(Vec::new());
        let record = |done: usize, total: usize| seen.lock().expect("lock").push((done, total));
        let u = union_snapped_with(&refs, 0.0, None, &record).expect("union");
        assert_eq!(validate(&u, &Default::default()).components, 2);
        let seen = seen.into_inner().expect("lock");
        assert_eq!(seen.last(), Some(&(10, 10)));
        assert!(seen.windows(2).all(|w| w[0].0 < w[1].0), "{seen:?}");
        assert!(
            seen[..seen.len() - 1].iter().all(|&(d, t)| d < t),
            "{seen:?}"
        );
        // One step per non-empty operand imported, 1 boolean, the end.
        assert_eq!(seen.len(), 4 + 1 + 1, "{seen:?}");
        let cancel = BooleanCancel::new();
        cancel.cancel();
        for refs in [refs.as_slice(), &refs[4..]] {
            assert_eq!(
                union_snapped_with(refs, 0.0, Some(&cancel), &|_, _| {}),
                Err(BooleanError::Cancelled)
            );
        }
    }
}
