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
use shapewright::doc::PrintScale;

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
    /// Replay an op script (.jsonl) and export the result (.stl or .3mf in
    /// millimetres for slicers, .obj or .ply in metres, as the printable
    /// union; .usda or .usdz with the whole op log).
    Apply {
        /// The script: one JSON op per line.
        script: PathBuf,
        /// Output file; the format follows the extension (.stl, .3mf, .obj,
        /// .ply, .usda, .usdz; .usdc is refused: use .usda).
        #[arg(long)]
        out: PathBuf,
    },
    /// Replay a recorded input trace (.trace.jsonl) through the interaction
    /// core, write any of --out/--stl/--png and print a summary.
    Replay(replay_cmd::ReplayArgs),
    /// Print the validation report of a mesh file (.stl, .3mf, .obj, .ply,
    /// read at its unit: size in mm, volume in cm³, bed fit), or the
    /// objects, op count, reports, printed size and bed fit of a
    /// Shapewright USD file.
    Info {
        /// The mesh or USD file.
        file: PathBuf,
    },
    /// Export the document of a Shapewright USD file as STL, 3MF, OBJ and/or PLY.
    Export {
        /// The .usda/.usdc/.usdz file.
        file: PathBuf,
        /// Write binary STL (millimetres) here.
        #[arg(long)]
        stl: Option<PathBuf>,
        /// Write 3MF (millimetres, one named object per piece) here.
        #[arg(long = "3mf")]
        three_mf: Option<PathBuf>,
        /// Write OBJ (metres) here.
        #[arg(long)]
        obj: Option<PathBuf>,
        /// Write PLY (metres) here.
        #[arg(long)]
        ply: Option<PathBuf>,
        /// Print at this uniform scale (0.5: half size); walls of
        /// thickened surfaces keep their thickness.
        #[arg(long, conflicts_with = "scale_to_fit")]
        scale: Option<f64>,
        /// Scale the model down to fit the document's printer (set_printer;
        /// Prusa MK4 by default), as far as needed and no further; a model
        /// that fits is written at true size.
        #[arg(long)]
        scale_to_fit: bool,
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
    /// Render a mesh file (.stl, .3mf, .obj, .ply) to a PNG with the host's Vulkan renderer.
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

/// Exit status of a tool whose reader went away: 128 + SIGPIPE, what a
/// shell shows for a tool the signal ended (`yes | head` under pipefail).
const CLOSED_PIPE_EXIT: i32 = 141;

/// A reader that goes away (`shapewright-xr ops --json | head`) closes the
/// pipe: Rust ignores SIGPIPE, so the next `print!` fails with EPIPE and
/// std panics ("failed printing to stdout: Broken pipe"). A command-line
/// tool ends quietly instead: this hook, for exactly that panic (stdout or
/// stderr, EPIPE on Unix, ERROR_NO_DATA / ERROR_BROKEN_PIPE on Windows),
/// exits with [`CLOSED_PIPE_EXIT`] before any message is printed; every
/// other panic goes to the default hook. One hook covers every subcommand
/// and needs no unsafe code (resetting SIGPIPE to its default would).
fn quiet_on_closed_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let msg = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        let printing = msg.starts_with("failed printing to stdout")
            || msg.starts_with("failed printing to stderr");
        let closed = ["os error 32)", "os error 232)", "os error 109)"]
            .iter()
            .any(|code| msg.ends_with(code));
        if printing && closed {
            std::process::exit(CLOSED_PIPE_EXIT);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    quiet_on_closed_pipe();
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
            three_mf,
            obj,
            ply,
            scale,
            scale_to_fit,
        } => {
            let targets: Vec<&std::path::Path> = [&stl, &three_mf, &obj, &ply]
                .into_iter()
                .filter_map(|p| p.as_deref())
                .collect();
            let scale = match (scale, scale_to_fit) {
                (_, true) => PrintScale::ToFit,
                (Some(s), false) => PrintScale::By(s),
                (None, false) => PrintScale::By(1.0),
            };
            usd_cmd::export(&file, &targets, scale)
        }
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
