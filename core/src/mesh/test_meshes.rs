//! Small meshes shared by the mesh module's unit tests.

use super::TriMesh;

/// The unit right tetrahedron, outward-oriented: closed, genus 0,
/// volume 1/6.
pub fn tetra() -> TriMesh {
    TriMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    )
}
