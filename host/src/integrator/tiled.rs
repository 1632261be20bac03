//! The pass loop shared by the camera-driven renderers (path tracing, BDPT): the image is cut
//! into tiles rendered in parallel, and the sample budget into passes, so that Ctrl-C stops
//! within one pass. A pass enters the film only when all its tiles are done (an interrupted
//! pass is dropped), so the film always holds whole sample indices `start..start + spp` of
//! every pixel: exactly what a checkpoint needs to resume. Samples are indexed globally
//! (pixel, sample number) and the film's sums are exact, so neither the pass sizes, the thread
//! count, nor a split into slices ([`SampleBudget::Range`]) change the image.

use super::render::{
    fixed_budget_passes, DroppedPass, ProgressFn, RenderError, RenderSettings, SampleBudget,
};
use crate::film::spectral::SpectralBins;
use crate::film::spectral_film::{SpectralFilm, SpectralSums};
use crate::film::{FilmState, SplatFilm, TileBuffer};
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// A rayon pool with `threads` workers (`None`: one per core).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, RenderError> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        b = b.num_threads(t.max(1));
    }
    b.build().map_err(|e| RenderError::Threads {
        threads: threads.unwrap_or(0),
        message: e.to_string(),
    })
}

/// How a sample or time budget is cut into passes (spp per pass), shared by every driver so
/// that all stop the same way. For a sample budget: [`fixed_budget_passes`]. For a time budget:
/// 1 spp first, then passes sized from the measured cost per spp to fit half of the remaining
/// time (at most doubling, at most 64 spp); a pass still running at the end is stopped and
/// dropped ([`PassDeadline`]).
pub struct PassSchedule {
    budget: SampleBudget,
    fixed: Vec<u32>,
    pass: usize,
}

impl PassSchedule {
    /// The schedule for `budget`.
    pub fn new(budget: SampleBudget) -> Self {
        Self {
            budget,
            fixed: fixed_budget_passes(budget),
            pass: 0,
        }
    }

    /// Size of the next pass after `spp_done` samples per pixel took `elapsed`, or `None` when
    /// the budget is spent.
    pub fn next(&mut self, spp_done: u32, elapsed: Duration) -> Option<u32> {
        let size = match self.budget {
            SampleBudget::Spp(_) | SampleBudget::Range { .. } => *self.fixed.get(self.pass)?,
            SampleBudget::Time(t) => {
                if self.pass > 0 && elapsed >= t {
                    return None;
                }
                if spp_done == 0 {
                    1
                } else {
                    let per_spp = elapsed.as_secs_f64() / spp_done as f64;
                    // Aim at half of what is left: a pass still running at the end is
                    // dropped (see `PassDeadline`), and a pass aimed at 90% was lost whenever
                    // the rate fell by a tenth (4 s of a 10 s budget on a loaded machine);
                    // halving costs a few more, smaller passes near the end instead.
                    let remaining = 0.5 * t.saturating_sub(elapsed).as_secs_f64();
                    ((remaining / per_spp.max(1e-9)) as u32).clamp(1, spp_done.min(64))
                }
            }
        };
        self.pass += 1;
        Some(size)
    }

    /// Passes known so far, for progress: all of a sample budget, or those started of a time
    /// budget.
    pub fn passes_planned(&self) -> u64 {
        match self.budget {
            SampleBudget::Spp(_) | SampleBudget::Range { .. } => self.fixed.len() as u64,
            SampleBudget::Time(_) => self.pass as u64,
        }
    }
}

/// The end of a time budget, checked before each unit of work (tile or chunk of light paths).
/// The first pass always completes (an image needs at least one sample per pixel); a later pass
/// still running at the end is stopped after the units in flight and dropped.
#[derive(Clone, Copy, Debug)]
pub struct PassDeadline(Option<Instant>);

impl PassDeadline {
    /// The deadline of `budget` counted from `start` (none for sample budgets).
    pub fn new(budget: SampleBudget, start: Instant) -> Self {
        match budget {
            SampleBudget::Time(t) => Self(Some(start + t)),
            _ => Self(None),
        }
    }

