//! `replay TRACE --out FILE`: replays a recorded input trace through the
//! core's interaction session and exports the resulting model.

use std::path::Path;

use anyhow::{Context, Result};
use shapewright::doc::ScriptCommand;
use shapewright::interact::{replay as replay_trace, Trace};
use shapewright::mesh;

use crate::cmd::write_mesh;

/// `replay TRACE --out FILE`.
pub fn replay(trace: &Path, out: &Path) -> Result<()> {
    let text =
        std::fs::read_to_string(trace).with_context(|| format!("reading {}", trace.display()))?;
    let parsed = Trace::from_jsonl(&text).with_context(|| format!("in {}", trace.display()))?;
    let result = replay_trace(&parsed).with_context(|| format!("replaying {}", trace.display()))?;
    for (i, e) in &result.rejected {
        eprintln!("shapewright-xr: command {i} was refused: {e}");
    }
    let doc = result.log.document();
    let mut m = doc.combined_mesh();
    m.compute_normals();
    write_mesh(&m, out)?;
    let report = mesh::validate(&m, &Default::default());
    let names: Vec<&str> = result
        .commands
        .iter()
        .map(|c| match c {
            ScriptCommand::Op(op) => op.name(),
            ScriptCommand::Undo => "undo",
            ScriptCommand::Redo => "redo",
        })
        .collect();
    println!(
        "{}: {} frames -> {} commands [{}], {} objects -> {} ({} triangles, {})",
        trace.display(),
        parsed.frames.len(),
        names.len(),
        names.join(", "),
        doc.len(),
        out.display(),
        m.triangle_count(),
        report.problems()
    );
    Ok(())
}
