//! The plugin options shared by every subcommand that builds objects.

use crate::plugin::Registry;
use crate::scene_file::ObjectFactory;
use std::path::PathBuf;

/// Which plugin libraries to load.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct PluginArgs {
    /// Load this plugin library (repeatable).
    #[arg(long = "plugin", value_name = "PATH")]
    pub libraries: Vec<PathBuf>,
    /// Load every plugin library in this directory (repeatable). The directories listed in the
    /// SPECTRACE_PLUGIN_PATH environment variable (separated like PATH) are loaded too.
    #[arg(long = "plugins", visible_alias = "dir", value_name = "DIR")]
    pub directories: Vec<PathBuf>,
    /// Leave the built-in materials, lights, SPDs and observers out of the registry, so that a
    /// library providing them under the same names (the standard set, `plugins/standard`) is
    /// used instead. Shapes, cameras and `blob` stay built in.
    #[arg(long)]
    pub no_builtins: bool,
    /// Types of the libraries given with --plugin replace the built-in types of the same name
    /// (and their aliases) instead of being refused as a clash: the standard set
    /// (`plugins/standard`) then provides what it exports and the built-ins the rest.
    #[arg(long, conflicts_with = "no_builtins")]
    pub replace_builtins: bool,
}

impl PluginArgs {
    /// Runs `f` with the one factory that builds every type, built-in, plugin or blob, from
    /// the registry of these arguments; then says which plugin calls failed or returned unusable
    /// values (they contributed nothing), once per call site or reason, with counts. The
    /// libraries the scene file lists (`plugins: [...]`, pinned ones checked) join the registry.
    pub fn with_factory<T>(
        &self,
        scene: Option<&std::path::Path>,
        f: impl FnOnce(&[&dyn ObjectFactory]) -> Result<T, String>,
    ) -> Result<T, String> {
        let mut registry = self.registry(false)?;
        if let Some(scene) = scene {
            registry.load_scene_plugins(scene)?;
        }
        let registry = std::sync::Arc::new(registry);
        let faults = crate::plugin::adapter::PluginFaults::new();
        let plugins = crate::plugin::factory::PluginFactory::new(registry, faults.clone());
        let result = f(&[&plugins])?;
        for line in faults.outcome()? {
            println!("  warning: plugin {line}");
        }
        Ok(result)
    }

    /// A registry with the built-in types (unless `--no-builtins`) and the requested plugins. A library that cannot be
    /// loaded is an error (the user named it); in a directory, bad libraries are reported as
    /// warnings and the good ones still load.
    pub fn registry(&self, verbose: bool) -> Result<Registry, String> {
        let mut registry = if self.no_builtins {
            crate::plugin::core_registry()
        } else {
            crate::plugin::builtin_registry()
        };
        let mut dirs = self.directories.clone();
        if let Some(paths) = std::env::var_os("SPECTRACE_PLUGIN_PATH") {
            dirs.extend(std::env::split_paths(&paths).filter(|p| !p.as_os_str().is_empty()));
        }
        for dir in &dirs {
            for e in registry.load_plugin_dir(dir) {
                eprintln!(
                    "spectrace: warning: {}",
                    if verbose { e.verbose() } else { e.to_string() }
                );
            }
        }
        for lib in &self.libraries {
            if self.replace_builtins {
                registry.load_plugin_replacing_builtins(lib)
            } else {
                registry.load_plugin(lib)
            }
            .map_err(|e| if verbose { e.verbose() } else { e.to_string() })?;
        }
        Ok(registry)
    }
}
