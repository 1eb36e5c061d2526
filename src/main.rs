//! The `pdcontact` command line: a thin shell over the library.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pdcontact::case::{CaseOptions, DEFAULT_HORIZON_FACTOR};
use pdcontact::importers::{Format, MeshSummary};
use pdcontact::Error;

/// Peridynamic point-to-surface contact from finite-element meshes.
#[derive(Parser, Debug)]
#[command(name = "pdcontact", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Summarise a mesh file (ANSYS CDB, Gmsh MSH, Abaqus INP).
    Inspect {
        /// The mesh file.
        file: PathBuf,
        /// Force the format instead of guessing it: cdb, msh or inp.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Turn a mesh into a PD case folder (particles, surface, master segments, scene skeleton).
    Convert {
        /// The mesh file.
        mesh: PathBuf,
        /// Output folder.
        #[arg(short, long)]
        output: PathBuf,
        /// Grid spacing Δ (default: the median element edge).
        #[arg(long)]
        spacing: Option<f64>,
        /// Horizon factor m (δ = m·Δ).
        #[arg(long, default_value_t = DEFAULT_HORIZON_FACTOR)]
        horizon_factor: f64,
        /// Force the mesh format: cdb, msh or inp.
        #[arg(long, value_parser = parse_format)]
        format: Option<Format>,
        /// Print the summary as JSON on stdout.
        #[arg(long)]
        json: bool,
    },
}

fn parse_format(s: &str) -> Result<Format, String> {
    Format::from_name(s).ok_or_else(|| format!("unknown format '{s}': use cdb, msh or inp"))
}

fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        Command::Inspect { file, format, json } => {
            let data = std::fs::read(&file).map_err(|e| {
                Error::Import(pdcontact::importers::ImportError::whole_file(
                    &file,
                    "a readable file",
                    e.to_string(),
                ))
            })?;
            let format = match format {
                Some(f) => f,
                None => pdcontact::importers::detect_format(&file, &data)?,
            };
            let mesh = pdcontact::importers::read_format(&file, &data, format)?;
            let summary = MeshSummary::of(&mesh, format);
            if json {
                println!("{}", to_json(&summary));
            } else {
                print!("{}", summary.to_text(&file.display().to_string()));
            }
            Ok(())
        }
        Command::Convert {
            mesh,
            output,
            spacing,
            horizon_factor,
            format,
            json,
        } => {
            let options = CaseOptions {
                spacing,
                horizon_factor,
                correction: pdcontact::correction::CorrectionMethod::Balanced,
            };
            let (_, summary) = pdcontact::convert::convert(&mesh, format, &output, options)?;
            if json {
                println!("{}", to_json(&summary));
            } else {
                print!("{}", summary.to_text());
                println!("wrote {}", output.display());
            }
            Ok(())
        }
    }
}

fn to_json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
