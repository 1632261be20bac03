//! `spectrace explain [SCENE] [--plugin …]`: every optical effect the scene calls for, the
//! objects and lights that call for it, what the render will do about it and what it will
//! skip (see [`crate::effects`]), then the render plan `render` would use with the same
//! `--effects`/`--effect` arguments. Without SCENE: the built-in Cornell box.

use crate::integrator::{EffectsRequest, RenderPlan};
use crate::scene::{default_scene_with, load_scene_file_with, BuiltinFactory};
use crate::scene_file::RepresentationOptions;
use std::path::PathBuf;

/// Arguments of `spectrace explain`.
#[derive(clap::Args, Debug)]
pub struct ExplainArgs {
    /// Scene file (RON); the measured Cornell box when absent.
    pub scene: Option<PathBuf>,
    /// Plugin libraries whose types the scene may use.
    #[command(flatten)]
    pub plugins: super::plugin_args::PluginArgs,
    /// The render plan for `--effects auto` (default) or `all`, as `render` would make it.
    #[arg(long, value_enum, default_value = "auto")]
    pub effects: crate::integrator::EffectsMode,
    /// Force one effect on or off, NAME=on|off (repeatable), as for `render`.
    #[arg(long = "effect", value_name = "NAME=on|off")]
    pub effect: Vec<String>,
}

/// Run `spectrace explain`.
pub fn run(args: &ExplainArgs) -> Result<(), String> {
    let registry = std::sync::Arc::new(args.plugins.registry(false)?);
    let faults = crate::plugin::adapter::PluginFaults::new();
    let plugins = crate::plugin::factory::PluginFactory::new(registry, faults);
    let repr = RepresentationOptions::default();
    let (scene, name) = match &args.scene {
        Some(p) => (
            load_scene_file_with(p, &[&BuiltinFactory, &plugins], &repr),
            p.display().to_string(),
        ),
        None => (default_scene_with(&repr), "Cornell box".to_string()),
    };
    let scene = scene.map_err(|e| e.to_string())?;
    let request = EffectsRequest::parse(args.effects, &args.effect)?;
    let plan = RenderPlan::new(&scene, &request);
    let effects = plan.effects();
    println!(
        "{name}: {} objects, {} lights",
        scene.objects.len(),
        scene.lights.lights().len()
    );
    println!("{}", effects.summary_line());
    print!("{}", effects.report());
    print!("{}", plan.report());
    for w in scene.warnings() {
        println!("warning: {w}");
    }
    Ok(())
}
