//! Issue 22's hostile-input failures of the file side, through the real
//! binary: a corrupted snapshot exported silently with a wrong warning,
//! stale temporary files of killed saves, a deeply nested USD file that
//! aborted the process, an empty or torn mesh file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_shapewright-xr")
}

fn run(args: &[&str]) -> Output {
    Command::new(bin()).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sw-crash-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

const SCRIPT: &str = r#"{"op":"add_solid","shape":{"kind":"sphere","radius":0.1},"segments":16}
{"op":"add_solid","shape":{"kind":"box","size":[0.1,0.2,0.3]},"transform":{"translate":[0.5,0,0]}}
"#;

#[test]
fn a_corrupted_snapshot_exports_the_log_and_says_so() {
    let d = scratch("snapshot");
    let script = d.join("s.jsonl");
    std::fs::write(&script, SCRIPT).unwrap();
    let good = d.join("good.usda");
    let o = run(&["apply", s(&script), "--out", s(&good)]);
    assert!(o.status.success(), "{}", text(&o));
    let usda = std::fs::read_to_string(&good).unwrap();
    let corrupt_text: String = usda
        .lines()
        .map(|l| {
            if l.contains("shapewright:snapshot") {
                l.replacen(r#""radius":0.1"#, r#""radius":0.3"#, 1)
            } else {
                l.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_ne!(corrupt_text, usda);
    let corrupt = d.join("corrupt.usda");
    std::fs::write(&corrupt, corrupt_text).unwrap();
    let (a, b) = (d.join("good.stl"), d.join("corrupt.stl"));
    let o = run(&["export", s(&good), "--stl", s(&a)]);
    assert!(o.status.success(), "{}", text(&o));
    let o = run(&["export", s(&corrupt), "--stl", s(&b)]);
    assert!(o.status.success(), "{}", text(&o));
    let msg = text(&o);
    assert!(
        msg.contains("disagrees with its op log") && msg.contains("exporting the log's document"),
        "{msg}"
    );
    // What is exported is the log's geometry, not the snapshot's.
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let o = run(&["info", s(&corrupt)]);
    assert!(text(&o).contains("snapshot:"), "{}", text(&o));
}

#[test]
fn info_says_a_save_was_interrupted_and_the_next_save_cleans_up() {
    let d = scratch("stale");
    let script = d.join("s.jsonl");
    std::fs::write(&script, SCRIPT).unwrap();
    for ext in ["stl", "usda"] {
        let out = d.join(format!("m.{ext}"));
        let o = run(&["apply", s(&script), "--out", s(&out)]);
        assert!(o.status.success(), "{}", text(&o));
        // What a save killed mid-write leaves.
        let stale = d.join(format!(
            ".m.{ext}.4242-0-0{}",
            shapewright_atomic::TEMP_SUFFIX
        ));
        std::fs::write(&stale, b"torn").unwrap();
        let o = run(&["info", s(&out)]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(text(&o).contains("last save interrupted"), "{}", text(&o));
        let o = run(&["apply", s(&script), "--out", s(&out)]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(
            !stale.exists(),
            "the next save must remove {}",
            stale.display()
        );
        let o = run(&["info", s(&out)]);
        assert!(!text(&o).contains("interrupted"), "{}", text(&o));
    }
}

#[test]
fn hostile_files_get_errors_not_aborts() {
    let d = scratch("hostile");
    // 20,000 nested prims overflowed the parser's stack (exit 134).
    let mut deep = String::from("#usda 1.0\n");
    deep.push_str(&"def Xform \"P\" {\n".repeat(20_000));
    deep.push_str(&"}\n".repeat(20_000));
    let deep_path = d.join("deep.usda");
    std::fs::write(&deep_path, deep).unwrap();
    for args in [
        vec!["info", s(&deep_path)],
        vec!["import", s(&deep_path), "--as", "brush", "--out", "b.json"],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("nested 4097 levels"), "{}", text(&o));
    }
    // Empty and torn mesh files (what a killed non-atomic write left).
    let empty = d.join("empty.stl");
    std::fs::write(&empty, b"").unwrap();
    let o = run(&["info", s(&empty)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("truncated"), "{}", text(&o));
    let script = d.join("s.jsonl");
    std::fs::write(&script, SCRIPT).unwrap();
    for ext in ["stl", "obj", "ply"] {
        let out = d.join(format!("t.{ext}"));
        let o = run(&["apply", s(&script), "--out", s(&out)]);
        assert!(o.status.success(), "{}", text(&o));
        let o = run(&["info", s(&out)]);
        assert!(o.status.success(), "{ext}: {}", text(&o));
        let bytes = std::fs::read(&out).unwrap();
        std::fs::write(&out, &bytes[..bytes.len() / 2]).unwrap();
        let o = run(&["info", s(&out)]);
        assert_eq!(o.status.code(), Some(1), "{ext}: {}", text(&o));
    }
}
