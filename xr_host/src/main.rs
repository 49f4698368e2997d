//! `shapewright-xr`: the standalone Shapewright host.
//!
//! Op scripts (`apply`), USD files (`info`, `export`), meshes (`render`),
//! input traces (`replay`) and the OpenXR session (`run`).

mod cmd;
mod import_cmd;
mod join;
mod render_cmd;
mod replay_cmd;
mod run_cmd;
mod usd_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// mimalloc: the system allocator returns and re-faults large blocks on
/// every mesh update (see the workspace manifest).
#[global_allocator]
static ALLOC: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Shapewright standalone host.
#[derive(Parser)]
#[command(name = "shapewright-xr", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replay an op script (.jsonl) and export the result (.stl, .obj, .ply
    /// as the printable union; .usda with the whole op log).
    Apply {
        /// The script: one JSON op per line.
        script: PathBuf,
        /// Output file; the format follows the extension.
        #[arg(long)]
        out: PathBuf,
    },
    /// Replay a recorded input trace (.trace.jsonl) through the interaction
    /// core, write any of --out/--stl/--png and print a summary.
    Replay(replay_cmd::ReplayArgs),
    /// Print the validation report of a mesh file (.stl, .obj), or the
    /// objects, op count and reports of a Shapewright USD file.
    Info {
        /// The mesh or USD file.
        file: PathBuf,
    },
    /// Export the document of a Shapewright USD file as STL, OBJ and/or PLY.
    Export {
        /// The .usda/.usdc/.usdz file.
        file: PathBuf,
        /// Write binary STL here.
        #[arg(long)]
        stl: Option<PathBuf>,
        /// Write OBJ here.
        #[arg(long)]
        obj: Option<PathBuf>,
        /// Write PLY here.
        #[arg(long)]
        ply: Option<PathBuf>,
    },
    /// Import the meshes of a USD file (Blender, pxr) into a document as an
    /// SDF library component or a sculpt base mesh, or as a grid brush.
    Import(import_cmd::ImportArgs),
    /// Run the OpenXR session (headset with Vulkan; `--headless`: input only, XR_MND_headless).
    Run(run_cmd::RunArgs),
    /// List every op the core knows, with its fields (`--json`: the whole
    /// machine-readable schema: types, units, ranges, defaults, docs).
    Ops {
        /// Print the schema as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Print the nats-server configuration that lets each member of a
    /// member list (lines `USER PASSWORD-HASH DOC:editor|viewer ...`) do
    /// exactly that in shared sessions (scripts/nats.sh --users FILE uses
    /// it); --hash hashes the list's passwords, --invite adds a member.
    SessionAccess(join::AccessArgs),
    /// Render a mesh file (.stl, .obj) to a PNG with the host's Vulkan renderer.
    Render {
        /// The mesh file.
        file: PathBuf,
        /// Output PNG.
        #[arg(long)]
        png: PathBuf,
        /// Image width in pixels.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = 480)]
        height: u32,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    shapewright_xr::sdf_store::DirStore::install_default();
    let result = match cli.command {
        Command::Apply { script, out } => cmd::apply(&script, &out),
        Command::Info { file } if usd_cmd::is_usd(&file) => {
            usd_cmd::info(&file).map(|text| print!("{text}"))
        }
        Command::Info { file } => cmd::info(&file),
        Command::Export {
            file,
            stl,
            obj,
            ply,
        } => usd_cmd::export(&file, stl.as_deref(), obj.as_deref(), ply.as_deref()),
        Command::Replay(args) => replay_cmd::replay(&args),
        Command::Import(args) => import_cmd::import(&args),
        Command::Run(args) => run_cmd::run(&args),
        Command::Ops { json } => {
            print!("{}", cmd::ops(json));
            Ok(())
        }
        Command::Render {
            file,
            png,
            width,
            height,
        } => render_cmd::render(&file, &png, width, height),
        Command::SessionAccess(args) => join::session_access(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shapewright-xr: {e:#}");
            ExitCode::FAILURE
        }
    }
}
