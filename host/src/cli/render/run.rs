//! The render itself (step 4 of the pipeline in [`super`]): fresh, resumed or a slice, with a
//! progress bar and the stop flag that Ctrl-C, SIGTERM and the testing hooks set; and, for a
//! slice or an unfinished render, the state file that `merge` and `--resume` read.

use super::args::absolute;
use super::job::RenderJob;
use super::output::{extra_layers, save, write_spectral};
use super::RenderArgs;
use crate::film::{FilmState, RenderState, SliceSpec};
use crate::integrator::{IntegratorOptions, IntegratorOutput};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The progress bar and the stop flag of one render.
pub struct Progress {
    /// The bar (hidden with `--quiet`).
    pub bar: indicatif::ProgressBar,
    /// Set by Ctrl-C or SIGTERM.
    interrupt: &'static AtomicBool,
    /// Tells the integrator to stop after the tiles in flight.
    stop: AtomicBool,
    /// The `--wait-for-signal-after-units` hook has waited once.
    waited: AtomicBool,
    wait_after: Option<u64>,
    stop_after: Option<u64>,
}

impl Progress {
    /// The bar and flags for `args` (Ctrl-C/SIGTERM or the testing hooks stop the render
    /// through one flag).
    pub fn new(args: &RenderArgs) -> Self {
        let bar = if args.quiet {
            indicatif::ProgressBar::hidden()
        } else {
            let b = indicatif::ProgressBar::new(1);
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] [{bar:40}] {percent:>3}% tiles, eta {eta}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            b
        };
        Self {
            bar,
            interrupt: crate::cli::interrupt::interrupt_flag(),
            stop: AtomicBool::new(false),
            waited: AtomicBool::new(false),
            wait_after: args.wait_for_signal_after_units,
            stop_after: args.stop_after_units,
        }
    }

    /// The integrator's progress callback: `done` of `total` units.
    fn update(&self, done: u64, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(done);
        if self.wait_after.is_some_and(|k| done >= k) && !self.waited.swap(true, Ordering::SeqCst) {
            eprintln!("waiting for a signal");
            let t = Instant::now();
            while !self.interrupt.load(Ordering::SeqCst) && t.elapsed() < Duration::from_secs(60) {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        if self.interrupt.load(Ordering::Relaxed) || self.stop_after.is_some_and(|k| done >= k) {
            self.stop.store(true, Ordering::Relaxed);
        }
    }

    /// True when the render was told to stop.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// What a render made: the integrator's output (none when the resumed state was already
/// complete), the whole film (the resumed state's plus this run's: exact, so the same bits as
/// one run) and the samples per pixel rendered now.
pub struct Rendered {
    pub output: Option<IntegratorOutput>,
    pub film: FilmState,
    pub new_spp: u32,
}

/// Renders the job's samples and merges them into the resumed film.
pub fn render(job: &mut RenderJob, progress: &Progress) -> Result<Rendered, String> {
    let mut output = if job.already_done() {
        None
    } else {
        Some(
            crate::integrator::select::render_planned_with_options(
                &job.scene,
                &job.plan,
                &job.settings,
                job.args.integrator,
                IntegratorOptions {
                    strategy_images: job.args.strategy_images.is_some(),
                    spectral: job.spectral_bins,
                },
                &|done, total| progress.update(done, total),
                Some(&progress.stop),
            )
            .map_err(|e| e.to_string())?,
        )
    };
    let (w, h) = job.resolution()?;
    let mut new_spp = 0;
    let this_run = match &mut output {
        Some(o) => {
            new_spp = o.result.spp;
            std::mem::replace(&mut o.film, FilmState::new(0, 0, false))
        }
        None => FilmState::new(w, h, false),
    };
    let film = match &mut job.resume {
        Some((_, st)) => {
            let mut f = std::mem::replace(&mut st.film, FilmState::new(0, 0, false));
            f.merge(&this_run);
            f
        }
        None => this_run,
    };
    Ok(Rendered {
        output,
        film,
        new_spp,
    })
}

/// True when the render ends in a state file: a slice, or an unfinished render (the
/// checkpoint); a finished whole render needs none.
pub fn ends_in_state(job: &RenderJob, rendered: &Rendered) -> bool {
    let done_until = job.first_sample + rendered.new_spp;
    job.range
        .as_ref()
        .is_some_and(|r| job.slice.is_some() || done_until != r.end)
}

/// Writes the state file of a slice or an unfinished render and reports: a finished slice is
/// `Ok`, an unfinished one (with its partial image) an error saying how to continue.
pub fn write_state(
    job: &RenderJob,
    rendered: Rendered,
    bar: &indicatif::ProgressBar,
) -> Result<(), String> {
    let args = &job.args;
    let total_spp = job.total_spp.unwrap_or(0);
    let state = RenderState {
        scene: args.scene.as_deref().map(absolute),
        fingerprint: job.fingerprint,
        settings: job.key.clone(),
        args: {
            // The sample count goes into the stored command line even when it came from
            // the scene, so --resume aims at the same N.
            let mut a = args.to_command_line();
            if args.spp.is_none() {
                a.extend(["--spp".to_string(), total_spp.to_string()]);
            }
            a
        },
        seed: args.seed,
        spp_total: total_spp,
        slice: job.slice.unwrap_or(SliceSpec::WHOLE),
        done_until: job.first_sample + rendered.new_spp,
        rgb_space: job.scene.options.rgb_space_name.clone(),
        png_exposure: job.scene.options.png_exposure,
        film: rendered.film,
    };
    let state_path = args.state_path(job.slice);
    state.save(&state_path).map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    match job.slice {
        Some(s) => report_slice(job, &state, s, rendered.new_spp, &state_path),
        None => report_checkpoint(job, &state, &state_path),
    }
}

/// The end of a slice: its rejected samples and the state written, or how to continue it.
fn report_slice(
    job: &RenderJob,
    state: &RenderState,
    s: SliceSpec,
    new_spp: u32,
    state_path: &std::path::Path,
) -> Result<(), String> {
    let r = job.range.clone().unwrap_or_default();
    for line in state.film.rejected.summary() {
        println!("  {line}");
    }
    if !state.is_complete() {
        return Err(format!(
            "interrupted: slice {s} holds samples {}..{} of {}..{}; state written to \
             {}; continue with `spectrace render --resume {}`",
            r.start,
            state.done_until,
            r.start,
            r.end,
            state_path.display(),
            state_path.display()
        ));
    }
    println!(
        "slice {s}: samples {}..{} of every pixel ({} spp in all), {} rendered now; wrote {}",
        r.start,
        r.end,
        state.spp_total,
        new_spp,
        state_path.display()
    );
    Ok(())
}

/// The end of an interrupted render: the partial image written and how to continue.
fn report_checkpoint(
    job: &RenderJob,
    state: &RenderState,
    state_path: &std::path::Path,
) -> Result<(), String> {
    let (args, film) = (&job.args, &state.film);
    let image = film.image();
    let mut written = save(
        &image,
        &job.outputs,
        &job.scene,
        extra_layers(args, film),
        args,
    )?;
    if let Some((p, _)) = write_spectral(args, film, &image, &job.scene)? {
        written.push(p);
    }
    for wr in written {
        println!(
            "  wrote {} (partial: {} spp)",
            wr.display(),
            state.done_until
        );
    }
    Err(format!(
        "interrupted after {} of {} spp; checkpoint written to {}; continue with \
         `spectrace render --resume {}`",
        state.done_until,
        state.spp_total,
        state_path.display(),
        state_path.display()
    ))
}
