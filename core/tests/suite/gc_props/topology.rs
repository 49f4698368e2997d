//! The printed union's topology, and when an edit may change it.
//!
//! A structure-aware edit keeps the union's genus and component count
//! (issue 33), except where the user's edit makes parts meet that did not
//! (a body resized into its handle's loop fills it) or part that met (a
//! rail re-placed with its post no longer reaching the other post: parts
//! that touch without being parent and child have no relation to keep).
//! [`Contacts`] records both, so the property test compares the genus
//! only while the contacts are those of the unedited model; a child
//! leaking or leaving its parent at its junction is never a contact
//! change, so that is always compared.

use std::collections::BTreeSet;

use shapewright::assembly::{
    project_to_surface, union_mesh, union_mesh_cached, AssemblyError, UnionCache,
};
use shapewright::gc::{mesh_gc, GcAssembly, GcError};
use shapewright::mesh::{self_intersections, union, validate, TriMesh};

use super::edits::profile_radius;

/// What the union is: closed, its genus, components and degenerate
/// triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Topology {
    pub genus: i64,
    pub components: usize,
    pub degenerate: usize,
}

/// An assembly after an op: its parts' meshes and its union's topology,
/// or the typed GC error a part cannot be meshed with (the document
/// refuses the op that made it).
pub struct Evaluated {
    pub parts: Vec<TriMesh>,
    pub topology: Topology,
}

/// With `cache` (kept across the ops of one random sequence, as the
/// document keeps it), the union is also evaluated through it and must be
/// the fresh union bit for bit: the incremental union of issue 37 (a
/// change re-unites only the union tree's nodes over the parts it
/// changed) under random edits.
pub fn evaluate(
    asm: &GcAssembly,
    cache: Option<&UnionCache>,
) -> Result<Result<Evaluated, GcError>, String> {
    let mut parts = Vec::with_capacity(asm.parts.len());
    for p in &asm.parts {
        match mesh_gc(&p.gc) {
            Ok(m) => parts.push(m),
            Err(e) => return Ok(Err(e)),
        }
    }
    let mesh = match union_mesh(asm) {
        Err(AssemblyError::Gc(e)) => return Ok(Err(e)),
        Err(e) => return Err(format!("union: {e}")),
        Ok(m) => m,
    };
    if let Some(cache) = cache {
        let cached = union_mesh_cached(asm, cache).map_err(|e| format!("cached union: {e}"))?;
        if cached != mesh {
            return Err(format!(
                "the cached union differs from the fresh one ({} and {} triangles)",
                cached.triangles.len(),
                mesh.triangles.len()
            ));
        }
    }
    let r = validate(&mesh, &Default::default());
    if !r.is_closed() || r.non_manifold_vertices > 0 {
        return Err(format!(
            "the union is not a closed 2-manifold: {}",
            r.problems()
        ));
    }
    let topology = Topology {
        genus: r.genus.ok_or("no genus")?,
        components: r.components,
        degenerate: r.degenerate_triangles,
    };
    Ok(Ok(Evaluated { parts, topology }))
}

/// The first part whose own mesh passes through itself.
pub fn folded_part(ev: &Evaluated) -> Option<usize> {
    ev.parts
        .iter()
        .position(|m| !self_intersections(m).pairs.is_empty())
}

pub fn topology(asm: &GcAssembly) -> Result<Topology, String> {
    match evaluate(asm, None)? {
        Ok(ev) => Ok(ev.topology),
        Err(e) => Err(e.to_string()),
    }
}

/// Which parts touch that are not parent and child, and which children
/// come near their parent away from where they are attached.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contacts {
    /// Pairs `(i, j)`, `i < j`, neither the other's parent, whose meshes
    /// unite into one piece.
    pub touching: BTreeSet<(usize, usize)>,
    /// Children whose spine, between its attached ends, comes within its
    /// largest section radius (plus 1 mm) of its parent's surface.
    pub near_parent: BTreeSet<usize>,
}

fn bbox_overlap(a: &TriMesh, b: &TriMesh, pad: f64) -> bool {
    match (a.bbox(), b.bbox()) {
        (Some((al, ah)), Some((bl, bh))) => {
            (al - pad).cmple(bh).all() && (bl - pad).cmple(ah).all()
        }
        _ => false,
    }
}

fn largest_radius(gc: &shapewright::gc::Gc) -> f64 {
    gc.sections
        .iter()
        .map(|s| profile_radius(&s.profile) * s.scale)
        .fold(0.0, f64::max)
}

/// The contacts of `asm`, whose parts' meshes are `meshes`.
pub fn contacts(asm: &GcAssembly, meshes: &[TriMesh]) -> Result<Contacts, String> {
    let mut touching = BTreeSet::new();
    for i in 0..meshes.len() {
        for j in i + 1..meshes.len() {
            let related = asm.parts[j].parent == Some(i) || asm.parts[i].parent == Some(j);
            if related || !bbox_overlap(&meshes[i], &meshes[j], 1e-3) {
                continue;
            }
            let u = union(&[&meshes[i], &meshes[j]]).map_err(|e| e.to_string())?;
            if validate(&u, &Default::default()).components == 1 {
                touching.insert((i, j));
            }
        }
    }
    let mut near_parent = BTreeSet::new();
    for (c, part) in asm.parts.iter().enumerate() {
        let (Some(p), Some(att)) = (part.parent, part.attach) else {
            continue;
        };
        let surf = asm.parts[p].gc.surface().map_err(|e| e.to_string())?;
        let spine = &part.gc.spine.curve;
        let (a, b) = spine.domain();
        let hi = if att.end.is_some() { 0.7 } else { 1.0 };
        let clearance = largest_radius(&part.gc) + 1e-3;
        let near = (0..=24).any(|k| {
            let t = 0.3 + (hi - 0.3) * k as f64 / 24.0;
            let q = spine.point(a + (b - a) * t);
            let pr = project_to_surface(&surf, q);
            let d = surf.derivatives(pr.anchor.u, pr.anchor.v, 1);
            let inside = d[1][0]
                .cross(d[0][1])
                .try_normalize()
                .is_some_and(|n| (q - pr.point).dot(n) < 0.0);
            inside || pr.distance < clearance
        });
        if near {
            near_parent.insert(c);
        }
    }
    Ok(Contacts {
        touching,
        near_parent,
    })
}
