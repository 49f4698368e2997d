//! The evaluated mesh of an assembly: the manifold union of its parts,
//! with the inside of its hollow parts kept empty.

use std::sync::Arc;

use rayon::prelude::*;

use super::cache::{gc_key, key, Tag, Value};
use super::{AssemblyError, UnionCache};
use crate::gc::{cavity_gc, mesh_gc, GcAssembly};
use crate::mesh::{
    difference, disjoint_groups, union_tree_nodes, unite_tree, validate, TriMesh, UnionOperand,
    UnionTree, ValidationReport,
};

/// Meshes every part and unites them with `manifold-rust`
/// ([`crate::mesh::union`], which checks every operand's status), keeping
/// the inside of every shell and container empty: each part first loses
/// the cavities ([`cavity_gc`]) of the other parts it reaches into. So a part's end sunk into a hollow
/// parent is trimmed at the parent's inner wall, and a hollow child (a
/// spout) opens its channel through its parent's wall: the teapot pours,
/// and no sealed void is left where a tube's inside meets a hollow body.
/// The result is checked to be a closed oriented 2-manifold. A one-part
/// assembly is its part's mesh (already closed), unchanged.
///
/// Computes everything afresh: [`union_mesh_cached`] with a new cache.
pub fn union_mesh(asm: &GcAssembly) -> Result<TriMesh, AssemblyError> {
    union_mesh_cached(asm, &UnionCache::new())
}

