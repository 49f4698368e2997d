//! The command-line subcommands: thin wrappers that read files, call the
//! core and write files.

use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::doc::{parse_script, run_script, OpLog};
use shapewright::mesh::{self, MeshFormat, TriMesh, ValidationReport};

/// `apply SCRIPT --out FILE`.
pub fn apply(script: &Path, out: &Path) -> Result<()> {
    let text =
        std::fs::read_to_string(script).with_context(|| format!("reading {}", script.display()))?;
    let lines = parse_script(&text).with_context(|| format!("in {}", script.display()))?;
    let mut log = OpLog::new();
    run_script(&mut log, &lines).with_context(|| format!("in {}", script.display()))?;
    let doc = log.document();
    if crate::usd_cmd::is_usd(out) {
        shapewright_usd::save_file(out, &log, &shapewright_usd::SaveOptions::default())
            .with_context(|| format!("saving {}", out.display()))?;
        let (ops, objects) = (log.cursor(), doc.len());
        println!(
            "{}: {ops} ops, {objects} objects -> {}",
            script.display(),
            out.display()
        );
        return Ok(());
    }
    let mesh = doc
        .printable_mesh()
        .context("building the printable union")?;
    write_mesh(&mesh, out)?;
    let report = mesh::validate(&mesh, &Default::default());
    println!(
        "{}: {} ops, {} objects -> {} ({} triangles, {})",
        script.display(),
        log.cursor(),
        doc.len(),
        out.display(),
        mesh.triangle_count(),
        report.problems()
    );
    Ok(())
}

/// `info FILE`.
pub fn info(file: &Path) -> Result<()> {
    let mesh = read_mesh(file)?;
    let report = mesh::validate(&mesh, &Default::default());
    print!("{}", format_report(file, &report));
    Ok(())
}

/// Writes `mesh` in the format named by `path`'s extension.
pub fn write_mesh(mesh: &TriMesh, path: &Path) -> Result<()> {
    let Some(format) = MeshFormat::from_path(path) else {
        bail!(
            "cannot write {}: unknown extension (use .stl, .obj or .ply)",
            path.display()
        );
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = BufWriter::new(file);
    format
        .write(mesh, &mut w)
        .and_then(|()| w.flush())
        .with_context(|| format!("writing {}", path.display()))
}

/// Reads a mesh in the format named by `path`'s extension.
pub fn read_mesh(path: &Path) -> Result<TriMesh> {
    let Some(result) = MeshFormat::from_path(path)
        .and_then(|f| std::fs::read(path).map(|bytes| f.read(&bytes)).transpose())
    else {
        bail!(
            "cannot read {}: unknown extension (use .stl or .obj)",
            path.display()
        );
    };
    result
        .with_context(|| format!("reading {}", path.display()))?
        .with_context(|| format!("in {}", path.display()))
}

/// The report as `info` prints it.
pub fn format_report(file: &Path, r: &ValidationReport) -> String {
    let bbox = r.bbox.map_or("none".to_string(), |[lo, hi]| {
        format!(
            "[{:.4}, {:.4}, {:.4}] .. [{:.4}, {:.4}, {:.4}]",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        )
    });
    let genus = r
        .genus
        .map_or("n/a (not a closed manifold)".to_string(), |g| g.to_string());
    format!(
        "file:                 {}\n\
         printable:            {}\n\
         problems:             {}\n\
         vertices:             {} ({} referenced)\n\
         triangles:            {}\n\
         edges:                {}\n\
         components:           {}\n\
         euler characteristic: {}\n\
         genus:                {}\n\
         signed volume:        {:.6}\n\
         surface area:         {:.6}\n\
         bounding box:         {}\n",
        file.display(),
        if r.is_closed_manifold() {
            "yes (closed oriented 2-manifold)"
        } else {
            "NO"
        },
        r.problems(),
        r.vertex_count,
        r.referenced_vertices,
        r.triangle_count,
        r.edge_count,
        r.components,
        r.euler_characteristic,
        genus,
        r.signed_volume,
        r.area,
        bbox,
    )
}

/// The op list (`ops`), or the whole op schema as JSON (`ops --json`).
pub fn ops(json: bool) -> String {
    let schema = shapewright::doc::schema::op_schema();
    if json {
        return format!("{schema:#}\n");
    }
    let mut out = String::new();
    for op in schema["ops"].as_array().into_iter().flatten() {
        let fields: Vec<String> = op["fields"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|f| {
                let name = f["name"].as_str().unwrap_or("?");
                match f["unit"].as_str() {
                    Some(u) => format!("{name} [{u}]"),
                    None => name.to_string(),
                }
            })
            .collect();
        out += &format!(
            "{:<28} {:<14} {}\n",
            op["name"].as_str().unwrap_or("?"),
            op["kind"].as_str().unwrap_or("?"),
            fields.join(", ")
        );
    }
    out
}
