//! The render driver: splits the image into tiles, renders them in parallel with rayon, and
//! merges them into the film in tile order. Each camera sample draws its random numbers from
//! `(seed, pixel, sample index)` only, so the image is bitwise identical for any thread count.

use super::tiled::render_tiles;
use super::wavelength_groups::{PathWavelengthSampler, PathWavelengths};
use super::{PathStats, PathTracer, PixelSampler};
use crate::camera::CameraSample;
use crate::film::{FilmState, Sensor, XyzImage};
use crate::scene::Scene;
use glam::Vec2;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
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

/// A camera sample's XYZ: the mean over wavelength groups of each group's sensor response to
/// its radiance `l` (scaled by the camera weight). One group gives exactly `Sensor::to_xyz`.
fn film_xyz(
    sensor: &Sensor,
    l: &super::path::GroupRadiance,
    lambdas: &PathWavelengths,
    camera_weight: f32,
) -> [f64; 3] {
    let groups = lambdas.groups();
    let mut xyz = sensor.to_xyz(&(l[0] * camera_weight), &groups[0]);
    if groups.len() > 1 {
        for (lg, wg) in l.iter().zip(groups).skip(1) {
            let x = sensor.to_xyz(&(*lg * camera_weight), wg);
            for c in 0..3 {
                xyz[c] += x[c];
            }
        }
        let inv = 1.0 / groups.len() as f64;
        for v in &mut xyz {
            *v *= inv;
        }
    }
    xyz
}

/// Render `scene` with `settings`. `progress` may be called from several threads.
/// `cancel`, when set, stops after the tiles in flight; the film of the whole passes done is
/// returned.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<RenderResult, RenderError> {
    render_pt(scene, settings, progress, cancel).map(|(r, _)| r)
}

/// [`render`], also returning the exact film (for slices and checkpoints).
pub fn render_pt(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<(RenderResult, FilmState), RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let (width, height) = cam.camera.resolution();
    let wavelength_sampler = PathWavelengthSampler::new(
        scene,
        settings.tracer.wavelengths,
        settings.tracer.wavelengths_per_path,
    )
    .map_err(RenderError::Setup)?;
    let sensor = Sensor::new(scene.observer.clone());
    let rays = AtomicU64::new(0);
    let outcome = render_tiles(
        (width, height),
        settings,
        progress,
        cancel,
        false,
        |buf, samples, _| {
            let mut stats = PathStats::default();
            for y in buf.y0..buf.y0 + buf.h {
                for x in buf.x0..buf.x0 + buf.w {
                    let pixel = y as u64 * width as u64 + x as u64;
                    for s in samples.clone() {
                        let mut rng = PixelSampler::new(settings.seed, pixel, s);
                        let mut lambdas = wavelength_sampler.sample(&mut rng);
                        let offset = cam.filter.sample(rng.next_2d());
                        let sample = CameraSample {
                            p_film: Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset,
                            p_lens: rng.next_2d(),
                        };
                        let xyz = match cam.camera.generate_ray(&sample) {
                            Some(r) => {
                                let l = settings.tracer.li_groups(
                                    scene,
                                    r.ray,
                                    &mut lambdas,
                                    &mut rng,
                                    &mut stats,
                                );
                                film_xyz(&sensor, &l, &lambdas, r.weight)
                            }
                            None => [0.0; 3],
                        };
                        // The film's guard keeps NaN/Inf/negative samples out and counts them.
                        buf.add(x, y, xyz, "pt camera path");
                    }
                }
            }
            rays.fetch_add(stats.rays + stats.shadow_rays, Ordering::Relaxed);
        },
    )?;
    let film = outcome.film;
    Ok((
        RenderResult {
            image: film.image(),
            spp: outcome.spp,
            samples: film.camera.sample_count(),
            rays: rays.load(Ordering::Relaxed),
            elapsed: outcome.elapsed,
        },
        film,
    ))
}
