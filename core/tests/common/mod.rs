//! Helpers shared by the integration tests that read `tests/data/` scripts.

// Each test binary uses a subset.
#![allow(dead_code)]

use std::path::Path;

use glam::DVec3;
use shapewright::assembly::{project_to_surface, GcTransformPart};
use shapewright::doc::{parse_script, run_script, Edit, LogError, ObjectId, Op, OpLog};
use shapewright::gc::PartId;
use shapewright::nurbs::NurbsSurface;

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
