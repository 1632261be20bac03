//! The render driver: splits the image into tiles, renders them in parallel with rayon, and
//! merges them into the film in tile order. Each camera sample draws its random numbers from
//! `(seed, pixel, sample index)` only, so the image is bitwise identical for any thread count.

use super::wavelengths::sampling::WavelengthSampling;
use crate::film::XyzImage;
use crate::sampler::SamplerKind;
use std::time::Duration;

/// How many samples to take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleBudget {
    /// Exactly this many samples per pixel.
    Spp(u32),
    /// Keep adding passes of samples until this much time has passed (the last pass finishes).
    Time(Duration),
    /// Only the sample indices `start..end` of every pixel (light paths
    /// `start·pixels..end·pixels` for light tracing): a slice of a larger render, or the rest of
    /// an interrupted one. The image of such a part alone is its own `end − start` spp estimate.
    Range {
        /// First sample index.
        start: u32,
        /// One past the last.
        end: u32,
    },
}

impl SampleBudget {
    /// The first sample index rendered (0 unless a [`Range`](Self::Range)).
    pub fn first_sample(&self) -> u32 {
        match *self {
            Self::Range { start, .. } => start,
            _ => 0,
        }
    }
}

/// What to render and how.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Samples per pixel or a time budget.
    pub budget: SampleBudget,
    /// Seed of all random numbers.
    pub seed: u64,
    /// Worker threads (`None`: rayon's default, one per core).
    pub threads: Option<usize>,
    /// Camera name (`None`: the first).
    pub camera: Option<String>,
    /// Tile edge in pixels.
    pub tile_size: u32,
    /// The path tracer's settings.
    pub tracer: PathTracer,
    /// The numbers of camera samples and light paths: Sobol' points (default) or independent.
    pub sampler: SamplerKind,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            budget: SampleBudget::Spp(16),
            seed: 0,
            threads: None,
            camera: None,
            tile_size: 16,
            tracer: PathTracer::default(),
            sampler: SamplerKind::Sobol,
        }
    }
}

/// A failure before or during rendering.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Unknown camera and the like.
    #[error("{0}")]
    Setup(String),
    /// The thread pool could not be created.
    #[error("cannot start {threads} render threads: {message}")]
    Threads {
        /// Requested count.
        threads: usize,
        /// Cause.
        message: String,
    },
}

/// The rendered image and the numbers for the summary.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// Mean XYZ per pixel.
    pub image: XyzImage,
    /// Samples per pixel actually taken.
    pub spp: u32,
    /// Camera samples taken in total.
    pub samples: u64,
    /// Closest-hit plus shadow rays traced.
    pub rays: u64,
    /// Wall-clock time of the sampling loop.
    pub elapsed: Duration,
    /// The pass a time budget stopped mid-way and dropped (its samples are not in the image).
    pub dropped_pass: Option<DroppedPass>,
}

/// A pass of a time budget that was still running when the budget ended: it is stopped after
/// the tiles in flight (so the overrun is a fraction of a pass) and dropped, so every pixel
/// holds the same whole number of samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DroppedPass {
    /// Its size in samples per pixel.
    pub spp: u32,
    /// How long it had run when it was stopped.
    pub after: Duration,
}

/// Progress reports: called from worker threads with (finished units, total units); for time
/// budgets the total grows with each pass.
pub type ProgressFn<'a> = dyn Fn(u64, u64) + Sync + 'a;

/// The pass sizes (spp) that make up a fixed budget: growing passes 1, 1, 2, 4, 8, 16, 16, …
/// so that a cancel (Ctrl-C) stops within one pass and leaves every pixel with the same sample
/// count. Empty for a time budget. Every driver indexes samples globally, so how a budget is
/// split into passes does not change the image.
pub fn fixed_budget_passes(budget: SampleBudget) -> Vec<u32> {
    let n = match budget {
        SampleBudget::Spp(n) => n,
        SampleBudget::Range { start, end } => end.saturating_sub(start),
        SampleBudget::Time(_) => return Vec::new(),
    };
    let mut passes = Vec::new();
    let mut left = n;
    let mut size = 1u32;
    while left > 0 {
        let p = size.min(left);
        passes.push(p);
        left -= p;
        if passes.len() > 1 {
            size = (size * 2).min(16);
        }
    }
    passes
}

/// Counters for the render summary (per thread, summed afterwards).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathStats {
    /// Closest-hit rays traced.
    pub rays: u64,
    /// Shadow (any-hit) rays traced.
    pub shadow_rays: u64,
}

/// Path settings shared by the integrators (depth, Russian roulette, wavelengths); path
/// tracing's own methods on it are in [`super::path`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathTracer {
    /// Maximum number of scattering events (bounces).
    pub max_depth: u32,
    /// Bounce from which Russian roulette may end paths (path tracing replaces the default 3
    /// by its own, [`super::path::PT_RR_DEPTH`]).
    pub rr_depth: u32,
    /// Only direct lighting (emission seen directly plus one bounce of NEE/BSDF sampling):
    /// used for analytic tests.
    pub direct_only: bool,
    /// How camera paths draw their hero wavelength.
    pub wavelengths: WavelengthSampling,
    /// Wavelengths carried by one camera path: 1, or a multiple of 4 up to
    /// [`MAX_WAVELENGTHS_PER_PATH`](super::wavelengths::groups::MAX_WAVELENGTHS_PER_PATH)
    /// (4 = one hero group, the default). More wavelengths per path lower the colour noise of
    /// one sample for the cost of evaluating materials and lights once more per group. N = 1
    /// keeps only the hero lane but still computes 4-wide vectors, so it is no faster than 4.
    pub wavelengths_per_path: u32,
}

impl Default for PathTracer {
    fn default() -> Self {
        Self {
            max_depth: 64,
            rr_depth: 3,
            direct_only: false,
            wavelengths: WavelengthSampling::Product,
            wavelengths_per_path: 4,
        }
    }
}