/// [`union_mesh`], reusing what `cache` holds from earlier evaluations of
/// the same object and keeping what this one computes (see
/// [`UnionCache`]): a part whose GC did not change is not re-meshed, a
/// part whose GC and cutting cavities did not change is not re-trimmed,
/// and the union takes every node it holds whole (a group's import
/// too). The union is [`crate::mesh::union`]'s: the fixed tree of
/// [`crate::mesh::union_tree_nodes`] over the groups of parts with
/// disjoint boxes ([`crate::mesh::disjoint_groups`]; here the boxes of
/// the parts before trimming, which hold the trimmed parts). So an edit
/// of one part re-imports its group (the other members from their kept
/// trims) and re-unites the nodes on that group's path to the root.
/// Bit-identical to [`union_mesh`] whatever the cache holds.
pub fn union_mesh_cached(asm: &GcAssembly, cache: &UnionCache) -> Result<TriMesh, AssemblyError> {
    asm.validate()?;
    cache.begin();
    let keys: Vec<u64> = asm.parts.iter().map(|p| gc_key(&p.gc)).collect();
    if let [only] = asm.parts.as_slice() {
        return Ok((*part_mesh(cache, keys[0], &only.gc)?).clone());
    }
    // Parts are meshed in parallel (each a pure function of its GC); the
    // first error in part order is the one reported, as sequentially.
    let pieces: Vec<_> = asm
        .parts
        .par_iter()
        .zip(&keys)
        .map(|(p, &k)| (part_mesh(cache, k, &p.gc), part_cavity(cache, k, &p.gc)))
        .collect();
    let mut meshes = Vec::with_capacity(asm.parts.len());
    let mut cavities = Vec::with_capacity(asm.parts.len());
    for (m, c) in pieces {
        let m = m?;
        let bbox = m.bbox();
        meshes.push((m, bbox));
        let c = c?;
        let cbox = c.as_ref().as_ref().and_then(TriMesh::bbox);
        cavities.push((c, cbox));
    }
    // Each part loses the cavities of the other parts it reaches into
    // (never its own: its inner wall is that cavity's surface, and a
    // boolean of coincident surfaces is slow and fragile).
    let cutters: Vec<Vec<usize>> = meshes
        .iter()
        .enumerate()
        .map(|(i, (_, bbox))| {
            let Some((lo, hi)) = *bbox else {
                return Vec::new();
            };
            cavities
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .filter(|(_, (c, cbox))| {
                    c.is_some()
                        && cbox.is_some_and(|(cl, ch)| cl.cmple(hi).all() && ch.cmpge(lo).all())
                })
                .map(|(j, _)| j)
                .collect()
        })
        .collect();
    let trim_keys: Vec<u64> = cutters
        .iter()
        .enumerate()
        .map(|(i, cut)| {
            let mut words = vec![i as u64, keys[i]];
            words.extend(cut.iter().map(|&j| keys[j]));
            key(b"trimmed", &words)
        })
        .collect();
    // The union tree's leaves: groups of parts whose boxes are disjoint
    // (a trimmed part lies in its part's box), imported together, without
    // a boolean.
    let boxes: Vec<_> = meshes.iter().map(|(_, b)| *b).collect();
    let groups = disjoint_groups(&boxes);
    // Every node of the tree, keyed by the groups under it and their
    // trimmed parts (its shape depends on how many groups it spans).
    let node_key = |under: &[Vec<usize>]| {
        let mut words = Vec::new();
        for g in under {
            words.push(g.len() as u64);
            words.extend(g.iter().map(|&i| trim_keys[i]));
        }
        key(b"node", &words)
    };
    let result_key = key(b"result", &[node_key(&groups)]);
    if let Some(Value::Result(m)) = cache.get(Tag::Result, result_key) {
        cache.count(|s| s.result_hits += 1);
        // Keep what an edit of this state will start from: the tree's
        // nodes (each group's among them) and every part's trim (an edit
        // imports the edited part's whole group again).
        for (lo, hi) in union_tree_nodes(groups.len()) {
            cache.get(Tag::Node, node_key(&groups[lo..hi]));
        }
        for &i in groups.iter().flatten() {
            cache.get(Tag::Trimmed, trim_keys[i]);
        }
        return Ok((*m).clone());
    }
    // Part `i` with its sources set and the cavities cutting it cut out.
    let trimmed_part = |i: usize| -> Result<Arc<TriMesh>, AssemblyError> {
        if let Some(Value::Trimmed(m)) = cache.get(Tag::Trimmed, trim_keys[i]) {
            cache.count(|s| s.trim_hits += 1);
            return Ok(m);
        }
        let mut mesh = (*meshes[i].0).clone();
        mesh.set_source(i as u32);
        let cuts: Vec<&TriMesh> = cutters[i]
            .iter()
            .filter_map(|&j| cavities[j].0.as_ref().as_ref())
            .collect();
        if !cuts.is_empty() {
            mesh = difference(&mesh, &cuts)?;
            mesh.set_source(i as u32);
        }
        let m = Arc::new(mesh);
        cache.put(Tag::Trimmed, trim_keys[i], Value::Trimmed(m.clone()));
        cache.count(|s| s.trim_misses += 1);
        Ok(m)
    };
    // The union tree over the trimmed parts, its nodes kept and reused:
    // a node over unchanged parts is found whole, the others are united
    // again, both halves of each at once (errors in part order, a part's
    // trim before its import, as sequentially).
    let nodes = Nodes {
        cache,
        trimmed_part,
        node_key,
    };
    let acc = unite_tree(&nodes, &groups)?;
    let united = match &acc {
        Some(a) => a.to_mesh()?,
        None => TriMesh::default(),
    };
    let (out, ok) = collapse_slivers(united);
    // Manifold may leave zero-area slivers; they do not break closedness.
    if !ok {
        // The full report (self-intersections too) says what is wrong.
        let report = validate(&out, &Default::default());
        return Err(AssemblyError::InvalidUnion(report.problems()));
    }
    let out = Arc::new(out);
    cache.put(Tag::Result, result_key, Value::Result(out.clone()));
    Ok(Arc::unwrap_or_clone(out))
}

