//! Command-line subcommands; each lives in its own file and `main.rs` only dispatches.

pub mod bench;
pub mod bench_effects;
pub mod bench_speed;
pub mod blob;
pub mod color;
pub mod compare;
pub mod convert;
pub mod explain;
pub mod gldf;
pub mod interrupt;
pub mod luminaire;
pub mod merge;
pub mod output_paths;
pub mod plugin_args;
pub mod plugins;
pub mod plugins_check;
pub mod plugins_new;
pub mod rays;
pub mod reference;
pub mod render;
pub mod representation_args;
pub mod sensors;
pub mod sensors_glare;

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
// Parsed once per process: the size of the `render` variant (its many flags) does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand, Debug)]
pub enum Command {
    /// List plugin libraries with their versions, API versions and types.
    Plugins(plugins::PluginsArgs),
    /// Pack and inspect serialized objects (blobs).
    #[command(subcommand)]
    Blob(blob::BlobCommand),
    /// Colour of a spectrum: XYZ, chromaticity and linear sRGB.
    Color(color::ColorArgs),
    /// A measured luminaire (IES LM-63, EULUMDAT): header, flux in lm, candela at angles.
    Luminaire(luminaire::LuminaireArgs),
    /// IES TM-25 ray files: `rays info FILE`, `rays export SCENE --light NAME -N COUNT -o OUT`.
    #[command(subcommand)]
    Rays(rays::RaysCommand),
    /// Render a scene (default: the measured spectral Cornell box) to OpenEXR and PNG.
    Render(render::RenderArgs),
    /// Convert a Mitsuba 3 XML scene to a spectrace RON scene, listing what changed or was dropped.
    Convert(convert::ConvertArgs),
    /// Merge the state files of a render's slices (`render --slice K/M`) into its image.
    Merge(merge::MergeArgs),
    /// Error of a render against a reference: RMSE, relative MSE, CIEDE2000, difference image.
    Compare(compare::CompareArgs),
    /// Long progressive reference render that can be stopped (Ctrl-C, --time) and resumed.
    Reference(reference::ReferenceArgs),
    /// Optical effects the scene calls for, who calls for them, and what the render does.
    Explain(explain::ExplainArgs),
    /// Benchmarks; `bench accuracy`: error versus time of renderer configurations; `bench speed`:
    /// equal-time efficiency against Mitsuba 3 and LuxCore; `bench effects`: the cost of each
    /// effect on or off.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Internal: open one plugin library and report (run by the loader in a child process).
    #[command(name = "probe-plugin", hide = true)]
    ProbePlugin {
        /// The library file.
        file: std::path::PathBuf,
    },
}

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
    let verbose = cli.verbose;
    let result: Result<(), String> = match cli.command {
        None => {
            eprintln!(
                "spectrace: no subcommand given; try `spectrace render` or `spectrace --help`"
            );
            return 2;
        }
        Some(Command::Plugins(args)) => plugins::run(&args, verbose),
        Some(Command::Blob(cmd)) => blob::run(&cmd, verbose),
        Some(Command::Color(args)) => color::run(&args),
        Some(Command::Luminaire(args)) => luminaire::run(&args),
        Some(Command::Rays(cmd)) => rays::run(&cmd),
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Merge(args)) => merge::run(&args),
        Some(Command::Convert(args)) => convert::run(&args),
        Some(Command::Compare(args)) => compare::run(&args),
        Some(Command::Reference(args)) => reference::run(&args),
        Some(Command::Bench(cmd)) => bench::run(&cmd),
        Some(Command::Explain(args)) => explain::run(&args),
        Some(Command::ProbePlugin { file }) => return crate::plugin::loader::probe_main(&file),
    };
    match result {
        Ok(()) => 0,
        Err(message) => {
            eprintln!("spectrace: {message}");
            1
        }
    }
}
