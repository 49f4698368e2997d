//! Runs a JSONL op script and writes the document's combined mesh.
//!
//! Usage: `cargo run --release -p shapewright --example run_script -- IN.jsonl OUT.stl`
//! (the extension picks STL, OBJ or PLY). Prints the mesh's validation.

use std::io::BufWriter;

use shapewright::doc::{parse_script, run_script, OpLog};
use shapewright::mesh::{validate, write_obj, write_ply, write_stl};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 3 {
        return Err("usage: run_script IN.jsonl OUT.(stl|obj|ply)".into());
    }
    let text = std::fs::read_to_string(&args[1])?;
    let lines = parse_script(&text)?;
    let mut log = OpLog::new();
    let t = std::time::Instant::now();
    run_script(&mut log, &lines)?;
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let mesh = log.document().combined_mesh();
    let report = validate(&mesh, &Default::default());
    println!(
        "{} ops in {ms:.0} ms; {} vertices, {} triangles, closed manifold: {}, genus {:?}, volume {:.4}, hash {:016x}",
        lines.len(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        report.is_closed_manifold(),
        report.genus,
        report.signed_volume,
        log.document().content_hash()
    );
    let mut w = BufWriter::new(std::fs::File::create(&args[2])?);
    match args[2].rsplit('.').next() {
        Some("obj") => write_obj(&mesh, &mut w)?,
        Some("ply") => write_ply(&mesh, &mut w)?,
        _ => write_stl(&mesh, &mut w)?,
    }
    Ok(())
}
