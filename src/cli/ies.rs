//! `lux ies …` subcommands (owned by the lux-ies work; placeholder until it lands).

use clap::Subcommand;

/// IES file tools.
#[derive(Debug, Subcommand)]
pub enum IesCommand {
    /// Print a summary of an IES file.
    Info {
        /// The IES file.
        file: std::path::PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// Runs an `ies` subcommand; the error string is printed to stderr and the process exits non-zero.
pub fn run(cmd: &IesCommand) -> Result<(), String> {
    match cmd {
        IesCommand::Info { file, .. } => Err(format!("{}: IES support is not built yet", file.display())),
    }
}
