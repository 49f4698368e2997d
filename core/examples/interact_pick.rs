//! Ray picking on a fixed scene, for the peer comparison in
//! `scripts/bench/interact.py`: writes the scene as STL and the nearest hit
//! distance of each ray of a 32x32 grid, and prints nanoseconds per ray.
//!
//! Usage: `interact_pick OUT.stl OUT_HITS.txt`

use std::io::Write;
use std::time::Instant;

use shapewright::doc::{AddSolid, Op, OpLog};
use shapewright::interact::{pick, Ray};
use shapewright::math::{DVec3, Transform};
use shapewright::mesh::write_stl;
use shapewright::solid::SolidShape;

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (stl, hits) = match args.as_slice() {
        [_, a, b] => (a.clone(), b.clone()),
        _ => {
            eprintln!("usage: interact_pick OUT.stl OUT_HITS.txt");
            std::process::exit(2);
        }
    };
    let mut log = OpLog::new();
    for i in 0..16 {
        let op = Op::AddSolid(AddSolid {
            shape: SolidShape::Sphere { radius: 0.1 },
            segments: 64,
            transform: Transform::translation([(i % 4) as f64 * 0.3, (i / 4) as f64 * 0.3, 0.0]),
        });
        if let Err(e) = log.apply(op) {
            eprintln!("scene: {e}");
            std::process::exit(1);
        }
    }
    let doc = log.document();
    let mesh = doc.combined_mesh();
    write_stl(
        &mesh,
        &mut std::io::BufWriter::new(std::fs::File::create(&stl)?),
    )?;
    let rays: Vec<Ray> = (0..32 * 32)
        .map(|k| Ray {
            origin: DVec3::new(
                -0.2 + 1.3 * (k % 32) as f64 / 31.0,
                -0.2 + 1.3 * (k / 32) as f64 / 31.0,
                2.0,
            ),
            dir: DVec3::NEG_Z,
        })
        .collect();
    let mut out = Vec::new();
    let reps = 5;
    let start = Instant::now();
    for _ in 0..reps {
        out = rays
            .iter()
            .map(|r| pick(doc, r, 10.0).map_or(-1.0, |h| h.t))
            .collect();
    }
    let ns = start.elapsed().as_nanos() as f64 / (reps * rays.len()) as f64;
    let mut f = std::io::BufWriter::new(std::fs::File::create(&hits)?);
    for t in &out {
        writeln!(f, "{t}")?;
    }
    println!(
        "triangles {} rays {} ns_per_ray {ns:.0}",
        mesh.triangles.len(),
        rays.len()
    );
    Ok(())
}
