//! The command-line subcommands: thin wrappers that read files, call the
//! core and write files.

use std::path::Path;

use anyhow::{bail, Context, Result};
use shapewright::doc::{document_names, print_document_scaled, PrintScale, ScaledPrint};
use shapewright::doc::{parse_script, run_script_with, Document, OpLog};
use shapewright::mesh::{self, MeshFormat, ValidationReport, MESH_EXTENSIONS};
use shapewright::print::{PrintControl, PrintSettings, Printable, PrintedSize, Printer};
pub use shapewright_xr::files::read_mesh;

/// `apply SCRIPT --out FILE`.
pub fn apply(script: &Path, out: &Path) -> Result<()> {
    check_out(out)?;
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
    write_printed(doc, &printed, out)?;
    println!(
        "{}: {} ops, {} objects -> {} ({})",
        script.display(),
        log.cursor(),
        doc.len(),
        out.display(),
        print_summary(&printed)
    );
    println!("{}", fit_line(doc, &printed));
    Ok(())
}

/// Writes the printable model `p` of `doc` to `out` (the format by its
/// extension; 3MF objects named after the document's objects), and warns
/// on stderr, by how much per axis, when it does not fit the document's
/// printer.
pub fn write_printed(doc: &Document, p: &Printable, out: &Path) -> Result<()> {
    shapewright_xr::files::write_mesh_named(&p.mesh, &document_names(doc), out)?;
    if let Some(fit) = p.report.size().map(|s| s.fit(&doc.print_setup().printer)) {
        if !fit.fits {
            eprintln!(
                "shapewright-xr: warning: {}: the model {fit}",
                out.display()
            );
        }
    }
    Ok(())
}

/// `printer    Prusa MK4 (250 x 210 x 220 mm): fits` or `... does NOT
/// fit ...: too big by x 100.0 mm; ...`, for the summaries.
pub fn fit_line(doc: &Document, p: &Printable) -> String {
    let printer = &doc.print_setup().printer;
    match p.report.size() {
        Some(size) => format!("printer    {}", size.fit(printer)),
        None => format!("printer    {}", printer.describe()),
    }
}

/// Refuses an output path no writer takes (an unknown extension, `.usdc`)
/// before any work is done, naming the extensions that work.
pub fn check_out(out: &Path) -> Result<()> {
    if crate::usd_cmd::is_usd(out) {
        shapewright_usd::UsdEncoding::of(out)?;
    } else if MeshFormat::from_path(out).is_none() {
        bail!(
            "cannot write {}: unknown extension (use {MESH_EXTENSIONS} for the printable model, or {} for the document with its op log)",
            out.display(),
            shapewright_usd::SAVE_EXTENSIONS
        );
    }
    Ok(())
}

/// The printable model of `doc` for the mesh file `out` (validated at the
/// precision of its format), or an error naming the object(s) and why,
/// before anything is written.
pub fn print_for(doc: &Document, out: &Path) -> Result<Printable> {
    Ok(print_for_scaled(doc, out, PrintScale::By(1.0))?.printable)
}

/// [`print_for`] at a [`PrintScale`] (the core's
/// [`shapewright::doc::print_document_scaled`]).
pub fn print_for_scaled(doc: &Document, out: &Path, scale: PrintScale) -> Result<ScaledPrint> {
    let Some(format) = MeshFormat::from_path(out) else {
        bail!(
            "cannot write {}: unknown extension (use {MESH_EXTENSIONS}, or {} for the document with its op log)",
            out.display(),
            shapewright_usd::SAVE_EXTENSIONS
        );
    };
    let settings = PrintSettings::for_format(format);
    let printed = with_progress(&format!("exporting {}", out.display()), |control| {
        print_document_scaled(doc, &settings, scale, control)
    })
    .with_context(|| format!("{} not written", out.display()))?;
    for part in printed.printable.report.skipped() {
        eprintln!("shapewright-xr: note: {part} has nothing to print yet and was left out");
    }
    Ok(printed)
}

/// Runs the print job `job` on a thread of its own and reports its
/// progress on stderr (issue 37: a 2-million-triangle export took 16 s
/// without a word): silent for the first second, then a line a second
/// with the share done and the stage. Ctrl-C ends the command; the file
/// is written crash-safely after the job, so nothing is half-written.
fn with_progress<T: Send>(what: &str, job: impl FnOnce(&PrintControl) -> T + Send) -> T {
    let control = PrintControl::new();
    let mut progress = shapewright_xr::progress::Progress::new(what);
    let out = std::thread::scope(|s| {
        let (finished, ended) = std::sync::mpsc::channel::<()>();
        let c = &control;
        let worker = s.spawn(move || {
            let out = job(c);
            let _ = finished.send(());
            out
        });
        // Until the job ends (or panics, which drops the sender).
        while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
            ended.recv_timeout(std::time::Duration::from_millis(100))
        {
            let p = control.progress();
            let steps = if p.total > 0 {
                format!(" {}/{}", p.done, p.total)
            } else {
                String::new()
            };
            progress.fraction(p.fraction(), &format!("{}{steps}", p.stage.name()));
        }
        worker.join()
    });
    progress.finish_fraction();
    match out {
        Ok(v) => v,
        Err(panic) => std::panic::resume_unwind(panic),
    }
}

/// `N triangles, printable closed 2-manifold at float32; #3
/// curve_network thickened to 2 mm`.
pub fn print_summary(p: &Printable) -> String {
    use shapewright::print::Treatment;
    let r = &p.report;
    let mut s = format!(
        "{} triangles, printable closed 2-manifold at {} {}",
        p.mesh.triangle_count(),
        r.precision.name(),
        r.unit.symbol()
    );
    if let Some(size) = r.size() {
        s += &format!("; printed size {size}");
    }
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

/// `info FILE`: the validation report of a mesh file read at its unit
/// (STL and 3MF in millimetres, OBJ and PLY in metres), with its printed
/// size and whether it fits the default printer.
pub fn info(file: &Path) -> Result<()> {
    let mesh = read_mesh(file)?;
    let report = mesh::validate(&mesh, &Default::default());
    print!("{}", format_report(file, &report));
    if let Some(b) = report.bbox {
        let size = PrintedSize::new(b, Some(report.signed_volume));
        println!("bed:                  {}", size.fit(&Printer::default()));
    }
    print!("{}", shapewright_xr::files::interrupted_note(file));
    Ok(())
}

/// The report as `info` prints it (lengths in millimetres, the volume in
/// m³ and cm³).
pub fn format_report(file: &Path, r: &ValidationReport) -> String {
    let mm = |v: f64| v * 1e3;
    let bbox = r.bbox.map_or("none".to_string(), |[lo, hi]| {
        format!(
            "[{:.2}, {:.2}, {:.2}] .. [{:.2}, {:.2}, {:.2}] mm",
            mm(lo[0]),
            mm(lo[1]),
            mm(lo[2]),
            mm(hi[0]),
            mm(hi[1]),
            mm(hi[2])
        )
    });
    let size = r.bbox.map_or("none".to_string(), |b| {
        let [x, y, z] = PrintedSize::new(b, None).extent_mm();
        format!("{x:.2} x {y:.2} x {z:.2} mm")
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
         signed volume:        {:.9e} m³ ({:.3} cm³)\n\
         surface area:         {:.6e} m²\n\
         bounding box:         {}\n\
         size:                 {size}\n",
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
        r.signed_volume * 1e6,
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
