//! A Shapewright USD document (log, snapshot, stored meshes, parametric
//! prims) loaded from any bytes: a document or a typed error.
//!
//! Loading applies the file's ops and evaluates its snapshot, so until
//! every op has a budget (issue 22, other lanes) this finds the ops'
//! allocation aborts too; scripts/fuzz.sh runs it in long runs, not in CI.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright_usd::{load_from_bytes, LoadOptions};

fuzz_target!(|data: &[u8]| {
    let _ = load_from_bytes(data, LoadOptions::default());
});