    /// True when a unit of a pass started after `spp_done` samples per pixel must not run.
    #[inline]
    pub fn passed(&self, spp_done: u32) -> bool {
        spp_done > 0 && self.0.is_some_and(|d| Instant::now() >= d)
    }
}

/// What [`render_tiles`] produced.
pub struct TiledOutcome {
    /// The accumulated film (camera sums, and splat sums when asked for) of whole passes.
    pub film: FilmState,
    /// Samples per pixel completed by every pixel.
    pub spp: u32,
    /// Wall-clock time of the passes.
    pub elapsed: Duration,
    /// The pass the time budget stopped and dropped, if any.
    pub dropped_pass: Option<DroppedPass>,
}

/// Render a `width`×`height` image tile by tile and pass by pass for `settings.budget`.
/// `render_tile(buffer, samples, splats, spectral)` adds the samples with global indices
/// `samples` of every pixel of `buffer`'s tile, splatting into the pass's `splats` (kept only
/// when `splats` is true) and, when `spectral` nodes are given, adding camera samples and splats
/// to the pass's spectral film too; passes follow [`PassSchedule`] from the budget's first
/// sample index.
pub fn render_tiles(
    (width, height): (u32, u32),
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
    splats: bool,
    spectral: Option<SpectralBins>,
    render_tile: impl Fn(&mut TileBuffer, Range<u32>, &SplatFilm, Option<&SpectralFilm>) + Sync,
) -> Result<TiledOutcome, RenderError> {
    let ts = settings.tile_size.max(1);
    let mut tiles = Vec::new();
    for y0 in (0..height).step_by(ts as usize) {
        for x0 in (0..width).step_by(ts as usize) {
            tiles.push((x0, y0, ts.min(width - x0), ts.min(height - y0)));
        }
    }
    let pool = thread_pool(settings.threads)?;
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let mut film = FilmState::new(width, height, splats);
    film.spectral = spectral.map(|b| SpectralSums::new(b, width, height));
    let pass_spectral = spectral.map(|b| SpectralFilm::new(b, width, height));
    let done = AtomicU64::new(0);
    let start = Instant::now();
    let mut schedule = PassSchedule::new(settings.budget);
    let first = settings.budget.first_sample();
    let mut spp_done = 0u32;
    let deadline = PassDeadline::new(settings.budget, start);
    let mut dropped_pass = None;
    while let Some(pass_spp) = schedule.next(spp_done, start.elapsed()) {
        let pass_start = Instant::now();
        let total_units = tiles.len() as u64 * schedule.passes_planned();
        let samples = first + spp_done..first + spp_done + pass_spp;
        let (sw, sh) = if splats { (width, height) } else { (0, 0) };
        let pass_splats = SplatFilm::new(sw, sh);
        let buffers: Vec<Option<TileBuffer>> = pool.install(|| {
            tiles
                .par_iter()
                .map(|&(x0, y0, w, h)| {
                    if cancelled() || deadline.passed(spp_done) {
                        return None;
                    }
                    let mut buf = TileBuffer::new(x0, y0, w, h);
                    render_tile(
                        &mut buf,
                        samples.clone(),
                        &pass_splats,
                        pass_spectral.as_ref(),
                    );
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total_units);
                    Some(buf)
                })
                .collect()
        });
        if buffers.iter().any(Option::is_none) {
            // Cancelled or out of time mid-pass: drop the pass, so the film holds whole sample
            // indices.
            if !cancelled() {
                dropped_pass = Some(DroppedPass {
                    spp: pass_spp,
                    after: pass_start.elapsed(),
                });
            }
            break;
        }
        for b in buffers.iter().flatten() {
            film.camera.merge(b);
            film.record_rejected(&b.rejected);
        }
        let (sums, rejected) = pass_splats.into_sums();
        if splats {
            film.add_splats(&sums);
        }
        film.record_rejected(&rejected);
        if let (Some(pass), Some(sums)) = (&pass_spectral, &mut film.spectral) {
            pass.drain_into(sums);
        }
        film.spp += pass_spp as u64;
        spp_done += pass_spp;
        if cancelled() {
            break;
        }
    }
    Ok(TiledOutcome {
        film,
        spp: spp_done,
        elapsed: start.elapsed(),
        dropped_pass,
    })
}
