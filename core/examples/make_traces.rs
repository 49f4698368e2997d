//! Regenerates the hand-gesture traces `tests/data/mug.trace.jsonl` and
//! `tests/data/teapot.trace.jsonl`, and the teapot by a controller
//! (`teapot_controller.trace.jsonl`, buttons for gestures), from their
//! puppet scripts (`shapewright::interact::{mug_trace, teapot_trace,
//! teapot_controller_trace}`), replays each and
//! prints its ops; with `--stl DIR` it also writes the replayed printable
//! models as `DIR/{mug,teapot}.stl` (to render and look at).
//!
//! `cargo run -p shapewright --example make_traces [-- --stl DIR]`

use std::path::PathBuf;

use shapewright::doc::ScriptCommand;
use shapewright::interact::replay;
use shapewright::interact::testkit::{mug_trace, teapot_controller_trace, teapot_trace};
use shapewright::mesh::{validate, ValidationSettings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let stl = args
        .iter()
        .position(|a| a == "--stl")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    for (name, trace) in [
        ("mug", mug_trace()),
        ("teapot", teapot_trace()),
        ("teapot_controller", teapot_controller_trace()),
    ] {
        let text = trace.to_jsonl();
        let path = data.join(format!("{name}.trace.jsonl"));
        std::fs::write(&path, &text)?;
        let r = replay(&trace)?;
        let ops: Vec<&str> = r.commands.iter().map(ScriptCommand::name).collect();
        println!(
            "{}: {} frames, {} bytes, ops {:?}, rejected {:?}",
            path.display(),
            trace.frames.len(),
            text.len(),
            ops,
            r.rejected
        );
        let mesh = r.log.document().printable_mesh()?;
        let rep = validate(&mesh, &ValidationSettings::default());
        println!(
            "  closed manifold {}, components {}, volume {:.6}",
            rep.is_closed_manifold(),
            rep.components,
            rep.signed_volume
        );
        if let Some(dir) = &stl {
            std::fs::create_dir_all(dir)?;
            let out = dir.join(format!("{name}.stl"));
            let mut f = std::io::BufWriter::new(std::fs::File::create(&out)?);
            shapewright::mesh::write_stl(&mesh, &mut f)?;
            println!("  wrote {}", out.display());
        }
        for (i, c) in r.commands.iter().enumerate() {
            if let ScriptCommand::Op(op) = c {
                println!("  {i}: {}", serde_json::to_string(op)?);
            }
        }
    }
    Ok(())
}
