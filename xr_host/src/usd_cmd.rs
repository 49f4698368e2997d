//! `export` and `info` for Shapewright USD files (shapewright-usd).

use std::fmt::Write as _;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::mesh::{validate, write_obj, write_ply, write_stl, TriMesh};
use shapewright_usd::{load_file, LoadOptions};

/// `export FILE.usda --stl/--obj/--ply OUT`: the document at the saved
/// cursor, all objects in one mesh, to each requested format.
pub fn export(
    file: &Path,
    stl: Option<&Path>,
    obj: Option<&Path>,
    ply: Option<&Path>,
) -> Result<()> {
    if stl.is_none() && obj.is_none() && ply.is_none() {
        bail!("nothing to export: give --stl, --obj and/or --ply with an output path");
    }
    let loaded = load_file(file, LoadOptions::default())
        .with_context(|| format!("loading {}", file.display()))?;
    if !loaded.report.is_consistent() {
        eprintln!(
            "warning: {}: geometry disagrees with the log; exporting the log's geometry:\n{}",
            file.display(),
            loaded.report
        );
    }
    let mesh = loaded.log.document().combined_mesh();
    type Writer = fn(&TriMesh, &mut BufWriter<File>) -> std::io::Result<()>;
    let targets: [(Option<&Path>, Writer); 3] = [
        (stl, |m, w| write_stl(m, w)),
        (obj, |m, w| write_obj(m, w)),
        (ply, |m, w| write_ply(m, w)),
    ];
    for (path, write) in targets {
        let Some(path) = path else { continue };
        let f = File::create(path).with_context(|| format!("creating {}", path.display()))?;
        let mut w = BufWriter::new(f);
        write(&mesh, &mut w).with_context(|| format!("writing {}", path.display()))?;
        std::io::Write::flush(&mut w).with_context(|| format!("writing {}", path.display()))?;
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
        writeln!(
            s,
            "  {id} {}: {} vertices, {} triangles, volume {:.6}, {}",
            obj.kind.name(),
            r.vertex_count,
            r.triangle_count,
            r.signed_volume,
            if r.is_closed_manifold() {
                format!(
                    "closed manifold, genus {}",
                    r.genus.map_or("?".to_owned(), |g| g.to_string())
                )
            } else {
                format!("problems: {}", r.problems())
            }
        )?;
    }
    writeln!(s, "validation: {}", loaded.report)?;
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
