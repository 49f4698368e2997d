//! PLY output (binary little-endian; float positions and normals, uchar
//! count + int indices), the layout slicers and Blender read.

use std::io::Write;

use super::TriMesh;

/// Writes `mesh` as binary little-endian PLY.
pub fn write_ply(mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
    let with_normals = mesh.normals.len() == mesh.positions.len() && !mesh.normals.is_empty();
    let mut head = String::from("ply\nformat binary_little_endian 1.0\ncomment Shapewright\n");
    head += &format!(
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        mesh.vertex_count()
    );
    if with_normals {
        head += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    head += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.triangle_count()
    );
    w.write_all(head.as_bytes())?;
    let mut buf = Vec::with_capacity(mesh.vertex_count() * 24 + mesh.triangle_count() * 13);
    for (i, p) in mesh.positions.iter().enumerate() {
        for x in p {
            buf.extend_from_slice(&(*x as f32).to_le_bytes());
        }
        if with_normals {
            for x in &mesh.normals[i] {
                buf.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
    }
    for t in &mesh.triangles {
        buf.push(3);
        for i in t {
            buf.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    w.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_size() {
        let m = TriMesh::new(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        );
        let mut out = Vec::new();
        write_ply(&m, &mut out).unwrap();
        let end = out.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let head = std::str::from_utf8(&out[..end]).unwrap();
        assert!(head.contains("element vertex 3") && head.contains("element face 1"));
        assert_eq!(out.len() - end, 3 * 12 + 13);
    }
}
