//! Errors of the sketch pipeline.

use crate::assembly::AssemblyError;
use crate::gc::GcError;
use crate::nurbs::NurbsError;

/// Why a stroke could not be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SketchError {
    /// Too few points for the operation.
    #[error("the stroke has {got} points, at least {need} are needed")]
    TooFewPoints {
        /// Points given (after removing repeats).
        got: usize,
        /// Points needed.
        need: usize,
    },
    /// The stroke has (nearly) zero length or encloses no area.
    #[error("the stroke has zero length or encloses no area")]
    ZeroLength,
    /// A NaN or infinite coordinate.
    #[error("the stroke has a non-finite coordinate at point {0}")]
    NonFinite(usize),
    /// A closed section sketch crosses itself.
    #[error("the section sketch intersects itself")]
    SelfIntersecting,
    /// The sketch plane normal is zero or non-finite.
    #[error("the sketch plane normal is zero or non-finite")]
    BadPlane,
    /// A parameter (tolerance, sample count) is out of range.
    #[error("{what} is out of range: {value}")]
    BadParameter {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The spine bends more tightly than the section is wide: the inner
    /// side of the tube would pass through itself. Sketch a wider curve or
    /// use a smaller section.
    #[error("the sketch bends with a radius of {:.1} mm at {:.0}% of its length, tighter than the section's radius of {:.1} mm: the tube would fold into itself; sketch a wider curve or a smaller section", bend_radius * 1e3, at * 1e2, radius * 1e3)]
    TooTight {
        /// Smallest radius of curvature of the spine (model units).
        bend_radius: f64,
        /// Largest radius of the sections (model units).
        radius: f64,
        /// Where, as a fraction of the spine's parameter range.
        at: f64,
    },
    /// Even `max` key sections leave the tube farther than the tolerance
    /// from the sketch (a stroke with very sharp wiggles): smooth the
    /// stroke or raise the tolerance.
    #[error("{max} key sections still leave the tube {:.2} mm from the sketch (tolerance {:.2} mm); draw a smoother stroke", error * 1e3, tolerance * 1e3)]
    TooManySections {
        /// The most sections allowed.
        max: usize,
        /// The deviation left.
        error: f64,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// The stroke ends too far from the part it should attach to.
    #[error("the stroke {which} {:.1} mm from the nearest part's surface (at most {:.1} mm): {hint}", distance * 1e3, tolerance * 1e3)]
    OffPart {
        /// `starts` or `ends`.
        which: &'static str,
        /// Distance to the nearest part surface (model units).
        distance: f64,
        /// Largest distance accepted.
        tolerance: f64,
        /// What to do.
        hint: &'static str,
    },
    /// Curve fitting failed.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
    /// The spine the stroke makes is not a valid GC spine (or its parent
    /// part's surface could not be evaluated).
    #[error(transparent)]
    Spine(#[from] GcError),
    /// The parent's surface has no usable frame where the stroke starts.
    #[error(transparent)]
    Attach(#[from] AssemblyError),
}