/// The union tree over an assembly's trimmed parts (see
/// [`union_mesh_cached`]): its nodes are looked up in and kept in the
/// cache by their content key.
struct Nodes<'a, F, K> {
    cache: &'a UnionCache,
    trimmed_part: F,
    node_key: K,
}
impl<F, K> UnionTree for Nodes<'_, F, K>
where
    F: Fn(usize) -> Result<Arc<TriMesh>, AssemblyError> + Sync,
    K: Fn(&[Vec<usize>]) -> u64 + Sync,
{
    type Value = UnionOperand;
    type Error = AssemblyError;
    fn group(
        &self,
        members: &[usize],
    ) -> Result<Option<Arc<UnionOperand>>, (usize, AssemblyError)> {
        // Each member trimmed, then all imported at once. A failed trim
        // is reported unless an earlier member fails its import (what
        // trimming and importing them one by one would report first).
        let mut trimmed = Vec::with_capacity(members.len());
        for &i in members {
            match (self.trimmed_part)(i) {
                Ok(m) => trimmed.push((i, m)),
                Err(e) => {
                    // The members before it, imported as a group, report
                    // the first of them that fails alone.
                    let before: Vec<(usize, &TriMesh)> =
                        trimmed.iter().map(|(i, m)| (*i, m.as_ref())).collect();
                    UnionOperand::import_group(&before).map_err(|(i, e)| (i, e.into()))?;
                    return Err((i, e));
                }
            }
        }
        let parts: Vec<(usize, &TriMesh)> = trimmed.iter().map(|(i, m)| (*i, m.as_ref())).collect();
        UnionOperand::import_group(&parts)
            .map(|v| v.map(Arc::new))
            .map_err(|(i, e)| (i, e.into()))
    }
    fn join(&self, a: &UnionOperand, b: &UnionOperand) -> Result<UnionOperand, AssemblyError> {
        self.cache.count(|s| s.union_steps += 1);
        Ok(a.union(b))
    }
    fn found(&self, under: &[Vec<usize>]) -> Option<Option<Arc<UnionOperand>>> {
        match self.cache.get(Tag::Node, (self.node_key)(under)) {
            Some(Value::Node(v)) => {
                let parts: usize = under.iter().map(Vec::len).sum();
                self.cache.count(|s| s.parts_reused += parts as u64);
                Some(v)
            }
            _ => None,
        }
    }
    fn keep(&self, under: &[Vec<usize>], v: &Option<Arc<UnionOperand>>) {
        self.cache
            .put(Tag::Node, (self.node_key)(under), Value::Node(v.clone()));
    }
}

/// A part's mesh, from the cache or meshed (and kept).
fn part_mesh(
    cache: &UnionCache,
    k: u64,
    gc: &crate::gc::Gc,
) -> Result<Arc<TriMesh>, AssemblyError> {
    if let Some(Value::Mesh(m)) = cache.get(Tag::Mesh, k) {
        cache.count(|s| s.mesh_hits += 1);
        return Ok(m);
    }
    let m = Arc::new(mesh_gc(gc)?);
    cache.put(Tag::Mesh, k, Value::Mesh(m.clone()));
    cache.count(|s| s.mesh_misses += 1);
    Ok(m)
}

/// A part's cavity, from the cache or computed (and kept).
fn part_cavity(
    cache: &UnionCache,
    k: u64,
    gc: &crate::gc::Gc,
) -> Result<Arc<Option<TriMesh>>, AssemblyError> {
    if let Some(Value::Cavity(c)) = cache.get(Tag::Cavity, k) {
        cache.count(|s| s.cavity_hits += 1);
        return Ok(c);
    }
    let c = Arc::new(cavity_gc(gc)?);
    cache.put(Tag::Cavity, k, Value::Cavity(c.clone()));
    cache.count(|s| s.cavity_misses += 1);
    Ok(c)
}

