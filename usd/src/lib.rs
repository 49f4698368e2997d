//! Shapewright documents and their op logs in USD.
//!
//! One `.usda` layer holds both what other tools see and what Shapewright
//! needs to keep editing (ARCHITECTURE.md, "USD mapping"):
//!
//! ```text
//! #usda 1.0
//! ( defaultPrim = "World"  metersPerUnit = 1  upAxis = "Z" )
//! def Xform "World" {
//!     def Xform "Object_1" {            # shapewright:objectId, shapewright:kind
//!         def Mesh "Mesh" { ... }       # points, faceVertexCounts/Indices, normals, extent
//!         # + NurbsCurves / NurbsPatch prims of parametric kinds (parametric.rs)
//!     }
//! }
//! def Scope "ShapewrightLog" {
//!     custom uniform int shapewright:formatVersion, shapewright:opFormatVersion,
//!                        shapewright:cursor, shapewright:opCount
//!     custom uniform token[] shapewright:opTypes
//!     custom uniform string[] shapewright:ops      # one JSON op per element
//!     custom uniform string shapewright:snapshot   # the document at the cursor
//! }
//! ```
//!
//! Choices made here:
//! - **One serialized JSON value per op** (an element of `string[] ops`),
//!   plus a `token[] opTypes` array naming each op's type, rather than typed
//!   attributes per op. An `Op` is already a versioned serde value with
//!   every parameter explicit ([`shapewright::doc::OP_FORMAT_VERSION`]) and
//!   serde_json prints f64 exactly, so the JSON is lossless and every op kind
//!   the other modules add is stored without USD code here. Typed
//!   attributes would need one prim per op (10k prims for a 10k-op session:
//!   slow to compose in every USD tool), a hand-written mapping for each
//!   nested enum (shapes, curves, brushes) kept in sync with the op structs,
//!   and a second versioning scheme. USD tools still see the history's shape
//!   through `opTypes`, and the JSON is plain text in the file.
//! - **A snapshot of the document at the cursor** (its kinds as JSON, meshes
//!   re-evaluated on load) makes reopening cost what the document costs,
//!   not what the history costs; the first undo replays once.
//! - **Meshes are checked on every load** against the evaluated document
//!   ([`check`]); a full replay check is an option ([`LoadOptions`]).
//! - **Writing uses `openusd`** (`=0.6.0`) to author the layer and emit usda;
//!   its usdc writer is not accepted by Pixar's reader, so we write usda
//!   (`.usda`, `.usd`) and USDZ packages of it (`.usdz`), refuse `.usdc`
//!   naming those ([`package`]), and read usda, usdc and usdz. An op or snapshot whose JSON holds
//!   a backslash (a JSON escape: openusd keeps it, Pixar unescapes it) is
//!   stored as `hex:` and its bytes' hex digits ([`save::encode_json`]), so
//!   every document can be saved and both readers agree.
//! - **A save never fails because of one object** ([`author`]): every
//!   mesh, the log and the snapshot are always written; a parametric part
//!   that cannot be made is left out and named. Patches of more than 4
//!   sides are written as their mesh plus their boundary curves.
//! - **Import** of meshes authored elsewhere ([`import`]) goes through
//!   `openusd`'s composed `Stage` (references, payloads, instancing); the
//!   xformOp stack is evaluated here ([`xform`]) so that unknown ops are
//!   errors instead of silently ignored.
//! - **Crash-safe saving** ([`atomic`], through the workspace's one writer
//!   `shapewright_atomic`): temp file, fsync, rename, fsync dir; temp files
//!   of interrupted saves are removed by the next save.
//! - **Input limits** ([`limits`]): nesting depth of usda text and of the
//!   prim tree, checked before parsing so no file can overflow the stack.
//! - **Crash-safe saving** ([`atomic`]): temp file, fsync, rename, fsync dir.
//! - **Other hosts' layouts** ([`layout`]): a stage Blender's exporter
//!   wrote with the add-on's hook keeps the log and the objects under
//!   Blender's root prim, with Blender's names; loading finds the log prim
//!   and the object prims (by `shapewright:objectId`) wherever they are.
#![forbid(unsafe_code)]

pub mod atomic;
pub mod check;
pub mod coons;
mod error;
pub mod import;
pub mod import_op;
pub mod kinds;
pub mod layout;
pub mod limits;
mod load;
pub mod package;
pub mod parametric;
pub mod prims;
pub mod save;
pub mod xform;

pub use atomic::{save_file, AutosaveSettings, Autosaver, SaveReport};
pub use check::{ConsistencyReport, Mismatch};
pub use error::{ImportError, LoadError, SaveError};
pub use import::{import_file, ImportOptions, ImportedMesh};
pub use import_op::{import_brush, import_combined, import_into, Combined, ImportTarget, Imported};
pub use load::{
    load_file, load_from_bytes, load_from_data, load_from_str, read_layer, LoadOptions, Loaded,
    SnapshotUse,
};
pub use package::{UsdEncoding, SAVE_EXTENSIONS};
pub use save::{author, save_to_string, Authored, SaveOptions, Unwritten};

/// Version of the file layout this build writes.
pub const FORMAT_VERSION: i64 = 1;
/// Oldest file layout version this build reads. Version 1 is the first
/// released layout; a future layout change bumps [`FORMAT_VERSION`] and
/// keeps reading the old one through a migration in `load.rs`.
pub const OLDEST_FORMAT_VERSION: i64 = 1;
/// The root prim holding the objects (the stage's `defaultPrim`).
pub const WORLD_PRIM: &str = "World";
/// The root prim holding the op log.
pub const LOG_PRIM: &str = "ShapewrightLog";
