//! `spectrace reference [SCENE] -o REF.exr [--time S | --spp N] [--pass-spp N] [--integrator
//! pt|bdpt|lt] [--seed N] [--threads N] [--max-depth N]`: a long progressive render that can be
//! stopped (Ctrl-C, time budget) and resumed without losing samples; the f64 sums live in
//! `REF.exr.state` (format in [`crate::analysis::reference_state`]).

use crate::analysis::{run_reference, state_path, ReferenceOutcome, ReferenceSettings};
use crate::integrator::{IntegratorKind, PathTracer};
use crate::scene::Scene;
use std::path::PathBuf;

/// Arguments of `spectrace reference`.
#[derive(clap::Args, Debug, Clone)]
pub struct ReferenceArgs {
    /// Scene file (RON). Without it the embedded measured Cornell box is rendered.
    pub scene: Option<PathBuf>,
    /// OpenEXR output; the resumable state goes beside it as OUTPUT.state.
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Stop after this many seconds in this run (the pass in flight is dropped).
    #[arg(long)]
    pub time: Option<f64>,
    /// Stop once this many samples per pixel are accumulated in total (resumed ones included).
    #[arg(long)]
    pub spp: Option<u64>,
    /// Samples per pixel per saved pass (a resumed reference keeps its own).
    #[arg(long, default_value_t = 16, value_parser = crate::limits::parse_spp)]
    pub pass_spp: u32,
    /// Light transport algorithm: pt, bdpt or lt.
    #[arg(long, default_value = "pt")]
    pub integrator: IntegratorKind,
    /// Base seed of a new reference (a resumed one keeps its own).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = crate::limits::parse_threads)]
    pub threads: Option<usize>,
    /// Maximum path depth (default: the scene's).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Plugin libraries whose types the scene may use.
    #[command(flatten)]
    pub plugins: super::plugin_args::PluginArgs,
}

/// Run `spectrace reference`: the scene loaded with the plugins named, the settings checked,
/// then the passes until the budget, Ctrl-C or the target.
pub fn run(args: &ReferenceArgs) -> Result<(), String> {
    super::output_paths::check_not_directory(&args.output, "-o")?;
    args.plugins
        .with_factory(args.scene.as_deref(), |factories| {
            let repr = Default::default();
            let scene =
                super::render::load_scene(args.scene.as_deref(), None, &[], &repr, factories)?;
            let settings = reference_settings(args, &scene)?;
            // Before the long run, not after it: a scene that renders black should not take hours.
            for w in scene.warnings() {
                eprintln!("spectrace: warning: {w}");
            }
            if settings.time.is_none() && args.spp.is_none() {
                eprintln!("spectrace: no --time or --spp: rendering until Ctrl-C");
            }
            let cancel = super::interrupt::interrupt_flag();
            let on_pass = |s: &crate::analysis::ReferenceState| {
                eprint!("\r  {} spp accumulated ({} passes)   ", s.spp(), s.passes);
            };
            let outcome = run_reference(&scene, &args.output, &settings, Some(cancel), &on_pass)
                .map_err(|e| e.to_string())?;
            eprintln!();
            print_outcome(args, &outcome);
            Ok(())
        })
}

/// The reference settings of `args` for `scene`.
fn reference_settings(args: &ReferenceArgs, scene: &Scene) -> Result<ReferenceSettings, String> {
    let time = super::render::time_budget(args.time)?;
    if args.pass_spp == 0 {
        return Err("--pass-spp must be at least 1".into());
    }
    Ok(ReferenceSettings {
        pass_spp: args.pass_spp,
        seed: args.seed,
        integrator: args.integrator,
        tracer: PathTracer {
            max_depth: args.max_depth.unwrap_or(scene.options.max_depth),
            ..PathTracer::default()
        },
        threads: args.threads,
        target_spp: args.spp,
        time,
        scene_name: match &args.scene {
            Some(p) => p.display().to_string(),
            None => "default Cornell box".into(),
        },
    })
}

/// What the run added, where the state is, and a pass dropped at the time limit.
fn print_outcome(args: &ReferenceArgs, outcome: &ReferenceOutcome) {
    println!(
        "reference {}: {} spp in total ({} passes resumed, {} added{}), {:.3} M samples/s",
        args.output.display(),
        outcome.state.spp(),
        outcome.passes_resumed,
        outcome.passes_added,
        if outcome.interrupted {
            "; interrupted, the pass in flight was dropped"
        } else {
            ""
        },
        outcome.samples_per_second / 1e6
    );
    println!(
        "  state in {} (run the same command again to continue)",
        state_path(&args.output).display()
    );
    if let Some(secs) = outcome.pass_dropped_at_time_limit {
        eprintln!(
            "spectrace: warning: the time budget ran out {secs:.2} s into a pass of {} spp, which \
             was stopped and dropped{}",
            outcome.state.pass_spp,
            if outcome.passes_added == 0 {
                "; no pass fits in this budget: give more --time, or start a new reference with \
                 a smaller --pass-spp"
            } else {
                ""
            }
        );
    }
}
