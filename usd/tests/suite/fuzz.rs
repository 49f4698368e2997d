//! Mutated and truncated usda never panics and never hangs the loader.
//!
//! Inputs are a real saved session (two small solids, a short history),
//! then proptest-generated edits: truncation at any byte, byte flips,
//! deleted and duplicated spans, and splices of usda tokens that change
//! types, counts and nesting. `FUZZ_CASES` cases (default 10 000) run in a
//! worker thread; the test fails if any case panics or takes longer than
//! `CASE_TIMEOUT`, printing the case. The cases come from a fixed seed, so
//! CI runs the same ones every time (a random seed once met, on a loaded
//! machine, a case that took over 20 s and could not be shown);
//! `FUZZ_SEED=N` explores others.

use crate::common;

use std::cell::Cell;
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use shapewright_usd::{load_from_str, save_to_string, LoadOptions, SaveOptions};

const CASE_TIMEOUT: Duration = Duration::from_secs(20);

const TOKENS: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    "\"",
    "'",
    "\"\"\"",
    "=",
    ",",
    "def",
    "over",
    "class",
    "custom",
    "uniform",
    "int",
    "int[]",
    "string[]",
    "token[]",
    "point3f[]",
    "Mesh",
    "Xform",
    "1e308",
    "-1",
    "nan",
    "inf",
    "99999999999999999999",
    "0",
    "(0, 0)",
    "\n",
    "#",
    "@",
    "</x>",
    "shapewright:cursor",
    "shapewright:ops",
    "{\"op\":\"delete\",\"id\":1}",
    "\\",
];

#[derive(Clone, Debug)]
enum Edit {
    Truncate(usize),
    Flip(usize, u8),
    Delete(usize, usize),
    Duplicate(usize, usize),
    Insert(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        1 => any::<usize>().prop_map(Edit::Truncate),
        3 => (any::<usize>(), any::<u8>()).prop_map(|(a, b)| Edit::Flip(a, b)),
        2 => (any::<usize>(), 1usize..64).prop_map(|(a, n)| Edit::Delete(a, n)),
        1 => (any::<usize>(), 1usize..256).prop_map(|(a, n)| Edit::Duplicate(a, n)),
        3 => (any::<usize>(), 0..TOKENS.len()).prop_map(|(a, t)| Edit::Insert(a, t)),
    ]
}

fn apply(base: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = base.to_vec();
    for e in edits {
        let n = b.len().max(1);
        match *e {
            Edit::Truncate(at) => b.truncate(at % n),
            Edit::Flip(at, v) => {
                if !b.is_empty() {
                    let i = at % b.len();
                    b[i] = v;
                }
            }
            Edit::Delete(at, len) => {
                let s = at % n;
                let e = (s + len).min(b.len());
                if s < e {
                    b.drain(s..e);
                }
            }
            Edit::Duplicate(at, len) => {
                let s = at % n;
                let e = (s + len).min(b.len());
                if s < e {
                    let span = b[s..e].to_vec();
                    b.splice(e..e, span);
                }
            }
            Edit::Insert(at, t) => {
                let s = (at % n).min(b.len());
                b.splice(s..s, TOKENS[t].bytes());
            }
        }
    }
    b
}

fn base_file() -> String {
    let log = common::run(
        r#"{"op":"add_solid","shape":{"kind":"box","size":[1,2,3]}}
{"op":"add_solid","shape":{"kind":"sphere","radius":0.5},"segments":8,"transform":{"translate":[1,0,0]}}
{"op":"transform_by","id":1,"transform":{"translate":[0,0,1]}}
{"op":"undo"}"#,
    );
    save_to_string(&log, &SaveOptions::default()).unwrap()
}

#[test]
fn mutated_and_truncated_usda_never_panics_or_hangs() {
    let cases: u32 = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let base = base_file();
    assert!(load_from_str(&base, LoadOptions::default()).is_ok());
    let seed: u64 = std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5eed_f05d);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let (tx, rx) = mpsc::channel::<(u32, usize, usize)>();
    // The case being loaded, to show when it hangs.
    let current = Arc::new(Mutex::new(String::new()));
    let current_in_worker = Arc::clone(&current);
    let worker = std::thread::spawn(move || {
        let mut runner = TestRunner::new_with_rng(
            Config {
                cases,
                failure_persistence: None,
                ..Config::default()
            },
            TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes),
        );
        let n = Cell::new(0u32);
        let ok = Cell::new(0usize);
        let err = Cell::new(0usize);
        runner
            .run(&proptest::collection::vec(edit(), 1..6), |edits| {
                let bytes = apply(base.as_bytes(), &edits);
                let text = String::from_utf8_lossy(&bytes);
                current_in_worker
                    .lock()
                    .unwrap()
                    .clone_from(&text.to_string());
                match load_from_str(
                    &text,
                    LoadOptions {
                        verify_history: true,
                        strict: false,
                    },
                ) {
                    Ok(_) => ok.set(ok.get() + 1),
                    Err(e) => {
                        // Errors must say something.
                        assert!(!e.to_string().is_empty());
                        err.set(err.get() + 1);
                    }
                }
                n.set(n.get() + 1);
                let _ = tx.send((n.get(), ok.get(), err.get()));
                Ok(())
            })
            .map_err(|e| e.to_string())
    });
    let mut last = (0, 0, 0);
    loop {
        match rx.recv_timeout(CASE_TIMEOUT) {
            Ok(p) => last = p,
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                panic!(
                    "a fuzz case hung for {CASE_TIMEOUT:?} after {} cases (FUZZ_SEED {seed}); the case:\n{}",
                    last.0,
                    current.lock().map(|c| c.clone()).unwrap_or_default()
                )
            }
        }
    }
    worker
        .join()
        .expect("worker panicked")
        .expect("a fuzz case failed");
    eprintln!(
        "fuzz: {} cases ran ({} loaded, {} rejected with typed errors)",
        last.0, last.1, last.2
    );
    assert_eq!(last.0, cases);
}
