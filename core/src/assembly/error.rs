//! Errors of assembly ops.

use crate::gc::GcError;
use crate::mesh::BooleanError;

/// Why an assembly op could not be applied or an assembly could not be
/// evaluated. Ops return it with the document unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AssemblyError {
    /// A child must start on its parent's surface.
    #[error("the picked point is {distance} from the parent's surface (tolerance {tolerance}); a child must start on its parent")]
    OffSurface {
        /// Distance of the point to the parent's side surface.
        distance: f64,
        /// The tolerance allowed.
        tolerance: f64,
    },
    /// A handle's spine must end on its parent's surface.
    #[error("the spine's last point is {distance} from the parent's surface (allowed {tolerance}); use end = free for a spout")]
    EndOffSurface {
        /// Distance of the last spine point to the parent's surface.
        distance: f64,
        /// The distance allowed.
        tolerance: f64,
    },
    /// A NaN or infinity in the input.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
    /// A tolerance or size that must be positive is not.
    #[error("{what} must be positive and finite, got {value}")]
    BadSize {
        /// What it is.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A spine needs at least two points.
    #[error("a child's spine needs at least 2 points, got {0}")]
    TooFewSpinePoints(usize),
    /// The parent's surface has no usable normal or spine tangent there.
    #[error("the parent's surface is degenerate at (u, v) = ({u}, {v}): no normal or spine tangent to sketch on")]
    DegenerateAnchor {
        /// Surface parameter around the section.
        u: f64,
        /// Spine parameter.
        v: f64,
    },
    /// A rotation quaternion of zero length.
    #[error("the rotation quaternion has zero length")]
    ZeroRotation,
    /// The edit would break a relation recorded between two parts (§3.3:
    /// a child left its parent, coplanar spines left their plane, ...).
    #[error("the edit would break the {relation} relation between parts {} and {}", parts.0, parts.1)]
    RelationBroken {
        /// Which relation.
        relation: super::RelationKind,
        /// The two parts (child first for `connected`, else the smaller index first).
        parts: (usize, usize),
    },
    /// `gc_release` named a relation the assembly does not record
    /// (connectivity is never recorded: it is the parent link).
    #[error("parts {} and {} have no recorded {relation} relation to release", parts.0, parts.1)]
    NotRecorded {
        /// Which relation.
        relation: super::RelationKind,
        /// The two parts.
        parts: (usize, usize),
    },
    /// A generalized cylinder could not be built, edited or meshed.
    #[error(transparent)]
    Gc(#[from] GcError),
    /// The union of the parts failed.
    #[error("the union of the assembly's parts failed: {0}")]
    Union(#[from] BooleanError),
    /// The union is not a closed 2-manifold.
    #[error("the union of the assembly's parts is not a closed 2-manifold: {0}")]
    InvalidUnion(String),
}
