//! Every op script and input trace in `tests/data` (and `tests/data/bench`)
//! replays to the content hash recorded in `tests/data/fixture_hashes.txt`.
//!
//! The table was recorded before the op vocabulary moved to the document
//! floor (issue 15), so any refactor that changes what a fixture builds, bit
//! for bit, fails here. A deliberate change of behaviour re-records the table
//! with `SHAPEWRIGHT_BLESS=1 cargo test -p shapewright --test suite fixture_hashes::`
//! and says why in its commit.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use shapewright::doc::{parse_script, run_script, OpLog};
use shapewright::interact::{replay, Trace};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data")
}

/// File name -> content hash of what it builds (op scripts: the log after
/// running every line; traces: the log the replayed session produced).
fn current_hashes() -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    // `bench/`: the 30-part shelf the GC commit bench runs (issue 37),
    // kept out of the folder the slicer, USD and Windows tests read.
    let mut names: Vec<_> = ["", "bench/"]
        .into_iter()
        .flat_map(|dir| {
            std::fs::read_dir(data_dir().join(dir))
                .expect("tests/data exists")
                .map(move |e| {
                    let name = e.expect("readable entry").file_name();
                    format!("{dir}{}", name.into_string().unwrap())
                })
        })
        .filter(|n| n.ends_with(".jsonl"))
        .collect();
    names.sort();
    for name in names {
        let text = std::fs::read_to_string(data_dir().join(&name)).unwrap();
        let hash = if name.ends_with(".trace.jsonl") {
            let trace = Trace::from_jsonl(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let r = replay(&trace).unwrap_or_else(|e| panic!("{name}: {e}"));
            r.log.document().content_hash()
        } else {
            let lines = parse_script(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mut log = OpLog::new();
            run_script(&mut log, &lines).unwrap_or_else(|e| panic!("{name}: {e}"));
            log.document().content_hash()
        };
        out.insert(name, format!("{hash:016x}"));
    }
    out
}

#[test]
fn every_fixture_replays_to_its_recorded_hash() {
    let table = data_dir().join("fixture_hashes.txt");
    let now = current_hashes();
    assert!(now.len() >= 20, "expected the fixtures, found {now:?}");
    if std::env::var_os("SHAPEWRIGHT_BLESS").is_some() {
        let text: String = now.iter().map(|(n, h)| format!("{n} {h}\n")).collect();
        std::fs::write(&table, text).unwrap();
        return;
    }
    let recorded: BTreeMap<String, String> = std::fs::read_to_string(&table)
        .expect("tests/data/fixture_hashes.txt (record with SHAPEWRIGHT_BLESS=1)")
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(n, h)| (n.to_string(), h.to_string()))
        .collect();
    let mut diffs = Vec::new();
    for (name, hash) in &now {
        match recorded.get(name) {
            Some(r) if r == hash => {}
            Some(r) => diffs.push(format!("{name}: recorded {r}, now {hash}")),
            None => diffs.push(format!("{name}: not recorded (now {hash})")),
        }
    }
    for name in recorded.keys().filter(|n| !now.contains_key(*n)) {
        diffs.push(format!("{name}: recorded but the file is gone"));
    }
    assert!(
        diffs.is_empty(),
        "fixture hashes changed:\n{}",
        diffs.join("\n")
    );
}
