//! Helpers shared by the integration tests that read `tests/data/` scripts.

// Each test binary uses a subset.
#![allow(dead_code)]

use std::path::Path;

use glam::DVec3;
use shapewright::assembly::{project_to_surface, GcTransformPart};
use shapewright::doc::{parse_script, run_script, Edit, LogError, ObjectId, Op, OpLog};
use shapewright::gc::{GcAssembly, PartId};
use shapewright::nurbs::{euclidean, NurbsSurface};

/// The text of `tests/data/NAME`.
pub fn data(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The log after running the op script `text` (panics on any error).
pub fn run(text: &str) -> OpLog {
    let lines = parse_script(text).unwrap_or_else(|e| panic!("{e}"));
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap_or_else(|e| panic!("{e}"));
    log
}

/// Slides `part` of assembly `id` over its parent's surface `surf`: its
/// start `anchor` dragged by `by` and projected back on the surface, as
/// the GC tool does. Returns where it was dropped.
pub fn slide(
    log: &mut OpLog,
    id: ObjectId,
    part: usize,
    surf: &NurbsSurface,
    anchor: DVec3,
    by: DVec3,
) -> Result<DVec3, LogError> {
    let target = project_to_surface(surf, anchor + by).point;
    log.apply(Op::GcTransformPart(Edit::new(
        id,
        GcTransformPart {
            part: PartId(part),
            translate: target - anchor,
            rotate: [0.0, 0.0, 0.0, 1.0],
            tolerance: 1e-6,
        },
    )))?;
    Ok(target)
}

/// A `sculpt_create` op whose base is one closed mesh passing through
/// itself: two 1 m cubes, the second moved by half a cube on every axis.
/// Each is closed and outward; together they cross in 2 × 6 faces. A
/// stroke cannot make such a surface (the sculpt's fold and crossing
/// guards put back the steps that would), so this is how a crossing sculpt
/// object enters a document to test the print path.
pub fn crossing_sculpt() -> String {
    let cube = |o: f64| -> Vec<[f64; 3]> {
        (0..8)
            .map(|i| {
                let b = |k: u32| if i >> k & 1 == 1 { o + 1.0 } else { o };
                [b(0), b(1), b(2)]
            })
            .collect()
    };
    // Corner i has x = bit 0, y = bit 1, z = bit 2; faces outward.
    const FACES: [[u32; 3]; 12] = [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    let positions: Vec<[f64; 3]> = cube(0.0).into_iter().chain(cube(0.5)).collect();
    let triangles: Vec<[u32; 3]> = FACES
        .iter()
        .chain(FACES.iter())
        .enumerate()
        .map(|(k, t)| if k < 12 { *t } else { t.map(|v| v + 8) })
        .collect();
    format!(
        r#"{{"op":"sculpt_create","base":{{"kind":"mesh","positions":{positions:?},"triangles":{triangles:?}}}}}"#
    )
}

/// The spine control points of part `part`, in Euclidean coordinates.
pub fn spine(asm: &GcAssembly, part: usize) -> Vec<DVec3> {
    asm.parts[part]
        .gc
        .spine
        .curve
        .control
        .iter()
        .map(|h| euclidean(*h))
        .collect()
}

/// CPU seconds (user + system, every thread) of this process so far.
pub fn cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap();
    let rest = &s[s.rfind(')').unwrap() + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // Fields 14 and 15 (utime, stime), in clock ticks of 1/100 s.
    let ticks: f64 = f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap();
    ticks / 100.0
}

/// `f`'s result, and its CPU and wall seconds.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, f64) {
    let (c, w) = (cpu_seconds(), std::time::Instant::now());
    let out = f();
    (out, cpu_seconds() - c, w.elapsed().as_secs_f64())
}
