//! Ops as flat forms: how a desktop host (the Blender add-on's operators,
//! a script, a test) offers an op as a list of plain fields and turns
//! their values into the op (issue 36: no op wire shapes or tool defaults
//! in a host).
//!
//! A form is what a person types or sketches: a section template and two
//! sizes instead of a profile, a location and an Euler-free quaternion
//! instead of a transform, a sketch instead of a spine and its key
//! sections. [`forms`] lists every form with its fields (kind, default,
//! choices, the schema field each stands for); its defaults are data here,
//! taken from the headset tools' settings where both hosts mean the same
//! thing (the curve tools' weights, the GC tool's template score, a part's
//! resolution). [`build`] turns a form's values into the op, or the ops
//! applied as one step, with the same sketch pipeline the headset runs
//! ([`crate::sketch`]). The host keeps only what is its own: labels,
//! menus, units shown, and reading its own data (a Blender mesh).
//!
//! - `table.rs`: the forms and their fields;
//! - `build.rs`: values to ops, and [`FormError`];
//! - `current.rs`: the values an edit's form starts from (the object's).

mod build;
mod current;
mod table;
#[cfg(test)]
mod tests;

pub use build::{build, FormError};
pub use current::current;
pub use table::{form_named, forms, Build, FieldKind, Form, FormField};
