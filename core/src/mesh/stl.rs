//! STL, binary and ASCII, in millimetres (every slicer reads STL as
//! millimetres; see [`super::format`]): the writer multiplies the model's
//! metres by 1000 before rounding to float32, the reader divides by 1000.
//! Triangles carry their own corners, so reading welds bit-identical
//! positions back into shared vertices.
//!
//! The reader takes outside data: no indexing that can panic (checked by
//! `clippy::indexing_slicing`).
#![deny(clippy::indexing_slicing)]

use std::io::Write;

use super::error::parse_point;
use super::{MeshIoError, TriMesh};

/// File units per model unit (millimetres per metre).
const MM: f64 = 1000.0;

/// Writes `mesh` (metres) as binary STL in millimetres (little-endian
/// f32, facet normals computed from the corners).
pub fn write_stl(mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
    let mut header = [0u8; 80];
    let tag = b"Shapewright binary STL, units: millimetres";
    for (h, t) in header.iter_mut().zip(tag) {
        *h = *t;
    }
    w.write_all(&header)?;
    w.write_all(&(mesh.triangles.len() as u32).to_le_bytes())?;
    let mut buf = Vec::with_capacity(mesh.triangles.len() * 50);
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let n = (b - a).cross(c - a).normalize_or_zero();
        for x in n.to_array() {
            buf.extend_from_slice(&(x as f32).to_le_bytes());
        }
        for v in [a, b, c] {
            for x in v.to_array() {
                buf.extend_from_slice(&((x * MM) as f32).to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
    }
    w.write_all(&buf)
}

/// Reads binary or ASCII STL (millimetres) into metres. Binary files must
/// be exactly as long as their triangle count says; any non-finite
/// coordinate is rejected.
///
/// Linear in the file's size; allocations are bounded by it (a count in
/// the header is checked against the bytes present before anything is
/// reserved).
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
    // Welding by the file's values, then metres: `x / 1000` keeps distinct
    // values distinct, and is what `at_precision_in` computes.
    mesh.weld_exact();
    for p in &mut mesh.positions {
        *p = p.map(|x| x / MM + 0.0);
    }
    Ok(mesh)
}

/// Bytes of one binary facet: normal, three corners, attribute count.
const FACET: usize = 50;

fn read_binary(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let truncated = |expected: usize| MeshIoError::Truncated {
        expected,
        actual: bytes.len(),
    };
    let (Some(count), Some(body)) = (bytes.get(80..84), bytes.get(84..)) else {
        return Err(truncated(84));
    };
    let count = u32::from_le_bytes(count.try_into().unwrap_or([0; 4])) as usize;
    let expected = count
        .checked_mul(FACET)
        .and_then(|x| x.checked_add(84))
        .unwrap_or(usize::MAX);
    if bytes.len() < expected {
        return Err(truncated(expected));
    }
    if count.saturating_mul(3) > u32::MAX as usize {
        return Err(MeshIoError::BadData {
            offset: 80,
            message: format!("{count} triangles exceed the 32-bit vertex index range"),
        });
    }
    let mut mesh = TriMesh::default();
    mesh.positions.reserve(count * 3);
    mesh.triangles.reserve(count);
    for (t, facet) in body.chunks_exact(FACET).take(count).enumerate() {
        // Skip the normal (12 bytes); three corners of three f32 each.
        let corners = facet.get(12..48).unwrap_or_default();
        for (k, corner) in corners.chunks_exact(12).enumerate() {
            let mut p = [0.0; 3];
            for (j, (slot, x)) in p.iter_mut().zip(corner.chunks_exact(4)).enumerate() {
                let x = f32::from_le_bytes(x.try_into().unwrap_or([0; 4]));
                if !x.is_finite() {
                    return Err(MeshIoError::NonFiniteAt {
                        offset: 84 + t * FACET + 12 + k * 12 + j * 4,
                    });
                }
                *slot = f64::from(x);
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
                let Ok(i) = u32::try_from(mesh.positions.len() - 3) else {
                    return Err(MeshIoError::Syntax {
                        line,
                        message: "too many vertices for 32-bit indices".into(),
                    });
                };
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
#[allow(clippy::indexing_slicing)]
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

    /// Slicers read STL in millimetres: a 0.35 m teapot must be 350 in
    /// the file (issue 31: it was 0.35, a 0.35 mm teapot).
    #[test]
    fn writes_millimetres_and_reads_them_back_as_metres() {
        let mut m = tetra();
        for p in &mut m.positions {
            *p = p.map(|x| x * 0.35);
        }
        let mut out = Vec::new();
        write_stl(&m, &mut out).unwrap();
        let f = |at: usize| f32::from_le_bytes(out[at..at + 4].try_into().unwrap());
        let corners: Vec<f32> = (0..9).map(|k| f(84 + 12 + 4 * k)).collect();
        let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
        let want: Vec<f32> = [a, b, c]
            .iter()
            .flatten()
            .map(|x| (x * 1000.0) as f32)
            .collect();
        assert_eq!(corners, want);
        assert!(corners.contains(&350.0), "{corners:?}");
        let back = read_stl(&out).unwrap();
        let (lo, hi) = back.bbox().unwrap();
        assert!(((hi - lo).max_element() - 0.35).abs() < 1e-9);
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
