//! `spectrace render [SCENE] [-o FILE.exr] [--png FILE.png] [--spp N | --time SECONDS] [--seed N]
//! [--threads N] [--camera NAME] [--slice K/M] [--state FILE] [--resume FILE]
//! [--diagnostic-layer] [--spectral-exr S.exr [--bins START:END:STEP]]`: render a scene file, or the embedded measured Cornell box when no scene
//! is given, with a progress bar and a summary.
//!
//! Slices and checkpoints (see `docs/distributed.md`): `--slice K/M` renders only the sample
//! indices `⌊(K−1)·N/M⌋..⌊K·N/M⌋` of every pixel and writes the exact film to a state file
//! (no image) for `spectrace merge`. Ctrl-C or SIGTERM during a sample-count render writes the
//! image of the whole passes done and the same kind of state file; `--resume FILE` continues it
//! to the image an uninterrupted run would have made, bit for bit.
//!
//! The command is a pipeline of steps, each in a file of its own:
//! 1. [`args`]: the flags ([`RenderArgs`]), the command line stored for `--resume`, the
//!    settings key;
//! 2. [`job`]: the arguments checked and turned into a [`RenderJob`] (resumed state, scene,
//!    render plan, sample budget and range, fingerprint, integrator settings);
//! 3. [`scene`]: the scene loaded (with `--resolution` applied);
//! 4. [`run`]: the render (fresh, resumed or a slice) into one film, and the state file of a
//!    slice or an unfinished render;
//! 5. [`summary`] and [`output`]: the summary printed and the files written.
//!
//! `merge` uses the same output step ([`save_image`], [`spectral_summary`]); `bench` the scene
//! step ([`load_scene`]) and the default settings ([`default_settings`]).

mod args;
mod job;
mod output;
mod run;
mod scene;
mod summary;

pub use args::{parse_ev, parse_resolution, time_budget, RenderArgs};
pub use job::{default_settings, RenderJob};
pub use output::{diagnostic_layers, save_image, spectral_summary};
pub use scene::{load, load_scene};

use crate::integrator::IntegratorOutput;
use crate::scene_file::ObjectFactory;
use run::{Progress, Rendered};

/// Run `spectrace render` with the built-in types and the plugins named in `args`.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    args.plugins
        .with_factory(args.scene.as_deref(), |factories| {
            run_with_factories(args, factories)
        })
}

/// Run `spectrace render`, building scene items with `factories` (the registry's factory, or
/// [`crate::scene::BuiltinFactory`] alone): arguments → job → render → state file, or outputs
/// and summary.
pub fn run_with_factories(
    args: &RenderArgs,
    factories: &[&dyn ObjectFactory],
) -> Result<(), String> {
    let mut job = RenderJob::new(args, factories)?;
    let progress = Progress::new(&job.args);
    let mut rendered = run::render(&mut job, &progress)?;
    if run::ends_in_state(&job, &rendered) {
        return run::write_state(&job, rendered, &progress.bar);
    }
    // The image comes from the whole film (resumed part included).
    let Some(mut output) = rendered.output.take() else {
        return write_completed(&job, &rendered);
    };
    output.result.image = rendered.film.image();
    if let Some(r) = &job.range {
        output.result.spp = job.first_sample + rendered.new_spp - r.start;
    }
    progress.bar.finish_and_clear();
    finish(&job, &output, &rendered, progress.stopped())
}

/// A resumed render whose state already held every sample: its outputs only.
fn write_completed(job: &RenderJob, rendered: &Rendered) -> Result<(), String> {
    let (args, film) = (&job.args, &rendered.film);
    let image = film.image();
    for wr in output::save(
        &image,
        &job.outputs,
        &job.scene,
        output::extra_layers(args, film),
        args,
    )? {
        println!("  wrote {}", wr.display());
    }
    if let Some((_, line)) = output::write_spectral(args, film, &image, &job.scene)? {
        println!("{line}");
    }
    Ok(())
}

/// The end of a finished (or time-budget) render: the summary, the outputs, the sensors.
fn finish(
    job: &RenderJob,
    output: &IntegratorOutput,
    rendered: &Rendered,
    stopped: bool,
) -> Result<(), String> {
    let (args, scene, film, result) = (&job.args, &job.scene, &rendered.film, &output.result);
    summary::print_setup(job);
    if let Some(dir) = &args.strategy_images {
        for w in crate::integrator::select::write_strategy_images(dir, output, scene)? {
            println!("  wrote {}", w.display());
        }
    }
    let layers = output::extra_layers(args, film);
    let written = output::save(&result.image, &job.outputs, scene, layers, args)?;
    let exposure_note = output::png_exposure(args, scene, &result.image).1;
    if let Some((_, line)) = output::write_spectral(args, film, &result.image, scene)? {
        println!("{line}");
    }
    summary::print_totals(job, result);
    for n in &output.notes {
        println!("  {n}");
    }
    summary::print_warnings(job, result, film);
    for w in written {
        println!("  wrote {}", w.display());
    }
    if let Some(note) = exposure_note {
        println!("  {note}");
    }
    if scene.options.length_unit != crate::scene_file::LengthUnit::Metre {
        println!(
            "  scene units: {} (lengths converted to metres when the scene was built)",
            scene.options.length_unit
        );
    }
    if let Some(path) = &args.luminance_out {
        super::sensors::write_luminance(scene, &result.image, path)?;
    }
    if !stopped {
        let spp = job.total_spp.unwrap_or(scene.options.spp);
        let sensors_out = args.sensors_out.as_deref();
        super::sensors::measure_sensors(scene, &job.settings, args.integrator, spp, sensors_out)?;
    }
    for w in scene.warnings() {
        println!("  warning: {w}");
    }
    if stopped && job.range.is_none() {
        return Err(format!(
            "interrupted: the image holds the {} spp rendered before the stop (a time budget \
             has no checkpoint; render with --spp to be able to resume)",
            result.spp
        ));
    }
    Ok(())
}
