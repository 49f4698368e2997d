//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use shapewright::doc::{parse_script, run_script, OpLog};

/// Every solid script: `usd/tests/data/*.jsonl` and the project's
/// `tests/data/*.jsonl` (when present).
pub fn scripts() -> Vec<(PathBuf, String)> {
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in [here.join("tests/data"), here.join("../tests/data")] {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension().is_some_and(|x| x == "jsonl")
                    && !p.to_string_lossy().ends_with(".trace.jsonl")
            })
            .collect();
        files.sort();
        for f in files {
            let text = std::fs::read_to_string(&f).expect("read script");
            out.push((f, text));
        }
    }
    out
}

/// Runs a script into a fresh log.
pub fn run(text: &str) -> OpLog {
    let lines = parse_script(text).expect("script parses");
    let mut log = OpLog::new();
    run_script(&mut log, &lines).expect("script runs");
    log
}

/// A scratch directory unique to this test process and `name`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sw-usd-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}
