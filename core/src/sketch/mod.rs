//! The sketch pipeline (paper §3.3 and §4; SPEC.md §1 "Sketch input"):
//! a 3D stroke is projected onto its sketch plane, resampled by arc length
//! and simplified by Ramer-Douglas-Peucker; closed section strokes are
//! matched against the section templates with a similarity score
//! ([`match_section`]); open spine strokes are simplified
//! ([`fit_spine_stroke`]) and interpolated by a cubic that stays within a
//! tolerance of the stroke ([`spine_points`]). Degenerate strokes
//! (too few points, zero length, self-intersecting section loops, NaN)
//! get a typed [`SketchError`]. [`section_params`] decides how many key
//! sections a sketched spine needs (from the skin's error, which curvature
//! drives), and [`child_from_stroke`] / [`replace_spine_from_stroke`] turn
//! strokes into the values of assembly edits.

#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod attach;
mod error;
mod sections;
mod spine;
mod stroke;
mod template;

pub use attach::{
    child_from_stroke, profile_radius, replace_spine_from_stroke, ChildSettings, ChildSketch,
    EndChoice, SpineReplacement, SINK,
};
pub use error::SketchError;
pub use sections::{
    section_params, sketch_spine, spine_points, stroke_deviation, SectionPlan, SectionSettings,
    SketchedSpine, CHECKS_PER_INTERVAL, CURVATURE_SAMPLES,
};
pub use spine::{fit_spine_stroke, SpineFit, SPINE_SAMPLES};
pub use stroke::{
    closed_loop_self_intersects, length, project_stroke, rdp, rdp_closed, resample, SketchPlane,
};
pub use template::{
    match_section, match_section_stroke, DrawnSection, SectionMatch, MATCH_SAMPLES,
};

#[cfg(test)]
mod sections_tests;
#[cfg(test)]
mod tests;
