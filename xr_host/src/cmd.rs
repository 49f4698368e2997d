//! The command-line subcommands: thin wrappers that read files, call the
//! core and write files.

use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::doc::{parse_script, run_script_with, Document, OpLog};
use shapewright::mesh::{self, MeshFormat, Precision, TriMesh, ValidationReport};
use shapewright::print::{print_document, PrintSettings, Printable};
pub use shapewright_xr::files::read_mesh;

/// `apply SCRIPT --out FILE`.
pub fn apply(script: &Path, out: &Path) -> Result<()> {
    let text =
        std::fs::read_to_string(script).with_context(|| format!("reading {}", script.display()))?;
    let lines = parse_script(&text).with_context(|| format!("in {}", script.display()))?;
    let mut log = OpLog::new();
    let mut progress = shapewright_xr::progress::Progress::new("applying ops");
    run_script_with(&mut log, &lines, |done, total| progress.step(done, total))
        .with_context(|| format!("in {}", script.display()))?;
    progress.finish(lines.len());
    let doc = log.document();
    if crate::usd_cmd::is_usd(out) {
        let saved = shapewright_usd::save_file(out, &log, &shapewright_usd::SaveOptions::default())
            .with_context(|| format!("saving {}", out.display()))?;
        eprint!("{}", saved.warnings());
        let (ops, objects) = (log.cursor(), doc.len());
        println!(
            "{}: {ops} ops, {objects} objects -> {}",
            script.display(),
            out.display()
        );
        return Ok(());
    }
    let printed = print_for(doc, out)?;
    write_mesh(&printed.mesh, out)?;
    println!(
        "{}: {} ops, {} objects -> {} ({})",
        script.display(),
        log.cursor(),
        doc.len(),
        out.display(),
        print_summary(&printed)
    );
    Ok(())
}

/// The printable model of `doc` for the mesh file `out` (validated at the
/// precision of its format), or an error naming the object(s) and why,
/// before anything is written.
pub fn print_for(doc: &Document, out: &Path) -> Result<Printable> {
    let Some(format) = MeshFormat::from_path(out) else {
        bail!(
            "cannot write {}: unknown extension (use .stl, .obj or .ply)",
            out.display()
        );
    };
    let settings = PrintSettings::for_precision(Precision::of_format(format));
    let printed =
        print_document(doc, &settings).with_context(|| format!("{} not written", out.display()))?;
    for part in printed.report.skipped() {
        eprintln!("shapewright-xr: note: {part} has nothing to print yet and was left out");
    }
    Ok(printed)
}

/// `N triangles, printable closed 2-manifold at float32; #3
/// curve_network thickened to 2 mm`.
pub fn print_summary(p: &Printable) -> String {
    use shapewright::print::Treatment;
    let r = &p.report;
    let mut s = format!(
        "{} triangles, printable closed 2-manifold at {}",
        p.mesh.triangle_count(),
        r.precision.name()
    );
    for part in &r.parts {
        match &part.treatment {
            Treatment::Thickened { thickness, .. } => {
                s += &format!("; {} thickened to {} mm", part.label, thickness * 1e3)
            }
            Treatment::Hollowed { thickness } => {
                s += &format!("; {} hollowed to {} mm", part.label, thickness * 1e3)
            }
            Treatment::Skipped { .. } => {
                s += &format!("; {} skipped (nothing to print)", part.label)
            }
            Treatment::Identical { to } => {
                s += &format!("; {} identical to #{to} (printed once)", part.label)
            }
            Treatment::Solid => {}
        }
    }
    s
}

/// `info FILE`.
pub fn info(file: &Path) -> Result<()> {
    let mesh = read_mesh(file)?;
    let report = mesh::validate(&mesh, &Default::default());
    print!("{}", format_report(file, &report));
    print!("{}", shapewright_xr::files::interrupted_note(file));
    Ok(())
}

/// Writes `mesh` in the format named by `path`'s extension, crash-safely
/// ([`shapewright_xr::files`]).
pub fn write_mesh(mesh: &TriMesh, path: &Path) -> Result<()> {
    shapewright_xr::files::write_mesh(mesh, path).map(|_| ())
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
    let checks: String = r
        .checks()
        .iter()
        .map(|(name, ok)| format!("  [{}] {name}\n", if *ok { "ok" } else { "FAIL" }))
        .collect();
    let pairs = match r.self_intersecting_pairs {
        Some(0) => String::new(),
        Some(n) => format!(
            "self-intersections:   {n} triangle pairs, e.g. {}\n",
            r.intersecting_examples
                .iter()
                .map(|(a, b)| format!("({a}, {b})"))
                .collect::<Vec<_>>()
                .join(" ")
        ),
        None => "self-intersections:   not checked (coordinates out of range)\n".into(),
    };
    format!(
        "file:                 {}\n\
         printable:            {}\n\
         problems:             {}\n\
         checks:\n{checks}{pairs}\
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
        if r.is_printable() {
            "yes (closed, oriented, embedded 2-manifold)"
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
