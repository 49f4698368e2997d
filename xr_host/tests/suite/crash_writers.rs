//! Kill -9 during writes, for every format the host writes (issue 22: "a
//! crash test for each writer"): STL, OBJ, PLY, USD, PNG, traces, reports.
//!
//! The child is this test binary re-run with `SW_CRASH_WRITER=FORMAT:PATH`:
//! it writes version 0, 1, 2, ... of a file of that format to PATH through
//! the host's own writer (`shapewright_xr::files`, `render::write_png`,
//! `shapewright_usd::save_file`) and prints `ACK n` after write n returned.
//! The parent kills it (SIGKILL) at a random moment after the first
//! acknowledgement, then checks that PATH is byte for byte version n or
//! n + 1 (never empty, torn or older), counts how often the kill left a
//! temporary file (the kill landed inside a write), and writes once more
//! itself: that next save must leave no temporary file behind.
//!
//! `CRASH_RUNS` kills per format (default 200).

use shapewright::math::fm::DetMath as _;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use shapewright::doc::{Op, OpLog};
use shapewright::mesh::TriMesh;
use shapewright_atomic::testkit;
use shapewright_xr::gfx::RgbaImage;

const ENV: &str = "SW_CRASH_WRITER";
const FORMATS: [&str; 7] = ["stl", "obj", "ply", "usda", "png", "trace", "report"];

/// A mesh of about 8k triangles that moves with the version.
fn mesh(version: usize) -> TriMesh {
    let (nu, nv) = (64usize, 64usize);
    let mut positions = Vec::new();
    for j in 0..=nv {
        for i in 0..nu {
            let (u, v) = (
                std::f64::consts::TAU * i as f64 / nu as f64,
                std::f64::consts::PI * j as f64 / nv as f64,
            );
            positions.push([
                v.fsin() * u.fcos() + version as f64 * 1e-3,
                v.fsin() * u.fsin(),
                v.fcos(),
            ]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..nv as u32 {
        for i in 0..nu as u32 {
            let a = j * nu as u32 + i;
            let b = j * nu as u32 + (i + 1) % nu as u32;
            let (c, d) = (a + nu as u32, b + nu as u32);
            triangles.push([a, b, c]);
            triangles.push([b, d, c]);
        }
    }
    let mut m = TriMesh::new(positions, triangles);
    m.compute_normals();
    m
}

fn text(version: usize, report: bool) -> String {
    if report {
        let v: serde_json::Value = serde_json::json!({
            "version": version,
            "frames": (0..2000).map(|i| i * version).collect::<Vec<_>>(),
        });
        serde_json::to_string_pretty(&v).unwrap()
    } else {
        (0..4000)
            .map(|i| format!("{{\"t\":{},\"v\":{version}}}\n", i as f64 * 0.011))
            .collect()
    }
}

fn log(version: usize) -> OpLog {
    let mut log = OpLog::new();
    let op: Op = serde_json::from_str(&format!(
        r#"{{"op":"add_solid","shape":{{"kind":"sphere","radius":0.1}},"segments":48,"transform":{{"translate":[{},0,0]}}}}"#,
        version as f64 * 1e-3
    ))
    .unwrap();
    log.apply(op).unwrap();
    log
}

fn image(version: usize) -> RgbaImage {
    let (width, height) = (320u32, 240u32);
    let pixels = (0..width * height * 4)
        .map(|i| ((i as usize * 7 + version * 13) % 251) as u8)
        .collect();
    RgbaImage {
        width,
        height,
        pixels,
    }
}

/// Writes version `v` of `format` to `path` with the host's writer.
fn write(format: &str, path: &Path, v: usize) {
    match format {
        "stl" | "obj" | "ply" => {
            shapewright_xr::files::write_mesh(&mesh(v), path).unwrap();
        }
        "usda" => {
            shapewright_usd::save_file(path, &log(v), &Default::default()).unwrap();
        }
        "png" => shapewright_xr::render::write_png(&image(v), path).unwrap(),
        "trace" => {
            shapewright_xr::files::write_text(path, &text(v, false)).unwrap();
        }
        "report" => {
            shapewright_xr::files::write_text(path, &text(v, true)).unwrap();
        }
        other => panic!("unknown format {other}"),
    }
}

#[test]
fn crash_child_writer() {
    let Ok(spec) = std::env::var(ENV) else {
        return;
    };
    let (format, path) = spec.split_once(':').unwrap();
    let path = PathBuf::from(path);
    for v in 0..100_000 {
        write(format, &path, v);
        println!("ACK {v}");
    }
}

fn temps(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.to_string_lossy()
                .ends_with(shapewright_atomic::TEMP_SUFFIX)
        })
        .collect()
}

#[test]
fn every_writer_survives_kill_9_at_random_moments() {
    let runs = testkit::runs(200);
    let root = std::env::temp_dir().join(format!("sw-crash-writers-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let mut delays = testkit::Delays::new(0x2545_F491_4F6C_DD1D);
    let mut summary = Vec::new();
    for format in FORMATS {
        let dir = root.join(format);
        std::fs::create_dir_all(&dir).unwrap();
        let refs = root.join(format!("{format}-expected"));
        std::fs::create_dir_all(&refs).unwrap();
        let mut expected: HashMap<usize, Vec<u8>> = HashMap::new();
        let mut expect = |v: usize| -> Vec<u8> {
            expected
                .entry(v)
                .or_insert_with(|| {
                    let p = refs.join(format!("v{v}.{format}"));
                    write(format, &p, v);
                    std::fs::read(&p).unwrap()
                })
                .clone()
        };
        let target = dir.join(format!("target.{format}"));
        let (mut mid_write, mut max_version) = (0, 0);
        for run in 0..runs {
            let child = testkit::Writer::spawn(
                "crash_writers::crash_child_writer",
                ENV,
                format!("{format}:{}", target.display()),
            );
            // After the first acknowledged write, wait 0-30 ms: a write
            // here takes a few ms, so kills land both between and inside
            // writes.
            child
                .first_ack(Duration::from_secs(60))
                .unwrap_or_else(|| panic!("{format} run {run}: the child never wrote"));
            std::thread::sleep(Duration::from_micros(delays.next_u64() % 30_000));
            let acked = child.kill().expect("an acknowledgement was read");
            let got = std::fs::read(&target)
                .unwrap_or_else(|e| panic!("{format} run {run}: target gone after kill: {e}"));
            let which = [acked, acked + 1]
                .into_iter()
                .find(|&v| got == expect(v))
                .unwrap_or_else(|| {
                    panic!(
                        "{format} run {run}: after {acked} acknowledged writes the file ({} bytes) is neither version {acked} nor {}",
                        got.len(),
                        acked + 1
                    )
                });
            max_version = max_version.max(which);
            if !temps(&dir).is_empty() {
                mid_write += 1;
            }
            // The next save of the same target removes what the kill left.
            write(format, &target, 0);
            assert!(
                temps(&dir).is_empty(),
                "{format} run {run}: a temporary file survived the next save: {:?}",
                temps(&dir)
            );
        }
        summary.push(format!(
            "{format}: {runs} kills, {mid_write} inside a write, up to version {max_version}"
        ));
        assert!(
            runs < 20 || mid_write > 0,
            "{format}: no kill landed inside a write; the test does not test"
        );
    }
    eprintln!("crash writers:\n  {}", summary.join("\n  "));
    let _ = std::fs::remove_dir_all(&root);
}
