//! The stable id of a document object, and the one macro for typed
//! indices into the lists an op names (`index_type!`).
//!
//! It lives below every module (not in `doc`) because a few geometry values
//! carry a reference to another object that the document resolves before
//! the geometry code runs (a sculpt brush or base made from "that object's
//! mesh"): those values hold an [`ObjectId`] as an opaque handle and never
//! look it up themselves.

use serde::{Deserialize, Serialize};

/// The stable id of a document object. Ids are allocated by the log in
/// order, starting at 1, and never reused, so a replay allocates the same
/// ids and a script can name the objects it created.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    schemars::JsonSchema,
)]
#[serde(transparent)]
#[schemars(extend("x-ref" = "object"))]
pub struct ObjectId(pub u32);

impl std::fmt::Display for ObjectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// A typed index into a list an op names (a part, a key section, a
/// pending operand, a curve, a patch): a `usize` newtype serialized as a
/// plain number, whose schema says what it indexes (`x-ref`) for the
/// hosts' forms. One macro for every such index (issue 36).
macro_rules! index_type {
    ($(#[$doc:meta])* $name:ident, $xref:literal, $desc:literal) => {
        $(#[$doc])*
        #[derive(
            Clone,
            Copy,
            Debug,
            Default,
            PartialEq,
            Eq,
            Hash,
            PartialOrd,
            Ord,
            ::serde::Serialize,
            ::serde::Deserialize,
        )]
        #[serde(transparent)]
        pub struct $name(pub usize);

        impl ::schemars::JsonSchema for $name {
            fn schema_name() -> std::borrow::Cow<'static, str> {
                stringify!($name).into()
            }
            fn json_schema(_: &mut ::schemars::SchemaGenerator) -> ::schemars::Schema {
                ::schemars::json_schema!({
                    "type": "integer", "minimum": 0, "x-ref": $xref, "description": $desc
                })
            }
        }
    };
}
pub(crate) use index_type;