/// Manifold can leave a few zero-area slivers where surfaces meet almost
/// tangentially. Each is removed by collapsing its shortest edge (its
/// neighbours across that edge become degenerate and are dropped); when
/// that does not give a closed 2-manifold without degenerate triangles
/// (zero-height caps of coplanar faces merged from two parts, whose
/// shortest edge is millimetres long), the caps are flipped away
/// ([`flip_caps`]) and the rest collapsed, then Manifold's own clean-up
/// is tried ([`snap_slivers`]); otherwise the union is returned as is.
/// Returns the mesh and whether it is closed, unpinched and of positive
/// volume (the verdict of [`validate`]'s topology-only report).
fn collapse_slivers(mesh: TriMesh) -> (TriMesh, bool) {
    // Topology only: this runs on every GC commit (print checks the rest),
    // so it takes the linear check, `validate` only for what that does not
    // judge.
    let settings = crate::mesh::ValidationSettings::topology_only();
    let verdict = |r: &ValidationReport| {
        r.is_closed() && r.non_manifold_vertices == 0 && r.signed_volume > 0.0
    };
    let (degenerate, ok) = match quick_check(&mesh) {
        Some(q) => (q.degenerate, q.closed && q.volume > 0.0),
        None => {
            let r = validate(&mesh, &settings);
            (r.degenerate_triangles, verdict(&r))
        }
    };
    if degenerate == 0 {
        return (mesh, ok);
    }
    let Some((lo, hi)) = mesh.bbox() else {
        return (mesh, ok);
    };
    let area_tol = 1e-14 * (hi - lo).length_squared();
    if let Some(out) = collapse_short_edges(&mesh, area_tol) {
        return (out, true);
    }
    // Flips keep the surface and the mesh closed: whatever follows starts
    // from the flipped mesh.
    let mut flipped = mesh.clone();
    if flip_caps(&mut flipped, area_tol) {
        if clean(&flipped) {
            return (flipped, true);
        }
        if let Some(out) = collapse_short_edges(&flipped, area_tol) {
            return (out, true);
        }
        return snap_slivers(flipped, ok);
    }
    snap_slivers(mesh, ok)
}

/// `validate(m).is_closed_manifold()` for a non-empty union, through the
/// linear check when it judges.
fn clean(m: &TriMesh) -> bool {
    match quick_check(m) {
        Some(q) => !m.triangles.is_empty() && q.degenerate == 0 && q.closed && q.volume > 0.0,
        None => validate(m, &crate::mesh::ValidationSettings::topology_only()).is_closed_manifold(),
    }
}

/// `mesh` with the shortest edge of each triangle of area at most
/// `area_tol` collapsed, when that leaves it [`clean`].
fn collapse_short_edges(mesh: &TriMesh, area_tol: f64) -> Option<TriMesh> {
    let mut remap: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    fn root(remap: &mut [u32], mut i: u32) -> u32 {
        while remap[i as usize] != i {
            i = remap[i as usize];
        }
        i
    }
    for t in &mesh.triangles {
        let c = t.map(|i| root(&mut remap, i));
        if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
            continue;
        }
        let p = c.map(|i| mesh.position(i));
        if (p[1] - p[0]).cross(p[2] - p[0]).length() * 0.5 > area_tol {
            continue;
        }
        let edges = [(0, 1), (1, 2), (2, 0)];
        let (a, b) = edges
            .iter()
            .copied()
            .min_by(|x, y| {
                let lx = p[x.0].distance(p[x.1]);
                let ly = p[y.0].distance(p[y.1]);
                lx.total_cmp(&ly)
            })
            .unwrap_or((0, 1));
        let (keep, gone) = (c[a].min(c[b]), c[a].max(c[b]));
        remap[gone as usize] = keep;
    }
    let mut out = mesh.clone();
    out.triangles.clear();
    out.tri_source.clear();
    for (k, t) in mesh.triangles.iter().enumerate() {
        let c = t.map(|i| root(&mut remap, i));
        if c[0] != c[1] && c[1] != c[2] && c[0] != c[2] {
            out.triangles.push(c);
            if let Some(s) = mesh.tri_source.get(k) {
                out.tri_source.push(*s);
            }
        }
    }
    clean(&out).then_some(out)
}

/// Passes of [`flip_caps`] at most.
const FLIP_PASSES: usize = 32;

