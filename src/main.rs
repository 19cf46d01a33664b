//! The `lux` command line: `lux render`, `lux info`, `lux ies …`.
//! With no arguments it renders the bundled demo scene.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(name = "lux", version, about = "UsdLux lighting, exactly")]
struct Args {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// IES (LM-63) photometric file tools.
    #[command(subcommand)]
    Ies(cli::ies::IesCommand),
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result = match &args.command {
        Some(Command::Ies(cmd)) => cli::ies::run(cmd),
        None => Ok(()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("lux: {msg}");
            ExitCode::FAILURE
        }
    }
}
