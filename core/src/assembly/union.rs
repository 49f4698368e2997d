//! The evaluated mesh of an assembly: the manifold union of its parts,
//! with the inside of its hollow parts kept empty.

use super::AssemblyError;
use crate::gc::{cavity_gc, mesh_gc, GcAssembly};
use crate::mesh::{difference, union, validate, TriMesh};

/// Meshes every part and unites them with `manifold-rust`
/// ([`crate::mesh::union`], which checks every operand's status), keeping
/// the inside of every shell and container empty: each part first loses
/// the cavities ([`cavity_gc`]) of the other parts it reaches into. So a part's end sunk into a hollow
/// parent is trimmed at the parent's inner wall, and a hollow child (a
/// spout) opens its channel through its parent's wall: the teapot pours,
/// and no sealed void is left where a tube's inside meets a hollow body.
/// The result is checked to be a closed oriented 2-manifold. A one-part
/// assembly is its part's mesh (already closed), unchanged.
pub fn union_mesh(asm: &GcAssembly) -> Result<TriMesh, AssemblyError> {
    asm.validate()?;
    if let [only] = asm.parts.as_slice() {
        return Ok(mesh_gc(&only.gc)?);
    }
    let mut meshes = Vec::with_capacity(asm.parts.len());
    let mut cavities = Vec::with_capacity(asm.parts.len());
    for (i, p) in asm.parts.iter().enumerate() {
        let mut m = mesh_gc(&p.gc)?;
        m.set_source(i as u32);
        meshes.push(m);
        cavities.push(cavity_gc(&p.gc)?);
    }
    // Each part loses the cavities of the other parts it reaches into
    // (never its own: its inner wall is that cavity's surface, and a
    // boolean of coincident surfaces is slow and fragile).
    for (i, mesh) in meshes.iter_mut().enumerate() {
        let Some((lo, hi)) = mesh.bbox() else {
            continue;
        };
        let cuts: Vec<&TriMesh> = cavities
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .filter_map(|(_, c)| c.as_ref())
            .filter(|c| {
                c.bbox()
                    .is_some_and(|(cl, ch)| cl.cmple(hi).all() && ch.cmpge(lo).all())
            })
            .collect();
        if !cuts.is_empty() {
            let mut cut = difference(mesh, &cuts)?;
            cut.set_source(i as u32);
            *mesh = cut;
        }
    }
    let refs: Vec<&TriMesh> = meshes.iter().collect();
    let united = union(&refs)?;
    let out = collapse_slivers(united);
    let report = validate(&out, &Default::default());
    // Manifold may leave zero-area slivers; they do not break closedness.
    if !(report.is_closed() && report.non_manifold_vertices == 0 && report.signed_volume > 0.0) {
        return Err(AssemblyError::InvalidUnion(report.problems()));
    }
    Ok(out)
}

/// Manifold can leave a few zero-area slivers where surfaces meet almost
/// tangentially. Each is removed by collapsing its shortest edge (its
/// neighbours across that edge become degenerate and are dropped); the
/// cleaned mesh is kept only when it validates as a closed 2-manifold
/// without degenerate triangles, otherwise the union is returned as is.
fn collapse_slivers(mesh: TriMesh) -> TriMesh {
    // Topology only: this runs on every GC commit (print checks the rest).
    let settings = crate::mesh::ValidationSettings::topology_only();
    let report = validate(&mesh, &settings);
    if report.degenerate_triangles == 0 {
        return mesh;
    }
    let Some((lo, hi)) = mesh.bbox() else {
        return mesh;
    };
    let area_tol = 1e-14 * (hi - lo).length_squared();
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
    out.compute_normals();
    if validate(&out, &settings).is_closed_manifold() {
        out
    } else {
        mesh
    }
}
