//! Errors from reading mesh files. Each names where in the file it went
//! wrong: a 1-based line for text formats, a byte offset for binary ones.

/// A mesh file could not be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshIoError {
    /// A line of a text format could not be parsed.
    #[error("line {line}: {message}")]
    Syntax {
        /// 1-based line number.
        line: usize,
        /// What was expected.
        message: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("line {line}: coordinate {value} is not finite")]
    NonFiniteLine {
        /// 1-based line number.
        line: usize,
        /// The text that parsed to a non-finite value.
        value: String,
    },
    /// A face refers to a vertex that does not exist.
    #[error("line {line}: vertex index {index} is out of range (the file has {vertex_count} vertices so far; OBJ indices start at 1)")]
    IndexOutOfRange {
        /// 1-based line number.
        line: usize,
        /// The index as written.
        index: i64,
        /// Vertices defined before this line.
        vertex_count: usize,
    },
    /// A binary file ends before the data its header announces.
    #[error("truncated file: the header announces {expected} bytes, but the file has {actual}")]
    Truncated {
        /// Bytes the header implies.
        expected: usize,
        /// Bytes present.
        actual: usize,
    },
    /// A binary coordinate is NaN or infinite.
    #[error("byte offset {offset}: coordinate is not finite")]
    NonFiniteAt {
        /// Byte offset of the float.
        offset: usize,
    },
    /// A binary file's content is invalid (a count, an index or a layout
    /// that cannot be), at a byte offset.
    #[error("byte offset {offset}: {message}")]
    BadData {
        /// Byte offset where it was found.
        offset: usize,
        /// What is wrong.
        message: String,
    },
    /// The file holds no triangles.
    #[error("the file holds no triangles")]
    Empty,
}

/// Parses the three coordinates of a text vertex line (OBJ `v`, ASCII STL
/// `vertex`), rejecting missing, unparsable and non-finite values.
pub(crate) fn parse_point<'a>(
    parts: &mut impl Iterator<Item = &'a str>,
    line: usize,
) -> Result<[f64; 3], MeshIoError> {
    let mut p = [0.0f64; 3];
    for (k, slot) in p.iter_mut().enumerate() {
        let tok = parts.next().ok_or_else(|| MeshIoError::Syntax {
            line,
            message: format!("vertex needs 3 coordinates, found {k}"),
        })?;
        *slot = tok.parse().map_err(|_| MeshIoError::Syntax {
            line,
            message: format!("`{tok}` is not a number"),
        })?;
        if !slot.is_finite() {
            return Err(MeshIoError::NonFiniteLine {
                line,
                value: tok.into(),
            });
        }
    }
    Ok(p)
}
