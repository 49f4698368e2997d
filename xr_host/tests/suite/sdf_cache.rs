//! The on-disk SDF cache end to end: the host writes component SDFs to its
//! cache directory, a second run reads them back to the same model, and a
//! corrupt or truncated blob is regenerated and rewritten.

use std::path::Path;
use std::process::Command;

fn apply(cache: &Path, out: &Path) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/csg_chair.jsonl");
    let status = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        .args([
            "apply".as_ref(),
            script.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .env("SHAPEWRIGHT_CACHE_DIR", cache)
        .status()
        .unwrap();
    assert!(status.success());
}

fn blobs(cache: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bin"))
        .map(|p| {
            let b = std::fs::read(&p).unwrap();
            (p, b)
        })
        .collect();
    v.sort();
    v
}

#[test]
fn cache_is_written_reused_and_repaired() {
    let tmp = std::env::temp_dir().join(format!("sw-sdf-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let cache = tmp.join("cache");
    let (a, b, c) = (tmp.join("a.stl"), tmp.join("b.stl"), tmp.join("c.stl"));

    apply(&cache, &a);
    let first = blobs(&cache);
    assert!(
        first.len() >= 2,
        "the chair uses at least a seat and a leg component: {first:?}"
    );

    apply(&cache, &b);
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        "cached SDFs give the same model"
    );
    assert_eq!(blobs(&cache), first, "a cache hit rewrites nothing");

    // Corrupt one blob (flip a byte) and truncate another.
    let mut flipped = first[0].1.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 0x5a;
    std::fs::write(&first[0].0, &flipped).unwrap();
    std::fs::write(&first[1].0, &first[1].1[..first[1].1.len() / 3]).unwrap();
    apply(&cache, &c);
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&c).unwrap(),
        "corrupt blobs are regenerated, not trusted"
    );
    assert_eq!(
        blobs(&cache),
        first,
        "regenerated blobs are written back intact"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}
