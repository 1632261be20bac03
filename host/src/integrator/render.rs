//! The render driver: splits the image into tiles, renders them in parallel with rayon, and
//! merges them into the film in tile order. Each camera sample draws its random numbers from
//! `(seed, pixel, sample index)` only, so the image is bitwise identical for any thread count.

use super::wavelength_groups::{PathWavelengthSampler, PathWavelengths};
use super::{PathStats, PathTracer, PixelSampler};
use crate::camera::CameraSample;
use crate::film::{PixelFilm, Sensor, TileBuffer, XyzImage};
use crate::scene::Scene;
use glam::Vec2;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How many samples to take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleBudget {
    /// Exactly this many samples per pixel.
    Spp(u32),
    /// Keep adding passes of samples until this much time has passed (the last pass finishes).
    Time(Duration),
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
    let SampleBudget::Spp(n) = budget else {
        return Vec::new();
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
/// `cancel`, when set, stops after the tiles in flight; the partial film is returned.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<RenderResult, RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let (width, height) = cam.camera.resolution();
    let ts = settings.tile_size.max(1);
    let mut tiles = Vec::new();
    for y0 in (0..height).step_by(ts as usize) {
        for x0 in (0..width).step_by(ts as usize) {
            tiles.push((x0, y0, ts.min(width - x0), ts.min(height - y0)));
        }
    }
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(t) = settings.threads {
            b = b.num_threads(t.max(1));
        }
        b.build().map_err(|e| RenderError::Threads {
            threads: settings.threads.unwrap_or(0),
            message: e.to_string(),
        })?
    };
    let wavelength_sampler = PathWavelengthSampler::new(
        scene,
        settings.tracer.wavelengths,
        settings.tracer.wavelengths_per_path,
    )
    .map_err(RenderError::Setup)?;
    let sensor = Sensor::new(scene.observer.clone());
    let mut film = PixelFilm::new(width, height);
    let rays = AtomicU64::new(0);
    let done = AtomicU64::new(0);
    let start = Instant::now();
    let mut spp_done = 0u32;
    // Pass sizes: for a fixed budget, see [`fixed_budget_passes`]; for a time budget, passes
    // sized from the measured cost per spp to fit the remaining time, so the last pass
    // overshoots little.
    let spp_passes = fixed_budget_passes(settings.budget);
    let mut pass = 0u32;
    loop {
        let pass_spp = match settings.budget {
            SampleBudget::Spp(_) => match spp_passes.get(pass as usize) {
                Some(&p) => p,
                None => break,
            },
            SampleBudget::Time(t) => {
                let elapsed = start.elapsed();
                if pass > 0 && elapsed >= t {
                    break;
                }
                if spp_done == 0 {
                    1
                } else {
                    // Fit the next pass into the remaining time from the measured cost per spp
                    // (at most doubling, at most 64 spp per pass).
                    let per_spp = elapsed.as_secs_f64() / spp_done as f64;
                    let remaining = (t - elapsed).as_secs_f64();
                    ((remaining / per_spp.max(1e-9)) as u32).clamp(1, spp_done.min(64))
                }
            }
        };
        let total_units = match settings.budget {
            SampleBudget::Spp(_) => tiles.len() as u64 * spp_passes.len() as u64,
            SampleBudget::Time(_) => tiles.len() as u64 * (pass as u64 + 1),
        };
        let first = spp_done;
        let buffers: Vec<Option<TileBuffer>> = pool.install(|| {
            tiles
                .par_iter()
                .map(|&(x0, y0, w, h)| {
                    if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                        return None;
                    }
                    let mut buf = TileBuffer::new(x0, y0, w, h);
                    let mut stats = PathStats::default();
                    for y in y0..y0 + h {
                        for x in x0..x0 + w {
                            let pixel = y as u64 * width as u64 + x as u64;
                            for s in first..first + pass_spp {
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
                                // A NaN/Inf sample would poison the pixel forever; drop it.
                                if xyz.iter().all(|v| v.is_finite()) {
                                    buf.add(x, y, xyz);
                                } else {
                                    buf.add(x, y, [0.0; 3]);
                                }
                            }
                        }
                    }
                    rays.fetch_add(stats.rays + stats.shadow_rays, Ordering::Relaxed);
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(d, total_units);
                    Some(buf)
                })
                .collect()
        });
        let mut complete = true;
        for b in &buffers {
            match b {
                Some(b) => film.merge(b),
                None => complete = false,
            }
        }
        if !complete {
            // Cancelled mid-pass: keep what exists (pixel means stay unbiased per pixel).
            break;
        }
        spp_done += pass_spp;
        pass += 1;
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            break;
        }
    }
    let elapsed = start.elapsed();
    Ok(RenderResult {
        image: film.image(),
        spp: spp_done,
        samples: film.sample_count() as u64,
        rays: rays.load(Ordering::Relaxed),
        elapsed,
    })
}
