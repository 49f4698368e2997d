//! The evaluated mesh of an assembly: the manifold union of its parts.

use super::AssemblyError;
use crate::gc::{mesh_gc, GcAssembly};
use crate::mesh::{union, validate, TriMesh};

/// Meshes every part and unites them with `manifold-rust`
/// ([`crate::mesh::union`], which checks every operand's status); the
/// result is checked to be a closed oriented 2-manifold. A one-part
/// assembly is its part's mesh (already closed), unchanged.
pub fn union_mesh(asm: &GcAssembly) -> Result<TriMesh, AssemblyError> {
    asm.validate()?;
    if let [only] = asm.parts.as_slice() {
        return Ok(mesh_gc(&only.gc)?);
    }
    let mut meshes = Vec::with_capacity(asm.parts.len());
    for (i, p) in asm.parts.iter().enumerate() {
        let mut m = mesh_gc(&p.gc)?;
        m.set_source(i as u32);
        meshes.push(m);
    }
    let refs: Vec<&TriMesh> = meshes.iter().collect();
    let out = union(&refs)?;
    let report = validate(&out, &Default::default());
    // Manifold may leave zero-area slivers; they do not break closedness.
    if !(report.is_closed() && report.non_manifold_vertices == 0 && report.signed_volume > 0.0) {
        return Err(AssemblyError::InvalidUnion(report.problems()));
    }
    Ok(out)
}
