//! PLY: output in binary little-endian (float positions and normals,
//! uchar count + int indices), the layout slicers and Blender read; input
//! in all three encodings (ascii, binary little- and big-endian). Lengths
//! are metres (PLY has no unit field; modelling tools read one unit as one
//! metre: see [`super::format`]), said in a header comment.
//!
//! Reading takes the `vertex` element's `x`, `y`, `z` (any numeric type)
//! and the `face` element's `vertex_indices` (or `vertex_index`) list,
//! fan-triangulating polygons; every other element and property is
//! skipped. It takes outside data: no indexing that can panic (checked by
//! `clippy::indexing_slicing`), counts are checked against the bytes
//! present before anything is reserved, and the work is linear in the
//! file's size.
#![deny(clippy::indexing_slicing)]

use std::io::Write;

use super::{MeshIoError, TriMesh};

/// Writes `mesh` as binary little-endian PLY.
pub fn write_ply(mesh: &TriMesh, w: &mut impl Write) -> std::io::Result<()> {
    let with_normals = mesh.has_vertex_normals();
    let mut head = String::from(
        "ply\nformat binary_little_endian 1.0\ncomment Shapewright\ncomment units: metres (1 unit = 1 m)\n",
    );
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
        if let Some(n) = mesh.normals.get(i).filter(|_| with_normals) {
            for x in n {
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

/// A scalar type of a PLY property.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

/// A property: a scalar, or a list (count type, item type).
#[derive(Clone, Debug, PartialEq)]
struct Property {
    name: String,
    scalar: Scalar,
    list_count: Option<Scalar>,
}

#[derive(Clone, Debug, PartialEq)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

fn syntax(line: usize, message: impl Into<String>) -> MeshIoError {
    MeshIoError::Syntax {
        line,
        message: message.into(),
    }
}

/// The header's elements and encoding, and the byte offset of the body.
fn read_header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, usize), MeshIoError> {
    let mut pos = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut line_no = 0;
    loop {
        line_no += 1;
        let rest = bytes.get(pos..).unwrap_or_default();
        let Some(nl) = rest.iter().position(|&b| b == b'\n') else {
            return Err(syntax(line_no, "the header has no end_header line"));
        };
        let raw = rest.get(..nl).unwrap_or_default();
        pos += nl + 1;
        let line = std::str::from_utf8(raw)
            .map_err(|_| syntax(line_no, "the header is not text"))?
            .trim_end_matches('\r');
        let mut words = line.split_whitespace();
        let first = words.next();
        if line_no == 1 {
            if line != "ply" {
                return Err(syntax(1, "not a PLY file (the first line is not `ply`)"));
            }
            continue;
        }
        match first {
            Some("format") => {
                encoding = Some(match (words.next(), words.next()) {
                    (Some("ascii"), Some("1.0")) => Encoding::Ascii,
                    (Some("binary_little_endian"), Some("1.0")) => Encoding::Little,
                    (Some("binary_big_endian"), Some("1.0")) => Encoding::Big,
                    _ => return Err(syntax(line_no, format!("unknown format `{line}`"))),
                });
            }
            Some("comment" | "obj_info") | None => {}
            Some("element") => {
                let (Some(name), Some(count)) = (words.next(), words.next()) else {
                    return Err(syntax(line_no, "element needs a name and a count"));
                };
                let count = count
                    .parse()
                    .map_err(|_| syntax(line_no, format!("`{count}` is not an element count")))?;
                elements.push(Element {
                    name: name.to_owned(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(syntax(line_no, "property before any element"));
                };
                let words: Vec<&str> = words.collect();
                let type_of = |w: &str| {
                    Scalar::parse(w)
                        .ok_or_else(|| syntax(line_no, format!("unknown property type `{w}`")))
                };
                let property = match words.as_slice() {
                    ["list", count, item, name] => Property {
                        name: (*name).to_owned(),
                        scalar: type_of(item)?,
                        list_count: Some(type_of(count)?),
                    },
                    [ty, name] => Property {
                        name: (*name).to_owned(),
                        scalar: type_of(ty)?,
                        list_count: None,
                    },
                    _ => return Err(syntax(line_no, format!("cannot read `{line}`"))),
                };
                element.properties.push(property);
            }
            Some("end_header") => break,
            Some(other) => {
                return Err(syntax(line_no, format!("unknown header keyword `{other}`")))
            }
        }
    }
    let encoding = encoding.ok_or_else(|| syntax(line_no, "the header has no format line"))?;
    Ok((encoding, elements, pos))
}

/// Reads values one by one from the body.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    encoding: Encoding,
    /// ascii: the current line (1-based) for errors.
    line: usize,
    words: std::str::SplitAsciiWhitespace<'a>,
}

impl<'a> Body<'a> {
    fn new(bytes: &'a [u8], pos: usize, encoding: Encoding, header_lines: usize) -> Self {
        Self {
            bytes,
            pos,
            encoding,
            line: header_lines,
            words: "".split_ascii_whitespace(),
        }
    }

    /// Bytes not read yet.
    fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    fn error(&self, message: impl Into<String>) -> MeshIoError {
        match self.encoding {
            Encoding::Ascii => syntax(self.line, message),
            _ => MeshIoError::BadData {
                offset: self.pos,
                message: message.into(),
            },
        }
    }

    /// Starts the next ascii record (one line per element instance).
    fn next_record(&mut self) -> Result<(), MeshIoError> {
        if self.encoding != Encoding::Ascii {
            return Ok(());
        }
        loop {
            let rest = self.bytes.get(self.pos..).unwrap_or_default();
            if rest.is_empty() {
                return Err(syntax(self.line, "the file ends before its elements do"));
            }
            let nl = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            let raw = rest.get(..nl).unwrap_or_default();
            self.pos += (nl + 1).min(rest.len());
            self.line += 1;
            let text =
                std::str::from_utf8(raw).map_err(|_| syntax(self.line, "a line is not text"))?;
            if !text.trim().is_empty() {
                self.words = text.split_ascii_whitespace();
                return Ok(());
            }
        }
    }

    fn value(&mut self, scalar: Scalar) -> Result<f64, MeshIoError> {
        if self.encoding == Encoding::Ascii {
            let word = self
                .words
                .next()
                .ok_or_else(|| syntax(self.line, "a record has too few values"))?;
            let v: f64 = word
                .parse()
                .map_err(|_| syntax(self.line, format!("`{word}` is not a number")))?;
            return Ok(v);
        }
        let n = scalar.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + n) else {
            return Err(MeshIoError::Truncated {
                expected: self.pos + n,
                actual: self.bytes.len(),
            });
        };
        let mut b = [0u8; 8];
        for (dst, src) in b.iter_mut().zip(raw) {
            *dst = *src;
        }
        if self.encoding == Encoding::Big {
            if let Some(head) = b.get_mut(..n) {
                head.reverse();
            }
        }
        self.pos += n;
        let [b0, b1, b2, b3, ..] = b;
        Ok(match scalar {
            Scalar::I8 => f64::from(b0 as i8),
            Scalar::U8 => f64::from(b0),
            Scalar::I16 => f64::from(i16::from_le_bytes([b0, b1])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b0, b1])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b0, b1, b2, b3])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b0, b1, b2, b3])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b0, b1, b2, b3])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// A list's length, checked against what is left of the file.
    fn list_len(&mut self, count: Scalar, item: Scalar) -> Result<usize, MeshIoError> {
        let n = self.value(count)?;
        if !(n >= 0.0 && n.fract() == 0.0 && n <= u32::MAX as f64) {
            return Err(self.error(format!("list length {n} is not a count")));
        }
        let n = n as usize;
        // An ascii record is one line (already consumed from `pos`): the
        // list must fit in the words left on it.
        let fits = match self.encoding {
            Encoding::Ascii => n <= self.words.clone().count(),
            _ => n.saturating_mul(item.size()) <= self.remaining(),
        };
        if !fits {
            return Err(self.error(format!(
                "a list of {n} values is longer than the rest of the file"
            )));
        }
        Ok(n)
    }
}

