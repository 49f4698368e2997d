//! Helpers shared by the integration tests that read `tests/data/` scripts.

use std::path::Path;

use shapewright::doc::{parse_script, run_script, OpLog};

/// The text of `tests/data/NAME`.
pub fn data(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The log after running the op script `text` (panics on any error).
pub fn run(text: &str) -> OpLog {
    let lines = parse_script(text).unwrap_or_else(|e| panic!("{e}"));
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap_or_else(|e| panic!("{e}"));
    log
}
