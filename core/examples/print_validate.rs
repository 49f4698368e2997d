//! Times the printable checks (issue 17 / issue 21: validation must stay
//! fast) on the teapot's printable mesh and on a 1M-triangle sphere, writes
//! both as binary STL into a directory, and prints JSON (medians and
//! spread in ms) for scripts/bench/print.py, which times manifold3d's
//! import check of the same files in the same run.
//!
//! Timed per mesh: topology only (`validate` without the search), the
//! self-intersection search alone, the full `validate`, and validation at
//! float32 (`at_precision` + full `validate`: what the printable path runs
//! on its result).
//!
//! Also timed: the edit-time fold check ([`check_edit`]: one exact
//! self-intersection search of the edited object's mesh) after every GC and
//! sculpt op of the teapot, chair and bust scripts and of the ops the
//! teapot and bust traces produce, beside the op's own apply time (with the
//! check off), so the per-edit overhead is a number, not a guess.
//!
//! `cargo run --release -p shapewright --example print_validate -- OUT_DIR RUNS [THREADS]`

use std::time::Instant;

use shapewright::doc::print_document;
use shapewright::doc::{parse_script, run_script, Op, OpLog, ScriptCommand};
use shapewright::interact::trace::{replay, Trace};
use shapewright::mesh::{
    at_precision, self_intersections, validate, write_stl, Precision, TriMesh, ValidationSettings,
};
use shapewright::print::{check_edit, PrintSettings};
use shapewright::solid::{tessellate, SolidShape};

fn stats(mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    format!(
        "{{\"median\": {:.3}, \"min\": {:.3}, \"max\": {:.3}}}",
        v[v.len() / 2],
        v[0],
        v[v.len() - 1]
    )
}

fn time(runs: usize, mut f: impl FnMut()) -> String {
    let mut v = Vec::with_capacity(runs);
    for _ in 0..runs {
        let t = Instant::now();
        f();
        v.push(t.elapsed().as_secs_f64() * 1e3);
    }
    stats(v)
}

/// The GC and sculpt ops of a script or a trace's replay.
fn edit_ops(root: &std::path::Path, name: &str) -> Result<Vec<Op>, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(root.join("tests/data").join(name))?;
    let commands: Vec<ScriptCommand> = if name.ends_with(".trace.jsonl") {
        replay(&Trace::from_jsonl(&text)?)?.commands
    } else {
        parse_script(&text)?
            .into_iter()
            .map(|l| l.command)
            .collect()
    };
    Ok(commands
        .into_iter()
        .filter_map(|c| match c {
            ScriptCommand::Op(op) => Some(op),
            _ => None,
        })
        .collect())
}

/// Per GC/sculpt op of `ops` (applied in order under the `flag` policy,
/// so the op itself runs without the check): the op's apply time and the
/// fold check's time on the edited object's mesh, in ms, and its size.
fn edit_costs(ops: Vec<Op>, runs: usize) -> Result<String, Box<dyn std::error::Error>> {
    let mut log = OpLog::new();
    log.apply(serde_json::from_str(
        r#"{"op":"set_self_intersection_policy","policy":"flag"}"#,
    )?)?;
    let (mut apply_ms, mut check_ms, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    for op in ops {
        let folds = matches!(op.kind(), "gc_assembly" | "sculpt_mesh");
        let edited = serde_json::to_value(&op)?
            .get("id")
            .and_then(|v| v.as_u64());
        let t = Instant::now();
        let Ok(outcome) = log.apply(op) else {
            continue;
        };
        let dt = t.elapsed().as_secs_f64() * 1e3;
        let id = outcome.created.map(|i| i.0 as u64).or(edited);
        let Some((_, obj)) =
            id.and_then(|id| log.document().objects().find(|(oid, _)| oid.0 as u64 == id))
        else {
            continue;
        };
        if !folds {
            continue;
        }
        let mut best = f64::INFINITY;
        for _ in 0..runs.max(1) {
            let t = Instant::now();
            let ok = check_edit("#1", None, &obj.mesh).is_ok();
            best = best.min(t.elapsed().as_secs_f64() * 1e3);
            std::hint::black_box(ok);
        }
        apply_ms.push(dt);
        check_ms.push(best);
        tris.push(obj.mesh.triangle_count() as f64);
    }
    if check_ms.is_empty() {
        return Ok("{\"edits\": 0}".into());
    }
    let ratio: Vec<f64> = check_ms.iter().zip(&apply_ms).map(|(c, a)| c / a).collect();
    Ok(format!(
        "{{\"edits\": {}, \"apply_ms\": {}, \"check_ms\": {}, \"check_over_apply\": {}, \"triangles\": {}}}",
        check_ms.len(),
        stats(apply_ms),
        stats(check_ms),
        stats(ratio),
        stats(tris)
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        return Err("usage: print_validate OUT_DIR RUNS [THREADS]".into());
    }
    let runs: usize = args[2].parse()?;
    let threads: usize = args.get(3).map_or(Ok(2), |s| s.parse())?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()?;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("tests/data/teapot.jsonl"))?;
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(&text)?)?;
    let t = Instant::now();
    let teapot = print_document(log.document(), &PrintSettings::default())?;
    let print_ms = t.elapsed().as_secs_f64() * 1e3;
    let sphere = tessellate(&SolidShape::Sphere { radius: 0.1 }, 1000)?;
    std::fs::create_dir_all(&args[1])?;
    let mut out = Vec::new();
    for (name, mesh) in [("teapot", &teapot.mesh), ("sphere_1m", &sphere)] {
        let path = format!("{}/{name}.stl", args[1]);
        let mut f = std::io::BufWriter::new(std::fs::File::create(&path)?);
        write_stl(mesh, &mut f)?;
        let full = ValidationSettings::default();
        let topo = ValidationSettings::topology_only();
        let r = validate(mesh, &full);
        assert!(r.is_printable(), "{name}: {}", r.problems());
        out.push(format!(
            "\"{name}\": {{\"triangles\": {}, \"stl\": \"{path}\", \"topology_ms\": {}, \"self_intersection_ms\": {}, \"validate_ms\": {}, \"at_float32_ms\": {}}}",
            mesh.triangle_count(),
            time(runs, || drop(validate(mesh, &topo))),
            time(runs, || drop(self_intersections(mesh))),
            time(runs, || drop(validate(mesh, &full))),
            time(runs, || {
                let m: TriMesh = at_precision(mesh, Precision::F32);
                drop(validate(&m, &full))
            }),
        ));
    }
    let mut edits = Vec::new();
    for name in [
        "teapot.jsonl",
        "chair.jsonl",
        "bust.jsonl",
        "teapot.trace.jsonl",
        "bust.trace.jsonl",
    ] {
        edits.push(format!(
            "\"{name}\": {}",
            edit_costs(edit_ops(&root, name)?, runs)?
        ));
    }
    println!(
        "{{\"threads\": {threads}, \"teapot_print_document_ms\": {print_ms:.1}, {}, \"edit_check\": {{{}}}}}",
        out.join(", "),
        edits.join(", ")
    );
    Ok(())
}
