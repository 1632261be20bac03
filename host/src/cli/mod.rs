//! Command-line subcommands; each lives in its own file and `main.rs` only dispatches.

use clap::{Parser, Subcommand};
use std::ffi::OsString;

/// spectrace: a spectral bidirectional path tracer and plugin host.
#[derive(Parser, Debug)]
#[command(name = "spectrace", version, about)]
pub struct Cli {
    /// Print full diagnostics (for example the whole ABI layout report of a refused plugin).
    #[arg(long, global = true)]
    pub verbose: bool,
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {}

/// Parse `args`, run the chosen subcommand and return the process exit code.
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return e.exit_code();
        }
    };
    match cli.command {
        None => {
            eprintln!("spectrace: no subcommand given; try `spectrace --help`");
            2
        }
        Some(command) => match command {},
    }
}
