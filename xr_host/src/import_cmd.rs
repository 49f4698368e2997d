//! `import FILE.usd[a|c|z] --as component|base|brush`: meshes authored
//! elsewhere (Blender, Pixar tools) into a Shapewright document
//! (shapewright-usd `import_into` and `import_brush`).
//!
//! `component` and `base` append one op (`sdf_import_component`,
//! `sculpt_create` with a mesh base) to the document `--into DOC.usda`,
//! created empty when it does not exist, and save it atomically with its
//! log; a component goes into `--volume ID`, or the document's only SDF
//! volume, or a new one (`sdf_create`, default step) when it has none.
//! `brush` writes the grid brush shape as JSON to `--out` (a brush is a
//! stroke parameter, not a document object).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use shapewright::doc::{ObjectId, OpLog};
use shapewright::math::Transform;
use shapewright_usd::{
    import_brush, import_into, load_file, save_file, ImportOptions, ImportTarget, LoadOptions,
    SaveOptions,
};

/// What the imported meshes become.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ImportAs {
    /// An SDF library component (`sdf_import_component`).
    Component,
    /// A sculpt base mesh (`sculpt_create`).
    Base,
    /// A grid brush for sculpt strokes (JSON, `--out`).
    Brush,
}

/// Arguments of `import`.
#[derive(Args, Debug)]
pub struct ImportArgs {
    /// The USD file with the meshes (.usda, .usdc, .usdz).
    pub file: PathBuf,
    /// What the meshes become.
    #[arg(long = "as", value_enum)]
    pub target: ImportAs,
    /// The Shapewright document (.usda or .usdz; .usdc is refused) to add
    /// the op to; created when missing.
    #[arg(long)]
    pub into: Option<PathBuf>,
    /// Component name (default: the file's stem).
    #[arg(long)]
    pub name: Option<String>,
    /// The SDF volume object for a component.
    #[arg(long)]
    pub volume: Option<u32>,
    /// Only meshes whose prim path starts with this.
    #[arg(long)]
    pub prefix: Option<String>,
    /// Output JSON for a brush.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Grid step of a brush, in meters.
    #[arg(long, default_value_t = 0.01)]
    pub step: f64,
}

/// Runs `import`.
pub fn import(args: &ImportArgs) -> Result<()> {
    let options = ImportOptions {
        meters_per_unit: 1.0,
        prefix: args.prefix.clone(),
    };
    if args.target == ImportAs::Brush {
        let Some(out) = &args.out else {
            bail!("--as brush needs --out BRUSH.json");
        };
        let (shape, flipped) = import_brush(&args.file, &options, args.step, 2.0 * args.step)?;
        for note in flipped {
            eprintln!("note: {note}");
        }
        shapewright_xr::files::write_text(out, &serde_json::to_string(&shape)?)?;
        println!("{} -> brush {}", args.file.display(), out.display());
        return Ok(());
    }
    let Some(into) = &args.into else {
        bail!("--as component/base needs --into DOC.usda");
    };
    shapewright_usd::UsdEncoding::of(into)?;
    let mut log = open_or_new(into)?;
    let target = match args.target {
        ImportAs::Component => ImportTarget::Component {
            volume: args.volume.map(ObjectId),
            name: match &args.name {
                Some(n) => n.clone(),
                None => stem(&args.file)?,
            },
        },
        _ => ImportTarget::SculptBase {
            transform: Transform::default(),
        },
    };
    let imported = import_into(&mut log, &args.file, &options, target)?;
    for note in &imported.flipped {
        eprintln!("note: {note}");
    }
    let outcome = imported.outcome;
    let saved = save_file(into, &log, &SaveOptions::default())
        .with_context(|| format!("saving {}", into.display()))?;
    eprint!("{}", saved.warnings());
    let name = log.ops().last().map_or("?", |op| op.name());
    println!(
        "{} -> {name}{} in {} ({} ops)",
        args.file.display(),
        outcome
            .created
            .map_or(String::new(), |id| format!(" (object {id})")),
        into.display(),
        log.len()
    );
    Ok(())
}

fn open_or_new(path: &Path) -> Result<OpLog> {
    if !path.exists() {
        return Ok(OpLog::new());
    }
    let loaded = load_file(path, LoadOptions::default())
        .with_context(|| format!("loading {}", path.display()))?;
    if let Some(w) = loaded.snapshot.warning() {
        eprintln!("warning: {}: {w}", path.display());
    }
    Ok(loaded.log)
}

fn stem(file: &Path) -> Result<String> {
    file.file_stem()
        .and_then(|s| s.to_str())
        .map(str::to_owned)
        .context("the file has no name to use for the component; give --name")
}
