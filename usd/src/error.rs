//! Typed errors of saving, loading and importing.

use crate::check::ConsistencyReport;

/// Why a document could not be saved. The target file is untouched.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The layer could not be authored (a name or value USD cannot hold).
    #[error("cannot author the USD layer: {0}")]
    Author(String),
    /// Writing the file failed (see [`shapewright_atomic::AtomicError`]);
    /// the previous file is untouched.
    #[error(transparent)]
    Write(#[from] shapewright_atomic::AtomicError),
    /// The file's extension names a USD encoding this build does not write
    /// (`.usdc`: our crate files would not open in Pixar USD); nothing was
    /// written.
    #[error("cannot save {path}: {why}")]
    Unsupported {
        /// The file.
        path: String,
        /// Why, naming the extensions that work.
        why: String,
    },
}

/// Why a Shapewright USD file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("reading {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file is not valid USD (usda, usdc or usdz) according to openusd.
    #[error("not a readable USD layer: {0}")]
    Parse(String),
    /// The layer has no `/ShapewrightLog` prim: it was not written by
    /// Shapewright. Use the mesh import instead.
    #[error("no /ShapewrightLog prim: this USD file was not saved by Shapewright (import its meshes instead)")]
    NotShapewright,
    /// A version this build cannot read.
    #[error("{what} version {found} is not supported: this build reads versions {oldest} to {newest}{}",
        if *found > *newest { "; the file was written by a newer Shapewright, update to open it" }
        else { "; the file predates the first released format and cannot be migrated" })]
    UnsupportedVersion {
        /// `file format` or `op format`.
        what: &'static str,
        /// The version in the file.
        found: i64,
        /// Oldest version this build reads.
        oldest: i64,
        /// Newest version this build reads.
        newest: i64,
    },
    /// A log attribute is missing or has the wrong type.
    #[error("log attribute `{name}` is {problem}")]
    BadAttribute {
        /// The attribute.
        name: &'static str,
        /// What is wrong.
        problem: String,
    },
    /// An op of the log does not parse.
    #[error("op {index} of the log does not parse: {message}")]
    BadOp {
        /// 0-based index.
        index: usize,
        /// The serde message.
        message: String,
    },
    /// The snapshot of the document does not parse or evaluate.
    #[error("the document snapshot is invalid: {0}")]
    BadSnapshot(String),
    /// Rebuilding the log failed (bad cursor, or a replay failed).
    #[error(transparent)]
    Log(#[from] shapewright::doc::LogError),
    /// The geometry stored in the file disagrees with the log (strict load).
    #[error("the file's geometry disagrees with its log:\n{0}")]
    Inconsistent(ConsistencyReport),
    /// The stored geometry disagrees with the snapshot, and the log, which
    /// would decide, cannot be replayed: neither can be trusted.
    #[error("the file's snapshot disagrees with its stored geometry ({mismatches}), and its op log does not replay ({replay}): nothing in it can be trusted")]
    Untrusted {
        /// How the stored geometry disagrees with the snapshot.
        mismatches: String,
        /// Why the log does not replay.
        replay: String,
    },
    /// The file is nested deeper than the readers accept.
    #[error(transparent)]
    TooDeep(#[from] crate::limits::TooDeep),
}

/// Why meshes could not be imported from a USD file.
#[derive(Clone, Debug, thiserror::Error)]
pub enum ImportError {
    /// The file could not be opened or composed.
    #[error("opening {path}: {message}")]
    Open {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// Reading a prim or attribute failed.
    #[error("{path}: {message}")]
    Read {
        /// The prim or attribute path.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// A mesh's topology or points are invalid.
    #[error("mesh {path}: {message}")]
    BadMesh {
        /// The mesh prim.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// An xformOp this importer does not know.
    #[error("prim {path}: unsupported xformOp `{op}`")]
    UnsupportedXformOp {
        /// The prim.
        path: String,
        /// The op name.
        op: String,
    },
    /// Stage metadata that cannot be converted.
    #[error("stage metadata `{key}` = {value} is not supported")]
    BadStageMetadata {
        /// `upAxis` or `metersPerUnit`.
        key: &'static str,
        /// The value found.
        value: String,
    },
    /// No mesh matched.
    #[error("no UsdGeom.Mesh found in {0}")]
    NoMesh(String),
    /// The file is nested deeper than the readers accept.
    #[error(transparent)]
    TooDeep(#[from] crate::limits::TooDeep),
    /// The document refused the import op (e.g. a component that is not a
    /// closed 2-manifold, an unknown volume, a duplicate name).
    #[error("applying {op}: {message}")]
    Apply {
        /// The op name.
        op: &'static str,
        /// Why it failed.
        message: String,
    },
}
