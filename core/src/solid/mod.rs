//! Parametric solids: box, sphere, ellipsoid, cylinder, cone, torus and
//! capsule, meshed to closed oriented 2-manifolds. The first object kind of
//! the document; the SDF component library and the sculpt brushes reuse
//! the shapes.

mod shape;
mod sizes;
mod tessellate;

pub use shape::{SolidError, SolidShape, DEFAULT_SEGMENTS, MAX_SEGMENTS, MIN_SEGMENTS};
pub use sizes::SOLID_KINDS;
pub use tessellate::tessellate;
