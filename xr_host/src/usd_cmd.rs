//! `export` and `info` for Shapewright USD files (shapewright-usd).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::doc::{print_document, PrintScale};
use shapewright::mesh::validate;
use shapewright::print::PrintSettings;
use shapewright_usd::{load_file, LoadOptions, Mismatch};

/// `export FILE.usda --stl/--3mf/--obj/--ply OUT`: the printable model of
/// the document at the saved cursor (the union of every object, open
/// surfaces thickened, validated at each format's precision and unit), to
/// each requested format. Nothing is written when it is not printable; a
/// model that outgrows the document's printer is written with a warning
/// saying by how much.
///
/// The log is the truth: a snapshot that does not parse or that disagrees
/// with the log is replaced by the replayed log (the load does that and
/// says so), and stored meshes that disagree with the document are only
/// reported; what is exported is always the log's document.
pub fn export(file: &Path, targets: &[&Path], scale: PrintScale) -> Result<()> {
    if targets.is_empty() {
        bail!("nothing to export: give --stl, --3mf, --obj and/or --ply with an output path");
    }
    let loaded = load_file(file, LoadOptions::default())
        .with_context(|| format!("loading {}", file.display()))?;
    if let Some(w) = loaded.snapshot.warning() {
        eprintln!(
            "warning: {}: {w}; exporting the log's document ({} ops)",
            file.display(),
            loaded.log.cursor()
        );
    }
    let stored_differ = loaded
        .report
        .mismatches
        .iter()
        .any(|m| !matches!(m, Mismatch::History { .. }));
    if stored_differ {
        eprintln!(
            "warning: {}: the meshes stored in the file disagree with its op log; exporting the log's document ({}), not the stored meshes:\n{}",
            file.display(),
            if loaded.replayed {
                "replayed"
            } else {
                "its snapshot, which agrees with the replayed log"
            },
            loaded.report
        );
    }
    let doc = loaded.log.document();
    // Every target is checked before any is written, all at the scale the
    // first one settles on.
    let mut scale = scale;
    let mut printed = Vec::new();
    for path in targets {
        let p = crate::cmd::print_for_scaled(doc, path, scale)
            .with_context(|| format!("exporting {}", file.display()))?;
        if let Some(line) = p.scaled_line().filter(|_| printed.is_empty()) {
            println!("{line}");
        }
        scale = PrintScale::By(p.scale);
        printed.push((path, p.printable));
    }
    for (path, p) in &printed {
        crate::cmd::write_printed(doc, p, path)?;
        println!(
            "{} -> {} ({})",
            file.display(),
            path.display(),
            crate::cmd::print_summary(p)
        );
    }
    if let Some((_, p)) = printed.first() {
        println!("{}", crate::cmd::fit_line(doc, p));
    }
    Ok(())
}

/// `info FILE.usda`: objects, op count and cursor, mesh validation per
/// object, and whether the file's geometry agrees with its log (with a full
/// replay of the history).
pub fn info(file: &Path) -> Result<String> {
    let loaded = load_file(
        file,
        LoadOptions {
            verify_history: true,
            strict: false,
        },
    )
    .with_context(|| format!("loading {}", file.display()))?;
    let log = &loaded.log;
    let doc = log.document();
    let mut s = String::new();
    writeln!(s, "{}", file.display())?;
    writeln!(
        s,
        "format version {}, metersPerUnit {}",
        loaded.format_version, loaded.meters_per_unit
    )?;
    writeln!(
        s,
        "ops: {} (cursor {}, {} to redo)",
        log.len(),
        log.cursor(),
        log.len() - log.cursor()
    )?;
    writeln!(s, "objects: {}", doc.len())?;
    for (id, obj) in doc.objects() {
        let r = validate(&obj.mesh, &Default::default());
        let verdict = if r.is_printable() {
            format!(
                "closed manifold, genus {}",
                r.genus.map_or("?".to_owned(), |g| g.to_string())
            )
        } else {
            format!("problems: {}", r.problems())
        };
        writeln!(
            s,
            "  {id} {}: {} vertices, {} triangles, volume {:.6}, {}",
            obj.kind.name(),
            r.vertex_count,
            r.triangle_count,
            r.signed_volume,
            verdict
        )?;
    }
    writeln!(s, "validation: {}", loaded.report)?;
    if let Some(w) = loaded.snapshot.warning() {
        writeln!(s, "snapshot: {w}")?;
    }
    s.push_str(&shapewright_xr::files::interrupted_note(file));
    match print_document(doc, &PrintSettings::default()) {
        Ok(p) => {
            writeln!(
                s,
                "printable: yes, as STL or 3MF ({})",
                crate::cmd::print_summary(&p)
            )?;
            writeln!(s, "{}", crate::cmd::fit_line(doc, &p))?;
        }
        Err(e) => {
            writeln!(s, "printable: NO: {e}")?;
            writeln!(s, "printer    {}", doc.print_setup().printer.describe())?;
        }
    }
    Ok(s)
}

/// True when `path` names a USD file (.usda, .usdc, .usdz, .usd).
pub fn is_usd(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        matches!(
            e.to_ascii_lowercase().as_str(),
            "usd" | "usda" | "usdc" | "usdz"
        )
    })
}
