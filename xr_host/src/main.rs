//! Shapewright standalone host.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, Subcommand};

mod usd_cmd;

/// Shapewright standalone host.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Export the document of a Shapewright .usda file as STL, OBJ and/or PLY.
    Export {
        /// The .usda file.
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
    /// Print the objects, op count and validation report of a .usda file.
    Info {
        /// The .usda file.
        file: PathBuf,
    },
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Export {
            file,
            stl,
            obj,
            ply,
        } => usd_cmd::export(&file, stl.as_deref(), obj.as_deref(), ply.as_deref()),
        Command::Info { file } => {
            print!("{}", usd_cmd::info(&file)?);
            Ok(())
        }
    }
}
