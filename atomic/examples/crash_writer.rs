//! A writer to kill: the test fixture of the crash test under wine
//! (`tests/windows/test_wine.py`), cross-built for Windows by
//! `scripts/test_windows.sh`.
//!
//! `crash_writer PATH loop [BYTES]` writes version 0, 1, 2, ... of PATH
//! through [`shapewright_atomic::write_bytes`] until it is killed, and
//! prints `ACK n` after write n returned. Version n is the line
//! `version NNNNNNNNNN\n` repeated to about BYTES bytes (default 4 MiB),
//! so a kill lands inside a write often. `crash_writer PATH once` writes
//! version 0 once and prints `REMOVED k`: how many temporary files of
//! killed writes it removed (a dead writer's lock must be gone).

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

/// The content of version `n`.
fn version(n: u64, bytes: usize) -> Vec<u8> {
    let line = format!("version {n:010}\n");
    line.as_bytes().repeat(bytes.div_ceil(line.len()).max(1))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let (Some(path), Some(mode)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: crash_writer PATH loop|once [BYTES]");
        return ExitCode::from(2);
    };
    let bytes = args.get(3).and_then(|b| b.parse().ok()).unwrap_or(4 << 20);
    let path = Path::new(path);
    let mut out = std::io::stdout();
    match mode.as_str() {
        "loop" => {
            for n in 0.. {
                if let Err(e) = shapewright_atomic::write_bytes(path, &version(n, bytes)) {
                    eprintln!("write {n}: {e}");
                    return ExitCode::FAILURE;
                }
                let _ = writeln!(out, "ACK {n}");
                let _ = out.flush();
            }
            ExitCode::SUCCESS
        }
        "once" => match shapewright_atomic::write_bytes(path, &version(0, bytes)) {
            Ok(w) => {
                let _ = writeln!(out, "REMOVED {}", w.removed_stale.len());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("{e}");
                ExitCode::FAILURE
            }
        },
        _ => {
            eprintln!("unknown mode {mode}: loop or once");
            ExitCode::from(2)
        }
    }
}
