//! Errors of generalized cylinders and their edits.

use crate::nurbs::NurbsError;

/// Why a GC could not be built, edited or meshed. Ops return it with the
/// document unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GcError {
    /// A GC needs at least two key sections.
    #[error("a generalized cylinder needs at least 2 key sections, got {got}")]
    TooFewSections {
        /// Sections there would be.
        got: usize,
    },
    /// A NaN or infinite number in the input.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
    /// A section index past the end.
    #[error("section {index} does not exist (the GC has {count})")]
    BadSection {
        /// The index asked for.
        index: usize,
        /// Number of sections.
        count: usize,
    },
    /// A part index past the end of the assembly.
    #[error("part {index} does not exist (the assembly has {count})")]
    BadPart {
        /// The index asked for.
        index: usize,
        /// Number of parts.
        count: usize,
    },
    /// Section parameters must increase strictly and lie on the spine.
    #[error("section {index} at v = {v} must lie strictly between {lo} and {hi}")]
    SectionOrder {
        /// Section index.
        index: usize,
        /// Its parameter.
        v: f64,
        /// Lower bound (exclusive unless it is the spine start).
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// The spine has (nearly) zero length or repeated points.
    #[error("the spine has zero length or coincident points")]
    ZeroLengthSpine,
    /// The spine points do not lie in the spine plane.
    #[error("spine point {index} is {distance} off the spine plane")]
    NonPlanarSpine {
        /// The offending point.
        index: usize,
        /// Its distance to the plane.
        distance: f64,
    },
    /// The spine plane normal is zero.
    #[error("the spine plane normal is zero")]
    ZeroPlaneNormal,
    /// A key point may only move within the spine plane.
    #[error("the new key point is {distance} off the spine plane")]
    OffPlane {
        /// Distance of the target to the plane.
        distance: f64,
    },
    /// A size that must be positive is not.
    #[error("{what} must be positive and finite, got {value}")]
    BadSize {
        /// What the size is.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A polygon needs at least 3 sides.
    #[error("a polygon needs at least 3 sides, got {0}")]
    TooFewSides(u32),
    /// The shell/container thickness does not fit the section.
    #[error("thickness {thickness} is too large: the section at v = {v} has inscribed radius {inscribed_radius} (or curves more tightly than that)")]
    ThicknessTooLarge {
        /// The thickness asked for.
        thickness: f64,
        /// The local inscribed radius (or length, for a container floor).
        inscribed_radius: f64,
        /// The spine parameter where it does not fit.
        v: f64,
    },
    /// The first and last sections stay fixed under twisting.
    #[error("section {0} is an end section: twisting keeps the first and last sections fixed")]
    EndSectionFixed(usize),
    /// The spine has a zero tangent somewhere.
    #[error("the spine has a zero tangent at v = {0}")]
    DegenerateSpine(f64),
    /// A section sketch is unusable.
    #[error("degenerate section: {0}")]
    DegenerateSection(&'static str),
    /// The lofted surface has a point with non-positive weight or a
    /// degenerate triangle at this resolution.
    #[error("the surface is degenerate near v = {0}")]
    DegenerateSurface(f64),
    /// The mesh failed validation: in practice a side surface turned
    /// inside out by a bend much tighter than the sections are wide.
    #[error("the GC mesh is not a closed positive-volume 2-manifold ({0}); is the spine bent more tightly than the sections are wide?")]
    InvalidMesh(String),
    /// Mesh resolution out of range.
    #[error("resolution {u} x {v} is out of range (4..=4096 each)")]
    BadResolution {
        /// Samples around sections.
        u: u32,
        /// Samples along the spine.
        v: u32,
    },
    /// The GC would take more memory or work than the budget allows
    /// ([`super::budget`]): reduce the parameter named.
    #[error(transparent)]
    OverBudget(#[from] crate::budget::OverBudget),
    /// A NURBS construction failed.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
}
