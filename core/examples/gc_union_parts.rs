//! Runs a GC example script, writes the part meshes of assembly object 1
//! into a directory, and times our union of them for
//! `scripts/bench/gc_union.py` (the manifold3d peer unites the same files).
//!
//! Each part is written as `partNN.pos.f64` (vertex positions, x y z,
//! little-endian f64: our `TriMesh` holds f64) and `partNN.tri.u32`
//! (triangle indices), the arrays our union imports; the peer builds its
//! `Mesh64` from exactly these arrays. `partNN.stl` too, to look at.
//!
//! Timed, per rep: one [`shapewright::mesh::union`] of the part meshes,
//! which covers (1) the import: checking indices and coordinates, building
//! a `MeshGL64` per part and `Manifold::from_mesh_gl64` (Manifold's own
//! merge and manifold check), status checked; (2) the batch union;
//! (3) the export back to a `TriMesh` (positions, triangles, per-triangle
//! sources; no vertex normals, as on the peer's side). Not
//! timed: meshing the parts (the peer gets them as files). One untimed
//! warm-up rep first, as the peer does.
//!
//! Threads: rayon's pool, sized from the CPUs the process may use (the
//! bench runs it pinned to one CPU, and on every CPU): the union tree
//! unites the two halves of each node at once, and manifold-rust's own
//! parallel sites run on the same pool, with the same bits on any number
//! of threads (`core/src/mesh/union_tree.rs`). Allocator: mimalloc, the
//! hosts'.
//!
//! Also timed, per rep (issue 37's floor of a GC commit): one *step*, the
//! last part added to the union of all the others, which is what an edit
//! commit does at the least when the rest of the union is kept whole: the
//! part imported, one boolean with the kept rest, the result exported.
//! The rest is united and imported before the timer (a commit finds it in
//! its cache). The peer times the same step on the same arrays.
//!
//! Prints one JSON line: median and 25th–75th percentiles in ms, parts,
//! input and output triangles, and whether the result is closed and its
//! genus; the step's quartiles, its added part's and its output's
//! triangles; and every rep's time of both (`all_ms`, `step_all_ms`), which
//! `scripts/bench/gc_union.py` pools over its rounds.
//!
//! `cargo run --release -p shapewright --example gc_union_parts -- SCRIPT OUT_DIR RUNS`

use std::time::Instant;

#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

use shapewright::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use shapewright::gc::mesh_gc;
use shapewright::mesh::{
    f64_le_bytes, u32_le_bytes, union, validate, write_stl, TriMesh, UnionOperand,
};

/// Median, 25th and 75th percentiles (nearest rank) of sorted values.
fn quartiles(sorted: &[f64]) -> [f64; 3] {
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    [at(0.5), at(0.25), at(0.75)]
}

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
    let dir = &args[2];
    std::fs::create_dir_all(dir)?;
    let mut parts: Vec<TriMesh> = Vec::new();
    for (i, p) in asm.parts.iter().enumerate() {
        let m = mesh_gc(&p.gc)?;
        let mut f = std::fs::File::create(format!("{dir}/part{i:02}.stl"))?;
        write_stl(&m, &mut f)?;
        let pos = f64_le_bytes(m.positions.iter().flatten(), 1.0);
        std::fs::write(format!("{dir}/part{i:02}.pos.f64"), pos)?;
        let tri = u32_le_bytes(m.triangles.iter().flatten());
        std::fs::write(format!("{dir}/part{i:02}.tri.u32"), tri)?;
        parts.push(m);
    }
    let refs: Vec<&TriMesh> = parts.iter().collect();
    let mut out = union(&refs)?; // warm-up, untimed
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        out = union(&refs)?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let [med, p25, p75] = quartiles(&times);
    // The step: the last part added to the kept union of the others.
    let (last, others) = refs.split_last().ok_or("no parts")?;
    let kept = UnionOperand::import_group(&[(0, &union(others)?)])
        .map_err(|(_, e)| e)?
        .ok_or("the other parts are empty")?;
    let mut step = Vec::new();
    let mut stepped = TriMesh::default();
    for _ in 0..runs.max(1) + 1 {
        let t = Instant::now();
        let part = UnionOperand::import_group(&[(others.len(), last)])
            .map_err(|(_, e)| e)?
            .ok_or("the last part is empty")?;
        stepped = kept.union(&part).to_mesh()?;
        step.push(t.elapsed().as_secs_f64() * 1e3);
    }
    step.remove(0); // warm-up
    step.sort_by(f64::total_cmp);
    let [s50, s25, s75] = quartiles(&step);
    let r = validate(&out, &Default::default());
    println!(
        "{{\"parts\": {}, \"input_triangles\": {}, \"output_triangles\": {}, \"ms\": [{med:.4}, {p25:.4}, {p75:.4}], \"all_ms\": {:?}, \"runs\": {}, \"threads\": {}, \"closed\": {}, \"genus\": {}, \"step_ms\": [{s50:.4}, {s25:.4}, {s75:.4}], \"step_all_ms\": {:?}, \"step_part_triangles\": {}, \"step_output_triangles\": {}}}",
        parts.len(),
        parts.iter().map(|m| m.triangles.len()).sum::<usize>(),
        out.triangles.len(),
        times,
        times.len(),
        rayon::current_num_threads(),
        r.is_closed(),
        r.genus.unwrap_or(-1),
        step,
        last.triangles.len(),
        stepped.triangles.len(),
    );
    Ok(())
}
