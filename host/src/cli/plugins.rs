//! `spectrace plugins`: what can be built, and who provides it.

use super::plugin_args::PluginArgs;
use crate::plugin::reference::{
    builtins_text, params_text, scene_format_markdown, write_scene_format_pages,
};
use crate::scene_file::TypeDoc;

/// Arguments of `spectrace plugins`.
#[derive(clap::Args, Debug)]
pub struct PluginsArgs {
    /// `check`: run the conformance kit on a library; `new`: write a plugin crate to start from.
    #[command(subcommand)]
    pub action: Option<PluginsAction>,
    #[command(flatten)]
    /// Libraries and directories to load.
    pub plugins: PluginArgs,
    /// Also list the built-in types with their parameter tables.
    #[arg(long)]
    pub builtins: bool,
    /// Print the scene-format reference (docs/scene-format.md and docs/scene-format/*.md, one
    /// page after another) as Markdown instead.
    #[arg(long, requires = "builtins")]
    pub markdown: bool,
    /// Write the scene-format reference pages into DIR (DIR/scene-format.md and
    /// DIR/scene-format/KIND.md) instead: `--markdown-dir docs` regenerates the docs.
    #[arg(
        long,
        value_name = "DIR",
        requires = "builtins",
        conflicts_with = "markdown"
    )]
    pub markdown_dir: Option<std::path::PathBuf>,
}

/// What `spectrace plugins` can do besides listing.
#[derive(clap::Subcommand, Debug)]
pub enum PluginsAction {
    /// Run the conformance kit on the types of a plugin library (exit status 1 when a check fails).
    Check(super::plugins_check::CheckArgs),
    /// Write a new plugin crate (light, material, SPD or observer) with a conformance test.
    New(super::plugins_new::NewArgs),
}

/// List each loaded plugin with its version, API version and types (with parameters).
pub fn run(args: &PluginsArgs, verbose: bool) -> Result<(), String> {
    match &args.action {
        Some(PluginsAction::Check(a)) => return super::plugins_check::run(a, verbose),
        Some(PluginsAction::New(a)) => return super::plugins_new::run(a),
        None => {}
    }
    let registry = args.plugins.registry(verbose)?;
    if args.markdown {
        println!("{}", scene_format_markdown(&registry));
        return Ok(());
    }
    if let Some(dir) = &args.markdown_dir {
        for path in write_scene_format_pages(&registry, dir)? {
            println!("wrote {}", path.display());
        }
        return Ok(());
    }
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
        if let Some(sha) = &p.sha256 {
            println!("  sha256 {sha}");
        }
        for t in p.info.types.iter() {
            println!(
                "  {} `{}` v{}: {}",
                t.kind, t.name, t.version, t.description
            );
            print!("{}", params_text(&TypeDoc::from(t)));
        }
    }
    if args.builtins {
        print!("{}", builtins_text(&registry));
    }
    Ok(())
}
