//! Math shared by every module: glam's f64 types, rigid and affine
//! transforms with validation, and tolerances.
//!
//! All geometry is `f64`. glam's scalar paths are deterministic (no fused
//! multiply-add unless asked), which keeps replays bit-identical; so are
//! the transcendental functions of [`fm`] (the platforms' C libraries
//! differ in the last bits, issue 32).

pub mod fm;
pub mod frames;
mod mirror;
mod tolerance;
mod transform;

pub use frames::{double_reflection, rmf_step, Frame};
pub use glam::{DAffine3, DMat3, DMat4, DQuat, DVec2, DVec3};
pub use mirror::{reflect, MirrorError, MirrorPlane};
pub use tolerance::{all_finite, LENGTH_EPS};
pub use transform::{Transform, TransformError};
