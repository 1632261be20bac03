//! `spectrace blob`: pack an object into a blob file, and inspect one.

use super::plugin_args::PluginArgs;
use crate::plugin::blob::{Blob, BlobLoadError};
use spectrace_plugin_api::ObjectKind;
use std::path::PathBuf;

/// The blob subcommands.
// Parsed once per run: boxing the larger variant would buy nothing.
#[allow(clippy::large_enum_variant)]
#[derive(clap::Subcommand, Debug)]
pub enum BlobCommand {
    /// Build a material, light, SPD or observer from a type name and parameters (or take one
    /// from a scene file) and save it as a self-contained blob.
    Pack {
        /// Type name (as listed by `spectrace plugins --builtins`), of kind --kind.
        #[arg(value_name = "TYPE", required_unless_present = "scene")]
        type_name: Option<String>,
        /// Kind of TYPE: light, material, spd or observer.
        #[arg(long, default_value = "light")]
        kind: String,
        /// Take the item from this scene file instead (with --light, --material, --spd,
        /// --observer or --item).
        #[arg(long, conflicts_with = "type_name")]
        scene: Option<PathBuf>,
        /// Name of a light in --scene.
        #[arg(long, requires = "scene")]
        light: Option<String>,
        /// Name of a material in --scene.
        #[arg(long, requires = "scene")]
        material: Option<String>,
        /// An SPD of --scene: `ITEM.PARAM`, e.g. `lamp.spd` or `ceiling.radiance`.
        #[arg(long, requires = "scene")]
        spd: Option<String>,
        /// The observer of --scene (its type name, e.g. `cie1931-2`).
        #[arg(long, requires = "scene")]
        observer: Option<String>,
        /// Any item of --scene as `KIND:NAME` (kind light, material, spd or observer).
        #[arg(long, requires = "scene")]
        item: Option<String>,
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

fn blob_kind(s: &str) -> Result<ObjectKind, String> {
    ObjectKind::ALL
        .into_iter()
        .find(|k| k.as_str() == s)
        .ok_or_else(|| format!("unknown kind `{s}`; blobs hold a light, material, spd or observer"))
}

/// The scene items named by `--light`, `--material`, `--spd`, `--observer` and `--item`.
fn picked_items(
    light: &Option<String>,
    material: &Option<String>,
    spd: &Option<String>,
    observer: &Option<String>,
    item: &Option<String>,
) -> Result<Vec<(ObjectKind, String)>, String> {
    let items = item
        .iter()
        .map(|it| {
            let (k, n) = it
                .split_once(':')
                .ok_or_else(|| format!("--item `{it}`: expected KIND:NAME, e.g. light:lamp"))?;
            Ok((blob_kind(k)?, n.to_string()))
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok([
        light.clone().map(|n| (ObjectKind::Light, n)),
        material.clone().map(|n| (ObjectKind::Material, n)),
        spd.clone().map(|n| (ObjectKind::Spd, n)),
        observer.clone().map(|n| (ObjectKind::Observer, n)),
    ]
    .into_iter()
    .flatten()
    .chain(items)
    .collect())
}

/// `blob pack TYPE --params ..`: a type and its parameters packed, built once first.
fn pack_type(
    registry: crate::plugin::Registry,
    kind: &str,
    type_name: &str,
    params: &str,
) -> Result<Blob, String> {
    let kind = blob_kind(kind)?;
    let value: ron::Value = ron::from_str(params).map_err(|e| format!("--params: {e}"))?;
    let factory = crate::plugin::factory::RegistryFactory::new(
        std::sync::Arc::new(registry),
        crate::plugin::adapter::PluginFaults::new(),
    );
    Blob::pack_item(&factory, kind, type_name, &value, std::path::Path::new("."))
}

/// Run a blob subcommand.
pub fn run(cmd: &BlobCommand, verbose: bool) -> Result<(), String> {
    match cmd {
        BlobCommand::Pack {
            type_name,
            kind,
            scene,
            light,
            material,
            spd,
            observer,
            item,
            params,
            output,
            plugins,
        } => {
            let registry = plugins.registry(verbose)?;
            let blob = match (scene, type_name) {
                (Some(scene), _) => {
                    let picked = picked_items(light, material, spd, observer, item)?;
                    let [(kind, name)] = picked.as_slice() else {
                        return Err(
                            "with --scene give exactly one of --light, --material, --spd, --observer or --item"
                                .into(),
                        );
                    };
                    Blob::pack_scene_item(&registry, scene, *kind, name)?
                }
                (None, Some(type_name)) => pack_type(registry, kind, type_name, params)?,
                _ => return Err("give a TYPE, or --scene FILE with the item to pack".into()),
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
