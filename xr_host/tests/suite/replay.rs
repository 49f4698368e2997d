//! `shapewright-xr replay`: a recorded trace through the interaction core
//! with no OpenXR runtime, to any subset of USD / STL / PNG, plus the
//! one-screen summary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use shapewright::interact::{replay, Trace};
use shapewright::mesh::{read_stl, validate};
use shapewright_usd::{load_file, LoadOptions};

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/primitives_session.trace.jsonl")
}

fn host(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        .args(args)
        .output()
        .unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sw_xr_replay_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn replay_writes_usd_stl_png_and_a_summary() {
    let dir = tmp("all");
    let (usd, stl, png) = (dir.join("m.usda"), dir.join("m.stl"), dir.join("m.png"));
    let fx = fixture();
    let out = host(&[
        "replay",
        fx.to_str().unwrap(),
        "--out",
        usd.to_str().unwrap(),
        "--stl",
        stl.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let want = replay(&Trace::from_jsonl(&std::fs::read_to_string(&fx).unwrap()).unwrap()).unwrap();
    // The USD file has the whole op log and the document of the core replay.
    let loaded = load_file(
        &usd,
        LoadOptions {
            verify_history: true,
            strict: true,
        },
    )
    .unwrap();
    assert_eq!(loaded.log.ops(), want.log.ops());
    assert_eq!(loaded.log.cursor(), want.log.cursor());
    assert_eq!(
        loaded.log.document().content_hash(),
        want.log.document().content_hash()
    );
    // The STL is the printable union: closed, with the union's volume.
    let mesh = read_stl(&std::fs::read(&stl).unwrap()).unwrap();
    let r = validate(&mesh, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    let union = want.log.document().printable_mesh().unwrap();
    let v = validate(&union, &Default::default()).signed_volume;
    assert!(
        v > 1e-4 && (r.signed_volume - v).abs() < 1e-6 * v.max(1.0),
        "{} vs {v}",
        r.signed_volume
    );
    // The PNG is the renderer's: 640x480 RGBA with the model covering pixels.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (640, 480));
    let px = &buf[..info.buffer_size()];
    let bg = &px[0..4];
    let covered = px.chunks_exact(4).filter(|p| *p != bg).count();
    assert!(covered > 640 * 480 / 50, "{covered} model pixels");
    // The summary names what happened and the frame time.
    for key in [
        "commands",
        "ops",
        "objects",
        "closed 2-manifold",
        "frame time",
        "p99",
        "written",
    ] {
        assert!(stdout.contains(key), "{key} missing:\n{stdout}");
    }
    assert!(stdout.lines().count() <= 12, "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn replay_writes_only_what_is_asked() {
    let dir = tmp("subset");
    let stl = dir.join("only.stl");
    let fx = fixture();
    let out = host(&[
        "replay",
        fx.to_str().unwrap(),
        "--stl",
        stl.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(files, ["only.stl"]);
    // No outputs at all: just the summary.
    let out = host(&["replay", fx.to_str().unwrap()]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("written    nothing"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_traces_and_tools_are_clean_errors() {
    let dir = tmp("bad");
    let bad = dir.join("bad.trace.jsonl");
    std::fs::write(&bad, "{\"format\":\"other\"}\n").unwrap();
    let fx = fixture();
    for (args, want) in [
        (vec!["replay", bad.to_str().unwrap()], "trace header"),
        (
            vec!["replay", "/nonexistent.trace.jsonl"],
            "reading /nonexistent.trace.jsonl",
        ),
        (
            vec!["replay", fx.to_str().unwrap(), "--tool", "nope"],
            "unknown tool `nope`",
        ),
    ] {
        let out = host(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
