//! Op-script lines (`.jsonl`, what `apply` and the hosts read): parsed into
//! ops or a typed error naming the line, never a panic.
//!
//! With `SW_FUZZ_APPLY=1` the parsed ops are also applied to a document
//! (a refused op changes nothing). Applying needs every op's budget
//! (issue 22, other lanes) to be abort-free, so CI parses only; the long
//! runs of scripts/fuzz.sh can apply.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright::doc::{parse_script, run_script, OpLog};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(lines) = parse_script(text) else {
        return;
    };
    if std::env::var_os("SW_FUZZ_APPLY").is_some() {
        let mut log = OpLog::new();
        let _ = run_script(&mut log, &lines);
    }
});
