//! Runs a GC example script, writes the part meshes of assembly object 1
//! as binary STL files into a directory, and times our union of them
//! (`mesh::union`, manifold-rust): median of `runs` runs, printed as JSON
//! for scripts/bench/gc_union.py.
//!
//! `cargo run --release -p shapewright --example gc_union_parts -- SCRIPT OUT_DIR RUNS`

use std::time::Instant;

use shapewright::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use shapewright::gc::mesh_gc;
use shapewright::mesh::{union, validate, write_stl, TriMesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        return Err("usage: gc_union_parts SCRIPT OUT_DIR RUNS".into());
    }
    let runs: usize = args[3].parse()?;
    let text = std::fs::read_to_string(&args[1])?;
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(&text)?)?;
    let ObjectKind::GcAssembly(asm) = &log.document().get(ObjectId(1))?.kind else {
        return Err("object 1 is not a GC assembly".into());
    };
    std::fs::create_dir_all(&args[2])?;
    let mut parts: Vec<TriMesh> = Vec::new();
    for (i, p) in asm.parts.iter().enumerate() {
        let m = mesh_gc(&p.gc)?;
        let mut f = std::fs::File::create(format!("{}/part{i:02}.stl", args[2]))?;
        write_stl(&m, &mut f)?;
        parts.push(m);
    }
    let refs: Vec<&TriMesh> = parts.iter().collect();
    let mut times = Vec::new();
    let mut out = TriMesh::default();
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        out = union(&refs)?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let r = validate(&out, &Default::default());
    println!(
        "{{\"parts\": {}, \"input_triangles\": {}, \"output_triangles\": {}, \"median_s\": {}, \"closed\": {}, \"genus\": {}}}",
        parts.len(),
        parts.iter().map(|m| m.triangles.len()).sum::<usize>(),
        out.triangles.len(),
        times[times.len() / 2],
        r.is_closed(),
        r.genus.unwrap_or(-1)
    );
    Ok(())
}
