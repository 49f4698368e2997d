//! Wavefront OBJ: positions and faces, in metres (the core's unit; OBJ
//! has no unit field, and modelling tools read one unit as one metre: see
//! [`super::format`]), said in a header comment. Polygons are
//! fan-triangulated; texture coordinates, normals, groups and materials
//! are ignored on read.
//!
//! The reader takes outside data: no indexing that can panic (checked by
//! `clippy::indexing_slicing`); linear in the file's size.
#![deny(clippy::indexing_slicing)]

use std::io::Write;

use super::error::parse_point;
use super::{MeshIoError, TriMesh};

/// Writes `mesh` as OBJ in metres (positions, normals when present,
/// faces).
pub fn write_obj(mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
    writeln!(
        w,
        "# Shapewright OBJ: {} vertices, {} triangles\n# units: metres (1 unit = 1 m)",
        mesh.vertex_count(),
        mesh.triangle_count()
    )?;
    for p in &mesh.positions {
        writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
    }
    let with_normals = mesh.has_vertex_normals();
    if with_normals {
        for n in &mesh.normals {
            writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
        }
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if with_normals {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        } else {
            writeln!(w, "f {a} {b} {c}")?;
        }
    }
    Ok(())
}

/// Reads OBJ text. Rejects non-finite coordinates, out-of-range or zero
/// indices, faces with fewer than three corners and unparsable numbers,
/// naming the line.
pub fn read_obj(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let text = String::from_utf8_lossy(bytes);
    let mut mesh = TriMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        let mut parts = content.split_whitespace();
        match parts.next() {
            Some("v") => {
                mesh.positions.push(parse_point(&mut parts, line)?);
            }
            Some("f") => {
                corners.clear();
                for tok in parts {
                    let idx_txt = tok.split('/').next().unwrap_or("");
                    let idx: i64 = idx_txt.parse().map_err(|_| MeshIoError::Syntax {
                        line,
                        message: format!("`{tok}` is not a vertex index"),
                    })?;
                    let n = mesh.positions.len() as i64;
                    let resolved = if idx > 0 { idx - 1 } else { n + idx };
                    if idx == 0 || resolved < 0 || resolved >= n {
                        return Err(MeshIoError::IndexOutOfRange {
                            line,
                            index: idx,
                            vertex_count: n as usize,
                        });
                    }
                    let Ok(resolved) = u32::try_from(resolved) else {
                        return Err(MeshIoError::Syntax {
                            line,
                            message: "too many vertices for 32-bit indices".into(),
                        });
                    };
                    corners.push(resolved);
                }
                if corners.len() < 3 {
                    return Err(MeshIoError::Syntax {
                        line,
                        message: format!("face needs at least 3 corners, found {}", corners.len()),
                    });
                }
                if let Some((&first, rest)) = corners.split_first() {
                    for pair in rest.windows(2) {
                        if let [b, c] = pair {
                            mesh.triangles.push([first, *b, *c]);
                        }
                    }
                }
            }
            _ => {}
        }
    }
    if mesh.triangles.is_empty() {
        return Err(MeshIoError::Empty);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_polygons() {
        let src = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf -4 -2 -1\n";
        let m = read_obj(src).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
        let mut out = Vec::new();
        write_obj(&m, &mut out).unwrap();
        assert_eq!(read_obj(&out).unwrap(), m);
    }

    #[test]
    fn errors_name_the_line() {
        let cases: &[(&[u8], MeshIoError)] = &[
            (
                b"v 0 0 0\nv 1 0\n",
                MeshIoError::Syntax {
                    line: 2,
                    message: "vertex needs 3 coordinates, found 2".into(),
                },
            ),
            (
                b"v 0 0 nan\n",
                MeshIoError::NonFiniteLine {
                    line: 1,
                    value: "nan".into(),
                },
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n",
                MeshIoError::IndexOutOfRange {
                    line: 5,
                    index: 9,
                    vertex_count: 3,
                },
            ),
            (
                b"v 0 0 0\nf 0 1 1\n",
                MeshIoError::IndexOutOfRange {
                    line: 2,
                    index: 0,
                    vertex_count: 1,
                },
            ),
            (
                b"v 0 0 0\nv 1 0 0\nf 1 2\n",
                MeshIoError::Syntax {
                    line: 3,
                    message: "face needs at least 3 corners, found 2".into(),
                },
            ),
            (
                b"v 0 0 x\n",
                MeshIoError::Syntax {
                    line: 1,
                    message: "`x` is not a number".into(),
                },
            ),
            (b"# nothing\n", MeshIoError::Empty),
        ];
        for (src, want) in cases {
            assert_eq!(&read_obj(src).unwrap_err(), want);
        }
    }
}
