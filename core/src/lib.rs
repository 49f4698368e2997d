//! Shapewright: the modeling kernel of a VR modeling tool.
//!
//! The kernel holds a [`doc::Document`] of objects, changed only through
//! [`doc::Op`] values applied by a [`doc::OpLog`] (undo, redo, replay,
//! checkpoints). Every object evaluates to a [`mesh::TriMesh`], the one flat
//! buffer type used at every border (hosts, file formats, USD).
//!
//! The crate does no I/O beyond parsing and writing byte buffers handed to it
//! and has no host types; hosts (the Blender add-on, the OpenXR host) are thin
//! layers on top.
#![forbid(unsafe_code)]

pub mod assembly;
pub mod budget;
pub mod doc;
pub mod gc;
pub mod hash;
pub mod id;
pub mod interact;
pub mod math;
pub mod mesh;
pub mod nurbs;
pub mod print;
pub mod sculpt;
pub mod sdf;
pub mod sketch;
pub mod solid;
pub mod styling;
