//! `spectrace plugins check LIB [--type NAME] [--params RON] [--json]`: load a plugin library
//! through the normal loader and run the conformance kit (`spectrace-plugin-kit`, the very
//! checks a plugin author runs in `cargo test`) on its types, printing one table per type (or
//! JSON). The exit status is non-zero when a check fails.

use crate::plugin::services::HostServices;
use std::path::PathBuf;

/// Arguments of `spectrace plugins check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The plugin library to check.
    pub library: PathBuf,
    /// Check only the type of this name.
    #[arg(long = "type", value_name = "NAME")]
    pub type_name: Option<String>,
    /// Build the type from these parameters, in scene (RON) syntax, e.g. `(power_w: 10)`;
    /// without it each type is built from `()` (its defaults).
    #[arg(long, value_name = "RON", requires = "type_name")]
    pub params: Option<String>,
    /// Print the reports as JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// Run the checks; an error (exit status 1) when the library cannot be loaded or a check fails.
pub fn run(args: &CheckArgs, verbose: bool) -> Result<(), String> {
    // Only the types no plugin can provide, so that a library providing the standard names
    // loads too; the library's SPD specs are resolved by the host's spectrum module.
    let mut registry = crate::plugin::core_registry();
    registry.load_plugin(&args.library).map_err(|e| {
        if verbose {
            e.verbose()
        } else {
            e.to_string()
        }
    })?;
    let plugin = registry
        .plugins()
        .last()
        .cloned()
        .ok_or_else(|| format!("{}: no plugin was loaded", args.library.display()))?;
    let services = HostServices::new(&registry);
    let options = spectrace_plugin_kit::Options {
        type_name: args.type_name.clone(),
        params: args.params.clone(),
    };
    let reports = spectrace_plugin_kit::check_module_with_host(plugin.module, &options, &services)
        .map_err(|e| format!("{}: {e}", args.library.display()))?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&reports).map_err(|e| e.to_string())?
        );
    } else {
        println!(
            "{} {} ({})",
            plugin.info.name,
            plugin.info.version,
            plugin.path.display()
        );
        for r in &reports {
            print!("{r}");
        }
    }
    let failed: Vec<String> = reports
        .iter()
        .flat_map(|r| {
            r.failures()
                .into_iter()
                .map(move |c| format!("{} `{}`: {c}", r.kind, r.type_name))
        })
        .collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}: {} check(s) failed: {}",
            args.library.display(),
            failed.len(),
            failed.join(", ")
        ))
    }
}
