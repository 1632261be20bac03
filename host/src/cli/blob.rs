//! `spectrace blob`: pack an object into a blob file, and inspect one.

use super::plugin_args::PluginArgs;
use crate::plugin::blob::{Blob, BlobLoadError};
use std::path::PathBuf;

/// The blob subcommands.
#[derive(clap::Subcommand, Debug)]
pub enum BlobCommand {
    /// Build a light from a type name and parameters and save it as a blob.
    Pack {
        /// Light type name (as listed by `spectrace plugins`).
        #[arg(value_name = "TYPE")]
        type_name: String,
        /// Parameters in scene (RON) syntax, e.g. `(position: (0, 1, 0), power_w: 100)`.
        #[arg(long, default_value = "()")]
        params: String,
        /// Output file.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        /// Plugins to load.
        plugins: PluginArgs,
    },
    /// Print a blob's header and, when its plugin is loaded, its decoded parameters.
    Inspect {
        /// Blob file.
        file: PathBuf,
        #[command(flatten)]
        /// Plugins to load.
        plugins: PluginArgs,
    },
}

/// Run a blob subcommand.
pub fn run(cmd: &BlobCommand, verbose: bool) -> Result<(), String> {
    match cmd {
        BlobCommand::Pack {
            type_name,
            params,
            output,
            plugins,
        } => {
            let registry = plugins.registry(verbose)?;
            let blob = Blob::pack_plugin_light(&registry, type_name, params)
                .map_err(|e| e.to_string())?;
            blob.write_file(output).map_err(|e| e.to_string())?;
            println!("{}", blob.header_text());
            println!("written to {}", output.display());
            Ok(())
        }
        BlobCommand::Inspect { file, plugins } => {
            let registry = plugins.registry(verbose)?;
            let blob = Blob::read_file(file).map_err(|e| e.to_string())?;
            println!("{}", blob.header_text());
            match blob.describe(&registry) {
                Ok(params) => {
                    println!("parameters:\n{params}");
                    Ok(())
                }
                Err(e @ BlobLoadError::MissingPlugin { .. }) => {
                    println!("parameters: not decoded: {e}");
                    Ok(())
                }
                Err(e) => Err(format!("{}: {e}", file.display())),
            }
        }
    }
}
