//! `shapewright-xr`: the standalone Shapewright host.
//!
//! Today it is the command line that replays op scripts and inspects
//! meshes; the OpenXR headset session joins it later.

mod cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Shapewright standalone host.
#[derive(Parser)]
#[command(name = "shapewright-xr", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replay an op script (.jsonl) and export the result (.stl, .obj, .ply).
    Apply {
        /// The script: one JSON op per line.
        script: PathBuf,
        /// Output file; the format follows the extension.
        #[arg(long)]
        out: PathBuf,
    },
    /// Print the validation report of a mesh file (.stl, .obj).
    Info {
        /// The mesh file.
        file: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Apply { script, out } => cmd::apply(&script, &out),
        Command::Info { file } => cmd::info(&file),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shapewright-xr: {e:#}");
            ExitCode::FAILURE
        }
    }
}
