//! `spectrace blob`: pack an object into a blob file, and inspect one.

use super::plugin_args::PluginArgs;
use crate::plugin::blob::{Blob, BlobLoadError};
use std::path::PathBuf;

/// The blob subcommands.
#[derive(clap::Subcommand, Debug)]
pub enum BlobCommand {
    /// Build a light from a type name and parameters (or take one from a scene file) and save
    /// it as a blob.
    Pack {
        /// Light type name (as listed by `spectrace plugins --builtins`).
        #[arg(value_name = "TYPE", required_unless_present = "scene")]
        type_name: Option<String>,
        /// Take the light from this scene file instead (with --light).
        #[arg(long, requires = "light", conflicts_with = "type_name")]
        scene: Option<PathBuf>,
        /// Name of the light in --scene.
        #[arg(long)]
        light: Option<String>,
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
            scene,
            light,
            params,
            output,
            plugins,
        } => {
            let registry = plugins.registry(verbose)?;
            let blob = match (scene, light, type_name) {
                (Some(scene), Some(light), _) => Blob::pack_scene_light(&registry, scene, light)?,
                (_, _, Some(type_name)) => {
                    match registry.plugin_for(spectrace_plugin_api::ObjectKind::Light, type_name) {
                        Ok(Some(_)) => Blob::pack_plugin_light(&registry, type_name, params)
                            .map_err(|e| e.to_string())?,
                        Ok(None) => {
                            let value: ron::Value =
                                ron::from_str(params).map_err(|e| format!("--params: {e}"))?;
                            Blob::pack_builtin_light(type_name, &value)?
                        }
                        Err(e) => return Err(e.to_string()),
                    }
                }
                _ => return Err("give a light TYPE, or --scene FILE --light NAME".into()),
            };
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