/// Removes zero-area *caps* (a corner on the opposite edge, all edges
/// long: Manifold's triangulation of coplanar faces merged from two parts,
/// as the end caps of a table and its copy slid across) by flipping that
/// edge: the cap `a b v` (with `v` on `a b`) and its neighbour `b a u`
/// become `v a u` and `u b v`, which split the neighbour at `v` exactly,
/// so the surface does not move and the mesh stays a closed 2-manifold
/// (a flip whose new edge `v u` already exists is skipped). Collapsing
/// the cap's shortest edge instead moved a vertex by that edge (millimetres)
/// and was rejected, leaving the slivers. Repeated while it makes
/// progress (a cap next to a cap, at most [`FLIP_PASSES`] times).
/// Returns whether anything was flipped.
fn flip_caps(mesh: &mut TriMesh, area_tol: f64) -> bool {
    use std::collections::HashMap;
    let pos = |m: &TriMesh, i: u32| glam::DVec3::from_array(m.positions[i as usize]);
    let twice_area = |m: &TriMesh, t: [u32; 3]| {
        let p = t.map(|i| pos(m, i));
        (p[1] - p[0]).cross(p[2] - p[0]).length()
    };
    let mut any = false;
    for _ in 0..FLIP_PASSES {
        let mut edges: HashMap<(u32, u32), usize> =
            HashMap::with_capacity(mesh.triangles.len() * 3);
        for (k, t) in mesh.triangles.iter().enumerate() {
            for e in 0..3 {
                edges.insert((t[e], t[(e + 1) % 3]), k);
            }
        }
        let mut flipped = false;
        for k in 0..mesh.triangles.len() {
            let t = mesh.triangles[k];
            if 0.5 * twice_area(mesh, t) > area_tol {
                continue;
            }
            // The longest edge a -> b, v the corner on it.
            let len = |e: usize| pos(mesh, t[e]).distance(pos(mesh, t[(e + 1) % 3]));
            let e = (0..3)
                .max_by(|&x, &y| len(x).total_cmp(&len(y)))
                .unwrap_or(0);
            let (a, b, v) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            let (pa, pb, pv) = (pos(mesh, a), pos(mesh, b), pos(mesh, v));
            let ab = pb - pa;
            let s = (pv - pa).dot(ab) / ab.length_squared();
            // A needle (v at an end) is the collapse's; v strictly inside.
            if !(s > 1e-9 && s < 1.0 - 1e-9) {
                continue;
            }
            let Some(&n) = edges.get(&(b, a)) else {
                continue;
            };
            let nt = mesh.triangles[n];
            let Some(u) = nt.iter().copied().find(|&x| x != a && x != b) else {
                continue;
            };
            if n == k || u == v || edges.contains_key(&(v, u)) || edges.contains_key(&(u, v)) {
                continue;
            }
            let (t1, t2) = ([v, a, u], [u, b, v]);
            // A neighbour with area is split at `v`: both halves have area
            // and face its way. A neighbour that is a sliver too (a strip
            // of them along one line) is re-cut with a shorter edge `v u`,
            // so the strip's longest edge shrinks until its slivers meet
            // triangles with area and are split away.
            if 0.5 * twice_area(mesh, nt) > area_tol {
                let normal = |t: [u32; 3]| {
                    let p = t.map(|i| pos(mesh, i));
                    (p[1] - p[0]).cross(p[2] - p[0])
                };
                let nn = normal(nt);
                let fine =
                    |t: [u32; 3]| 0.5 * twice_area(mesh, t) > area_tol && normal(t).dot(nn) > 0.0;
                if !(fine(t1) && fine(t2)) {
                    continue;
                }
            } else if pos(mesh, u).distance(pv) >= ab.length() {
                continue;
            }
            for (x, y) in [(a, b), (b, v), (v, a), (b, a), (a, u), (u, b)] {
                edges.remove(&(x, y));
            }
            mesh.triangles[k] = t1;
            mesh.triangles[n] = t2;
            for (tri, idx) in [(t1, k), (t2, n)] {
                for e in 0..3 {
                    edges.insert((tri[e], tri[(e + 1) % 3]), idx);
                }
            }
            if let (Some(&src), true) = (mesh.tri_source.get(n), mesh.tri_source.len() > k) {
                mesh.tri_source[k] = src;
            }
            flipped = true;
        }
        any |= flipped;
        if !flipped {
            break;
        }
    }
    any
}

