//! Why a document could not be printed. Every variant names the object(s)
//! at fault as `#id kind` and says how to fix it; hosts show the message
//! as it is (the CLI exits non-zero, Blender and the headset show it).

/// The printable path refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PrintError {
    /// A setting is out of its range.
    #[error("print setting `{field}` = {value}: {reason}")]
    Settings {
        /// The field's name.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// Nothing to print: no objects, or every object was skipped.
    #[error("nothing to print: {why}")]
    Empty {
        /// "the document has no objects", or the skipped objects and why.
        why: String,
    },
    /// An object's mesh has a NaN or infinite coordinate.
    #[error("object {object}: vertex {vertex} has a non-finite coordinate; undo the edit that made it or delete the object")]
    NonFinite {
        /// The object, as `#id kind`.
        object: String,
        /// Index of the first such vertex.
        vertex: usize,
    },
    /// An object's mesh reaches absurdly far from the origin.
    #[error("object {object}: coordinate {value:e} is beyond the printable range (±{limit:e} model units); check its sizes and placement")]
    OutOfRange {
        /// The object, as `#id kind`.
        object: String,
        /// The largest offending coordinate.
        value: f64,
        /// The limit in force.
        limit: f64,
    },
    /// An object's mesh is neither a closed solid nor an open surface that
    /// can be thickened.
    #[error("object {object} is not printable: {problems}")]
    NotSolid {
        /// The object, as `#id kind`.
        object: String,
        /// What validation found.
        problems: String,
    },
    /// An open surface could not be made into a shell.
    #[error("object {object}: cannot thicken its surface to {thickness} m: {reason}")]
    Thicken {
        /// The object, as `#id kind`.
        object: String,
        /// The wall thickness asked for.
        thickness: f64,
        /// What went wrong.
        reason: String,
    },
    /// An object passes through itself (a spine bent tighter than its
    /// sections, a warp that folded the surface, a shell thicker than the
    /// surface's curvature allows).
    #[error("object {object} intersects itself ({pairs} pairs of triangles cross); undo the edit that folded it")]
    SelfIntersecting {
        /// The object, as `#id kind`.
        object: String,
        /// Crossing triangle pairs found.
        pairs: usize,
    },
    /// Manifold could not unite the parts.
    #[error("the union of {objects} failed (Manifold status {status})")]
    Union {
        /// The objects involved, as `#id kind, ...`.
        objects: String,
        /// Manifold's status.
        status: String,
    },
    /// The host stopped the job ([`super::PrintControl::cancel`]); nothing
    /// was made, and a host writes nothing.
    #[error("printing was cancelled; nothing was written")]
    Cancelled,
    /// The union is not printable at the precision of the file, even after
    /// snapping at the largest tolerance.
    #[error("{objects}: the union is not printable at {precision} ({problems}) where they touch, nearly coincide or fold; move them apart or overlap them by more than {tolerance:e} model units")]
    Invalid {
        /// The objects whose triangles are at fault, as `#id kind, ...`.
        objects: String,
        /// `float32` or `float64`.
        precision: &'static str,
        /// What validation found.
        problems: String,
        /// The largest snapping tolerance tried.
        tolerance: f64,
    },
}
