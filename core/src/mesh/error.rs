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
    /// The file holds no triangles.
    #[error("the file holds no triangles")]
    Empty,
}
