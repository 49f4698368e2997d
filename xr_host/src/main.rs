//! `shapewright-xr`: the standalone Shapewright host.
//!
//! Today it is the command line that replays op scripts and inspects
//! meshes; the OpenXR headset session joins it later.

mod cmd;
mod render_cmd;
mod run_cmd;

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
    /// Run the OpenXR session (headset with Vulkan; `--headless`: input only, XR_MND_headless).
    Run(run_cmd::RunArgs),
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
    let result = match cli.command {
        Command::Apply { script, out } => cmd::apply(&script, &out),
        Command::Info { file } => cmd::info(&file),
        Command::Run(args) => run_cmd::run(&args),
        Command::Render {
            file,
            png,
            width,
            height,
        } => render_cmd::render(&file, &png, width, height),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shapewright-xr: {e:#}");
            ExitCode::FAILURE
        }
    }
}
