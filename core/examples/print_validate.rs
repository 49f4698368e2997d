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
//! `cargo run --release -p shapewright --example print_validate -- OUT_DIR RUNS [THREADS]`

use std::time::Instant;

use shapewright::doc::{parse_script, run_script, OpLog};
use shapewright::mesh::{
    at_precision, self_intersections, validate, write_stl, Precision, TriMesh, ValidationSettings,
};
use shapewright::print::{print_document, PrintSettings};
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
    println!(
        "{{\"threads\": {threads}, \"teapot_print_document_ms\": {print_ms:.1}, {}}}",
        out.join(", ")
    );
    Ok(())
}