/// Slivers the shortest-edge collapse could not remove (coplanar faces of
/// overlapping parts, a copied table slid along its original, leave
/// chains of them that share edges): Manifold's own clean-up
/// ([`crate::mesh::snap`], which keeps the mesh a closed 2-manifold by
/// construction) at 1e-9, then 1e-7 and 1e-6 of the box's diagonal. The
/// first result that is closed, without degenerate triangles and of
/// positive volume is kept; otherwise the union as it was.
fn snap_slivers(mesh: TriMesh, ok: bool) -> (TriMesh, bool) {
    let Some((lo, hi)) = mesh.bbox() else {
        return (mesh, ok);
    };
    let diagonal = (hi - lo).length();
    for rel in [1e-9, 1e-7, 1e-6] {
        let Ok(snapped) = crate::mesh::snap(&mesh, rel * diagonal) else {
            continue;
        };
        let clean = quick_check(&snapped).is_some_and(|q| {
            !snapped.triangles.is_empty() && q.degenerate == 0 && q.closed && q.volume > 0.0
        });
        if clean {
            return (snapped, true);
        }
    }
    (mesh, ok)
}

/// What [`quick_check`] found.
struct QuickCheck {
    /// Triangles [`validate`] counts as degenerate.
    degenerate: usize,
    /// Every directed edge once, with its reverse, and every vertex one fan.
    closed: bool,
    /// The signed volume, summed as [`validate`] sums it.
    volume: f64,
}