/// Reads a PLY file (ascii or binary) as triangles: polygons are
/// fan-triangulated, and every index and coordinate is checked.
pub fn read_ply(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let (encoding, elements, start) = read_header(bytes)?;
    let header_lines = bytes
        .get(..start)
        .map_or(0, |h| h.iter().filter(|&&b| b == b'\n').count());
    let mut body = Body::new(bytes, start, encoding, header_lines);
    let mut mesh = TriMesh::default();
    let mut seen_vertices = false;
    for element in &elements {
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        let xyz: Vec<Option<usize>> = ["x", "y", "z"]
            .iter()
            .map(|n| {
                element
                    .properties
                    .iter()
                    .position(|p| p.name == *n && p.list_count.is_none())
            })
            .collect();
        if is_vertex && xyz.iter().any(Option::is_none) {
            return Err(syntax(0, "the vertex element has no x, y and z properties"));
        }
        // Every instance takes at least a byte (a property or a line), so a
        // count beyond the rest of the file is a lie: refuse it before
        // reserving anything.
        let min_size = match encoding {
            Encoding::Ascii => 1,
            _ => element
                .properties
                .iter()
                .map(|p| p.list_count.unwrap_or(p.scalar).size())
                .sum::<usize>()
                .max(1),
        };
        if element.count.saturating_mul(min_size) > body.remaining() {
            return Err(body.error(format!(
                "element `{}` announces {} instances, more than the rest of the file holds",
                element.name, element.count
            )));
        }
        if is_vertex {
            if u32::try_from(element.count).is_err() {
                return Err(body.error("too many vertices for 32-bit indices"));
            }
            mesh.positions.reserve(element.count);
            seen_vertices = true;
        }
        if is_face {
            mesh.triangles.reserve(element.count);
        }
        let mut polygon: Vec<u32> = Vec::new();
        for _ in 0..element.count {
            body.next_record()?;
            let mut p = [0.0f64; 3];
            for (k, prop) in element.properties.iter().enumerate() {
                match prop.list_count {
                    None => {
                        let v = body.value(prop.scalar)?;
                        if is_vertex {
                            if let Some(axis) = xyz.iter().position(|i| *i == Some(k)) {
                                if !v.is_finite() {
                                    return Err(body.error(format!("coordinate {v} is not finite")));
                                }
                                if let Some(slot) = p.get_mut(axis) {
                                    *slot = v;
                                }
                            }
                        }
                    }
                    Some(count) => {
                        let n = body.list_len(count, prop.scalar)?;
                        let wanted = is_face
                            && (prop.name == "vertex_indices" || prop.name == "vertex_index");
                        polygon.clear();
                        for _ in 0..n {
                            let v = body.value(prop.scalar)?;
                            if wanted {
                                let nv = mesh.positions.len();
                                if !(v >= 0.0 && v.fract() == 0.0 && (v as usize) < nv) {
                                    return Err(body.error(format!(
                                        "vertex index {v} is out of range for {nv} vertices"
                                    )));
                                }
                                polygon.push(v as u32);
                            }
                        }
                        if wanted {
                            if !seen_vertices {
                                return Err(body.error("faces come before the vertices"));
                            }
                            if n < 3 {
                                return Err(body
                                    .error(format!("a face needs at least 3 corners, found {n}")));
                            }
                            if let Some((&first, rest)) = polygon.split_first() {
                                for pair in rest.windows(2) {
                                    if let [b, c] = pair {
                                        mesh.triangles.push([first, *b, *c]);
                                    }
                                }
                            }
                        }
                    }
                }
            }
            if is_vertex {
                mesh.positions.push(p);
            }
        }
    }
    if mesh.triangles.is_empty() {
        return Err(MeshIoError::Empty);
    }
    Ok(mesh)
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)]
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

    fn tetra() -> TriMesh {
        let mut m = crate::mesh::test_meshes::tetra();
        m.compute_normals();
        m
    }

    #[test]
    fn binary_round_trip() {
        let m = tetra();
        let mut out = Vec::new();
        write_ply(&m, &mut out).unwrap();
        let r = read_ply(&out).unwrap();
        assert_eq!(r.triangles, m.triangles);
        for (a, b) in r.positions.iter().zip(&m.positions) {
            for k in 0..3 {
                assert_eq!(a[k], f64::from(b[k] as f32));
            }
        }
    }

    #[test]
    fn ascii_and_big_endian_with_quads_and_extra_elements() {
        let ascii = "ply\nformat ascii 1.0\ncomment x\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int a\nproperty int b\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n4 0 1 2 3\n0 1\n";
        let m = read_ply(ascii.as_bytes()).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.positions[2], [1.0, 1.0, 0.0]);
        let mut big = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_index\nend_header\n".to_vec();
        for p in [[0.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.5]] {
            for x in p {
                big.extend_from_slice(&x.to_be_bytes());
            }
        }
        big.push(3);
        for i in [0u32, 1, 2] {
            big.extend_from_slice(&i.to_be_bytes());
        }
        let m = read_ply(&big).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.positions[2], [0.0, 3.0, 0.5]);
    }

    #[test]
    fn bad_files_are_typed_errors() {
        let head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let cases: Vec<(String, &str)> = vec![
            ("plx\n".into(), "line 1: not a PLY file"),
            (head.replace("end_header\n", ""), "no end_header"),
            (
                format!("{head}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
                "out of range",
            ),
            (
                format!("{head}0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"),
                "not finite",
            ),
            (
                format!("{head}0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
                "at least 3 corners",
            ),
            (format!("{head}0 0 0\n1 0 0\n"), "ends before"),
            (head.replace("vertex 3", "vertex 99999999999"), "announces"),
            (
                format!("{head}0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n"),
                "longer than the rest",
            ),
            (head.replace("property float z\n", ""), "no x, y and z"),
            (head.replace("float x", "quad x"), "unknown property type"),
        ];
        for (src, want) in cases {
            let e = read_ply(src.as_bytes()).unwrap_err().to_string();
            assert!(e.contains(want), "{want:?} not in {e:?}");
        }
        let bin = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        let e = read_ply(bin.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("announces 1000000"), "{e}");
    }
}
