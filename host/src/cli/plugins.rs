//! `spectrace plugins`: what can be built, and who provides it.

use super::plugin_args::PluginArgs;
use crate::plugin::registry::Provider;
use spectrace_plugin_api::abi::std_types::ROption;

/// Arguments of `spectrace plugins`.
#[derive(clap::Args, Debug)]
pub struct PluginsArgs {
    #[command(flatten)]
    /// Libraries and directories to load.
    pub plugins: PluginArgs,
    /// Also list the built-in types.
    #[arg(long)]
    pub builtins: bool,
}

/// List each loaded plugin with its version, API version and types (with parameters).
pub fn run(args: &PluginsArgs, verbose: bool) -> Result<(), String> {
    let registry = args.plugins.registry(verbose)?;
    if registry.plugins().is_empty() {
        println!(
            "no plugins loaded (use --plugin PATH or --dir DIR, or set SPECTRACE_PLUGIN_PATH)"
        );
    }
    for p in registry.plugins() {
        println!(
            "{} {}  (API {}, {})",
            p.info.name,
            p.info.version,
            p.info.api_version,
            p.path.display()
        );
        for t in p.info.types.iter() {
            println!(
                "  {} `{}` v{}: {}",
                t.kind, t.name, t.version, t.description
            );
            for q in t.params.iter() {
                let unit = if q.unit.is_empty() {
                    String::new()
                } else {
                    format!(" [{}]", q.unit)
                };
                let default = match &q.default {
                    ROption::RSome(d) => format!(" = {d}"),
                    ROption::RNone => " (required)".to_string(),
                };
                println!("      {}{unit}{default}: {}", q.name, q.description);
            }
        }
    }
    if args.builtins {
        println!("built-in types:");
        for t in registry
            .types()
            .filter(|t| matches!(t.provider, Provider::Builtin))
        {
            println!(
                "  {} `{}`: {}",
                t.info.kind, t.info.name, t.info.description
            );
        }
    }
    Ok(())
}
