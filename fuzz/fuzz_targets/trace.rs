//! Recorded input traces (`.trace.jsonl`): parsed or a typed error, never
//! a panic. (Replaying a trace applies ops: see op_script.rs.)
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::interact::Trace;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Trace::from_jsonl(text);
    }
});