/// The parts of [`validate`]'s topology-only report the union's verdict
/// reads, in linear time (a per-vertex list of outgoing edges instead of a
/// sort of all edges, fans walked through it): the same degenerate count
/// and volume (same formulas, same order) and the same verdict on
/// closedness and pinched vertices. `None` (use [`validate`]) for what it
/// does not judge: a triangle with a repeated or out-of-range index, or a
/// non-finite coordinate.
fn quick_check(mesh: &TriMesh) -> Option<QuickCheck> {
    let n = mesh.positions.len();
    if mesh.positions.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let tris = &mesh.triangles;
    if tris
        .iter()
        .any(|t| t.iter().any(|&i| i as usize >= n) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    {
        return None;
    }
    let (lo, hi) = mesh.bbox()?;
    let area_tol =
        crate::mesh::ValidationSettings::default().degenerate_area_rel * (hi - lo).length_squared();
    let origin = (lo + hi) * 0.5;
    let (mut degenerate, mut volume) = (0, 0.0);
    for t in tris {
        let [a, b, c] = t.map(|i| glam::DVec3::from_array(mesh.positions[i as usize]) - origin);
        let twice_area = (b - a).cross(c - a).length();
        if (0.5 * twice_area).partial_cmp(&area_tol) != Some(std::cmp::Ordering::Greater) {
            degenerate += 1;
        }
        volume += a.dot(b.cross(c));
    }
    volume /= 6.0;
    // Corners grouped by vertex: (next, prev) around each.
    let (start, link) = crate::mesh::validate::corners_by_vertex(n, tris);
    let closed = (0..n).all(|v| {
        let fan = &link[start[v] as usize..start[v + 1] as usize];
        // Outgoing edges v->next are unique, and each has its reverse:
        // some corner of `next` points back to v.
        for (i, &(w, _)) in fan.iter().enumerate() {
            if fan[..i].iter().any(|&(x, _)| x == w) {
                return false;
            }
            let back = &link[start[w as usize] as usize..start[w as usize + 1] as usize];
            if !back.iter().any(|&(x, _)| x as usize == v) {
                return false;
            }
        }
        // One fan: from a corner (next w, prev u), the next corner around
        // v is the one whose next is u; every corner is reached.
        if fan.is_empty() {
            return true;
        }
        let mut at = 0;
        for _ in 1..fan.len() {
            let u = fan[at].1;
            match fan.iter().position(|&(x, _)| x == u) {
                Some(j) if j != 0 => at = j,
                _ => return false,
            }
        }
        fan.iter().position(|&(x, _)| x == fan[at].1) == Some(0)
    });
    Some(QuickCheck {
        degenerate,
        closed,
        volume,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ValidationSettings;
    use crate::solid::{tessellate, SolidShape};
    use glam::{DAffine3, DVec3};

    use crate::mesh::test_meshes::tetra;

    /// A closed tetrahedron with a zero-height cap `A B M` (M the middle
    /// of A B) standing for the face split at M: [`flip_caps`] splits the
    /// other face at M instead, without moving a vertex.
    #[test]
    fn a_cap_is_flipped_into_the_face_beside_it() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, 0.0],
        ];
        let (a, b, c, d, m) = (0, 1, 2, 3, 4);
        let t = vec![
            [a, c, b],
            [a, b, m],
            [a, m, d],
            [m, b, d],
            [a, d, c],
            [b, c, d],
        ];
        let mut mesh = TriMesh::new(p.clone(), t);
        let before = quick_check(&mesh).expect("judged");
        assert!(before.closed);
        assert_eq!(before.degenerate, 1);
        assert!(flip_caps(&mut mesh, 1e-14));
        let after = quick_check(&mesh).expect("judged");
        assert!(after.closed);
        assert_eq!(after.degenerate, 0);
        assert!((after.volume - 1.0 / 6.0).abs() < 1e-15);
        assert_eq!(mesh.positions, p, "no vertex moved");
        assert_eq!(mesh.triangles[1], [m, a, c]);
        assert_eq!(mesh.triangles[0], [c, b, m]);
    }

    /// The quick check's verdict and counts are [`validate`]'s.
    fn agrees(m: &TriMesh, what: &str) {
        let r = validate(m, &ValidationSettings::topology_only());
        let q = quick_check(m).unwrap_or_else(|| panic!("{what}: judged"));
        assert_eq!(q.degenerate, r.degenerate_triangles, "{what}: degenerate");
        assert_eq!(
            q.closed,
            r.is_closed() && r.non_manifold_vertices == 0,
            "{what}: closed ({})",
            r.problems()
        );
        assert_eq!(
            q.volume.to_bits(),
            r.signed_volume.to_bits(),
            "{what}: volume"
        );
    }

    #[test]
    fn the_quick_check_agrees_with_validate() {
        let sphere = tessellate(&SolidShape::Sphere { radius: 0.3 }, 48).expect("sphere");
        agrees(&sphere, "sphere");
        agrees(&tetra(), "tetrahedron");
        let mut flipped = tetra();
        flipped.triangles[0].swap(1, 2);
        agrees(&flipped, "flipped face");
        let mut open = sphere.clone();
        open.triangles.pop();
        agrees(&open, "hole");
        let mut doubled = tetra();
        doubled.triangles.push(doubled.triangles[0]);
        agrees(&doubled, "a face twice");
        // Two tetrahedra sharing a vertex: closed edges, a pinched vertex.
        let mut pinched = tetra();
        let mut other = tetra();
        other.transform(&DAffine3::from_translation(DVec3::splat(-1.0)));
        let base = pinched.positions.len() as u32;
        pinched.append(&other);
        for t in &mut pinched.triangles[4..] {
            for i in t.iter_mut() {
                if *i == base + 3 {
                    *i = 0;
                }
            }
        }
        agrees(&pinched, "pinched");
        assert!(!quick_check(&pinched).expect("judged").closed);
        // A zero-area triangle (three collinear corners) in a closed mesh.
        let mut sliver = tetra();
        sliver.positions[3] = [0.5, 0.5, 0.0];
        agrees(&sliver, "flat");
        // What it does not judge goes to `validate`.
        let mut repeated = tetra();
        repeated.triangles[0] = [0, 0, 1];
        assert!(quick_check(&repeated).is_none());
        let mut nan = tetra();
        nan.positions[0][0] = f64::NAN;
        assert!(quick_check(&nan).is_none());
    }
}
