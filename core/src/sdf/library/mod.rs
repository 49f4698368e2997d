//! The component library (paper 2 §3: "a dataset of 155 basic models" in
//! three groups, primitives, animals and COSEG chair parts, which users
//! augment with their own), made by the project itself as code.
//!
//! Every [`Entry`] has a unique name, a [`Category`] from a fixed list
//! covering the paper's examples and the furniture and kitchenware its
//! users built, and a builder that makes its closed, oriented mesh at two
//! levels of [`Detail`]: the component itself, whose normalized discrete
//! SDF (§5.2: centred, longest side 0.4, padding 0.1, step 0.01) the
//! [`super::cache::SdfCache`] computes on first use and keeps, and a
//! low-poly preview of a few hundred triangles that the headset palette
//! draws as the component's thumbnail (a mesh rather than a picture: the
//! palette is 3D, the preview can be turned in the hand, and it costs no
//! image files or a renderer in the core).
//!
//! **Why code, not files.** Shipping meshes (or their 61³ SDFs, 0.9 MB
//! each) would need an asset pipeline and could drift from the code; the
//! builders are a few lines each, exact (lathes, sweeps on rotation-
//! minimizing frames, ear-clipped extrusions, Manifold unions, our own
//! marching cubes for blends; see [`kit`]) and deterministic, so a
//! replay computes the same bits with or without a cache hit.
//!
//! The first 22 entries are the original starter set, unchanged and in
//! their original order ([`STARTER_NAMES`]): models and traces that name
//! them build the same bits as before.

mod furniture;
pub mod kit;
mod misc;
mod starters;
mod vessels;

mod catalog;

pub use catalog::{
    cached_component_sdf, catalog, entry, in_category, starter_mesh, Category, Entry, STARTER_NAMES,
};
pub use kit::Detail;
