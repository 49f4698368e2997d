//! STL, binary and ASCII. Triangles carry their own corners, so reading
//! welds bit-identical positions back into shared vertices.

use std::io::Write;

use super::error::parse_point;
use super::{MeshIoError, TriMesh};

/// Writes `mesh` as binary STL (little-endian f32, facet normals computed
/// from the corners).
pub fn write_stl(mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
    let mut header = [0u8; 80];
    let tag = b"Shapewright binary STL";
    header[..tag.len()].copy_from_slice(tag);
    w.write_all(&header)?;
    w.write_all(&(mesh.triangles.len() as u32).to_le_bytes())?;
    let mut buf = Vec::with_capacity(mesh.triangles.len() * 50);
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let n = (b - a).cross(c - a).normalize_or_zero();
        for v in [n, a, b, c] {
            for x in v.to_array() {
                buf.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
    }
    w.write_all(&buf)
}

/// Reads binary or ASCII STL. Binary files must be exactly as long as
/// their triangle count says; any non-finite coordinate is rejected.
pub fn read_stl(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let looks_ascii = bytes.trim_ascii_start().starts_with(b"solid")
        && std::str::from_utf8(bytes).is_ok_and(|s| s.contains("facet"));
    let mut mesh = if looks_ascii {
        read_ascii(bytes)?
    } else {
        read_binary(bytes)?
    };
    if mesh.triangles.is_empty() {
        return Err(MeshIoError::Empty);
    }
    mesh.weld_exact();
    Ok(mesh)
}

fn read_binary(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    if bytes.len() < 84 {
        return Err(MeshIoError::Truncated {
            expected: 84,
            actual: bytes.len(),
        });
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    let expected = count
        .checked_mul(50)
        .and_then(|x| x.checked_add(84))
        .unwrap_or(usize::MAX);
    if bytes.len() < expected {
        return Err(MeshIoError::Truncated {
            expected,
            actual: bytes.len(),
        });
    }
    let mut mesh = TriMesh::default();
    mesh.positions.reserve(count * 3);
    for t in 0..count {
        let base = 84 + t * 50;
        for k in 0..3 {
            let mut p = [0.0; 3];
            for (j, slot) in p.iter_mut().enumerate() {
                let off = base + 12 + k * 12 + j * 4;
                let x = f32::from_le_bytes([
                    bytes[off],
                    bytes[off + 1],
                    bytes[off + 2],
                    bytes[off + 3],
                ]);
                if !x.is_finite() {
                    return Err(MeshIoError::NonFiniteAt { offset: off });
                }
                *slot = x as f64;
            }
            mesh.positions.push(p);
        }
        let i = (t * 3) as u32;
        mesh.triangles.push([i, i + 1, i + 2]);
    }
    Ok(mesh)
}

fn read_ascii(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let text = std::str::from_utf8(bytes).unwrap_or("");
    let mut mesh = TriMesh::default();
    let mut pending = 0;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let mut parts = raw.split_whitespace();
        match parts.next() {
            Some("vertex") => {
                mesh.positions.push(parse_point(&mut parts, line)?);
                pending += 1;
            }
            Some("endloop") => {
                if pending != 3 {
                    return Err(MeshIoError::Syntax {
                        line,
                        message: format!("a facet needs 3 vertices, found {pending}"),
                    });
                }
                let i = (mesh.positions.len() - 3) as u32;
                mesh.triangles.push([i, i + 1, i + 2]);
                pending = 0;
            }
            _ => {}
        }
    }
    if pending != 0 {
        return Err(MeshIoError::Syntax {
            line: last_line,
            message: "file ends inside a facet".into(),
        });
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::tetra;

    #[test]
    fn binary_round_trip_welds() {
        let mut out = Vec::new();
        write_stl(&tetra(), &mut out).unwrap();
        assert_eq!(out.len(), 84 + 4 * 50);
        let m = read_stl(&out).unwrap();
        assert_eq!(m.vertex_count(), 4);
        let r = crate::mesh::validate(&m, &Default::default());
        assert!(r.is_closed_manifold(), "{}", r.problems());
    }

    #[test]
    fn truncated_and_nan_binary() {
        let mut out = Vec::new();
        write_stl(&tetra(), &mut out).unwrap();
        assert_eq!(
            read_stl(&out[..out.len() - 7]).unwrap_err(),
            MeshIoError::Truncated {
                expected: 284,
                actual: 277
            }
        );
        assert_eq!(
            read_stl(&out[..40]).unwrap_err(),
            MeshIoError::Truncated {
                expected: 84,
                actual: 40
            }
        );
        let off = 84 + 50 + 12 + 4;
        out[off..off + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(
            read_stl(&out).unwrap_err(),
            MeshIoError::NonFiniteAt { offset: off }
        );
    }

    #[test]
    fn ascii_reads_and_rejects() {
        let good = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        assert_eq!(read_stl(good.as_bytes()).unwrap().triangle_count(), 1);
        let bad = good.replace("vertex 1 0 0\n", "");
        assert_eq!(
            read_stl(bad.as_bytes()).unwrap_err(),
            MeshIoError::Syntax {
                line: 6,
                message: "a facet needs 3 vertices, found 2".into()
            }
        );
        let nan = good.replace("vertex 1 0 0", "vertex 1 inf 0");
        assert!(matches!(
            read_stl(nan.as_bytes()).unwrap_err(),
            MeshIoError::NonFiniteLine { line: 5, .. }
        ));
    }
}
