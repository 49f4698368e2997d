//! Runs an op script and writes the document's combined mesh as STL.
//! `cargo run --example sdf_scene -- IN.jsonl OUT.stl`
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (inp, out) = (
        args.get(1).ok_or("IN.jsonl")?,
        args.get(2).ok_or("OUT.stl")?,
    );
    let lines = shapewright::doc::parse_script(&std::fs::read_to_string(inp)?)?;
    let mut log = shapewright::doc::OpLog::new();
    let t = Instant::now();
    shapewright::doc::run_script(&mut log, &lines)?;
    let m = log.document().combined_mesh();
    let r = shapewright::mesh::validate(&m, &Default::default());
    eprintln!(
        "{} ops in {:?}: {} triangles, {}, genus {:?}, volume {:.6}",
        lines.len(),
        t.elapsed(),
        m.triangle_count(),
        r.problems(),
        r.genus,
        r.signed_volume
    );
    let mut f = std::io::BufWriter::new(std::fs::File::create(out)?);
    shapewright::mesh::write_stl(&m, &mut f)?;
    Ok(())
}
