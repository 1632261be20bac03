//! Light tracing (the t = 1 strategies alone): paths start at lights and every vertex is
//! connected to a lens point sampled by the camera; the camera's importance `We` turns the
//! flux carried by the path into a pixel measurement, splatted onto a thread-safe film and
//! scaled by 1/(light paths per pixel).
//!
//! Lights flagged `BEAMS_ONLY` (only the seed's `next_beam`) are rendered here too: a beam is one
//! Monte Carlo sample of its source's flux (`power_w` already divides by the densities of its
//! origin, direction and wavelength), carried at its single wavelength ([`trace_beam`]). BDPT
//! uses the same code for those lights, with weight 1, since no other strategy can reach them.
//!
//! Determinism: light path `k` draws its random numbers from `(seed, k)` only, and the splat
//! film's sums are exact, so the image is identical for any thread count. Sample index `s`
//! (the unit of slices and checkpoints) is the block of light paths `s·pixels .. (s+1)·pixels`:
//! a slice of sample indices is a contiguous range of light paths, and the film of a whole
//! render is the exact sum of its slices' films.

use super::bdpt::{generate_light_subpath, random_walk, LightStart};
use super::render::ProgressFn;
use super::select::{IntegratorOutput, WavelengthMixture};
use super::vertex::{unoccluded, Vertex};
use super::{PathStats, RenderError, RenderResult, RenderSettings, SampleRng};
use crate::camera::Camera;
use crate::film::{FilmState, Sensor, SplatFilm};
use crate::geometry::Ray;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// The `sample` index of [`SampleRng::for_sample`] reserved for light paths (camera samples use
/// small indices), so light path `k` and pixel `k`'s samples never share a stream.
pub const LIGHT_PATH_STREAM: u64 = u64::MAX;

/// Light paths per parallel work unit.
const CHUNK: u64 = 4096;

/// Per-lane factors turning a spectral sample into film XYZ (`x̄ȳz̄(λ)/(pdf(λ)·LANES·∫ȳ)`), for
/// all lanes and for the hero alone (after a dispersive event: pdf/LANES, see
/// `SampledWavelengths::terminate_secondary`).
#[derive(Clone, Copy, Debug)]
pub struct XyzWeights {
    full: [[f64; 3]; LANES],
    hero: [f64; 3],
}

impl XyzWeights {
    /// Factors for `lambda` under `sensor`'s observer.
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn new(sensor: &Sensor, lambda: &SampledWavelengths) -> Self {
        let iy = sensor.observer().integral_y();
        let inv_iy = if iy > 0.0 { 1.0 / iy } else { 0.0 };
        let mut full = [[0.0; 3]; LANES];
        let mut hero = [0.0; 3];
        for i in 0..LANES {
            let p = lambda.pdf[i] as f64;
            if p > 0.0 {
                let bar = sensor.observer().xyz_bar(lambda.lambda[i] as f64);
                full[i] = bar.map(|b| b * inv_iy / (p * LANES as f64));
                if i == 0 {
                    hero = bar.map(|b| b * inv_iy / p);
                }
            }
        }
        Self { full, hero }
    }

    /// XYZ of spectral sample `l`; `hero_only` after a dispersive event.
    #[inline]
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn xyz(&self, l: &SampledSpectrum, hero_only: bool) -> [f64; 3] {
        if hero_only {
            let v = l.0[0] as f64;
            return if v == 0.0 {
                [0.0; 3]
            } else {
                self.hero.map(|h| h * v)
            };
        }
        let mut out = [0.0; 3];
        for i in 0..LANES {
            let v = l.0[i] as f64;
            if v != 0.0 {
                for c in 0..3 {
                    out[c] += self.full[i][c] * v;
                }
            }
        }
        out
    }
}

/// Largest single-sample luminance Y (before the 1/spp scaling) that reached each pixel, kept
/// with atomics so splats from any thread can record it (non-negative f64 bit patterns order
/// like the values, so an integer `fetch_max` is exact).
#[derive(Debug)]
pub struct PixelMaxY {
    width: u32,
    height: u32,
    bits: Vec<AtomicU64>,
}

impl PixelMaxY {
    /// All zero.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            bits: (0..width as usize * height as usize)
                .map(|_| AtomicU64::new(0))
                .collect(),
        }
    }

    /// Record `|y|` at raster position (`px`, `py`) (ignored off the film or if not finite).
    #[inline]
    pub fn record(&self, px: f32, py: f32, y: f64) {
        if !(px >= 0.0 && py >= 0.0 && y.is_finite()) {
            return;
        }
        let (x, yy) = (px as u32, py as u32);
        if x < self.width && yy < self.height {
            self.bits[yy as usize * self.width as usize + x as usize]
                .fetch_max(y.abs().to_bits(), Ordering::Relaxed);
        }
    }

    /// The maxima, row-major.
    pub fn values(&self) -> Vec<f64> {
        self.bits
            .iter()
            .map(|b| f64::from_bits(b.load(Ordering::Relaxed)))
            .collect()
    }
}

/// The t = 1 connection of light vertex `s − 1` (s ≥ 1) to a lens point sampled with `u`:
/// the unweighted contribution, the raster position and the lens vertex. For s = 1 it is the
/// light's own emission seen by the camera (area lights only).
pub fn connect_to_camera(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    s: usize,
    lambda: &SampledWavelengths,
    u: Vec2,
    stats: &mut PathStats,
) -> Option<(SampledSpectrum, Vec2, Vertex)> {
    let qs = &light_path[s - 1];
    if !qs.connectible() {
        return None;
    }
    let cs = camera.sample_wi(qs.p, u)?;
    if !(cs.pdf > 0.0 && cs.importance > 0.0) {
        return None;
    }
    let cam_v = Vertex::camera(
        cs.p_lens,
        cs.n_lens,
        SampledSpectrum::splat(cs.importance / cs.pdf),
    );
    let c = if s == 1 {
        let light = &scene.lights.lights()[qs.light_index(scene)? as usize];
        let w = cs.wi;
        let le = light.radiance(qs.p, qs.ng, qs.uv, w, lambda);
        let origin = qs.pdf_light_origin(scene, &cam_v);
        if le.is_black() || !(origin > 0.0) {
            return None;
        }
        le * (qs.ng.dot(w).abs() / origin) * cam_v.beta
    } else {
        let mut c = qs.beta * qs.f(scene, &cam_v, lambda, TransportMode::Importance) * cam_v.beta;
        if qs.on_surface() {
            c *= cs.wi.dot(qs.ns).abs();
        }
        c
    };
    if c.is_black() {
        return None;
    }
    stats.shadow_rays += 1;
    if !unoccluded(scene, qs, &cam_v) {
        return None;
    }
    Some((c, cs.p_raster, cam_v))
}

/// Trace one beam of beams-only light `index` (chosen with probability `pmf`) and hand every
/// camera connection of its path to `splat` as (raster position, XYZ).
#[allow(clippy::too_many_arguments)]
pub fn trace_beam(
    scene: &Scene,
    camera: &dyn Camera,
    sensor: &Sensor,
    index: usize,
    pmf: f32,
    max_depth: u32,
    rr_depth: u32,
    rng: &mut SampleRng,
    stats: &mut PathStats,
    splat: &mut dyn FnMut(Vec2, [f64; 3]),
) {
    let u: [f64; 8] = std::array::from_fn(|_| rng.next_1d() as f64);
    let light = &scene.lights.lights()[index];
    let Some(beam) = light.next_beam(&spectrace_plugin_api::RandomSample { u }) else {
        return;
    };
    let dir = Vec3A::new(
        beam.direction.x as f32,
        beam.direction.y as f32,
        beam.direction.z as f32,
    );
    let origin = Vec3A::new(
        beam.origin.x as f32,
        beam.origin.y as f32,
        beam.origin.z as f32,
    );
    let power = beam.power_w / pmf as f64;
    if !(power.is_finite() && power > 0.0 && dir.length_squared() > 0.0 && origin.is_finite()) {
        return;
    }
    let nm = beam.wavelength_nm as f32;
    let lambda = SampledWavelengths {
        lambda: [nm; LANES],
        pdf: [1.0, 0.0, 0.0, 0.0],
    };
    let iy = sensor.observer().integral_y();
    let bar = sensor.observer().xyz_bar(beam.wavelength_nm);
    if !(iy > 0.0) || bar.iter().all(|&b| b == 0.0) {
        return;
    }
    let beta = SampledSpectrum::splat(power as f32);
    let mut path = vec![Vertex::light(
        index as u32,
        origin,
        Vec3A::ZERO,
        Vec3A::ZERO,
        beta,
    )];
    random_walk(
        scene,
        Ray::new(origin, dir.normalize()),
        &lambda,
        rng,
        beta,
        1.0,
        max_depth as usize,
        TransportMode::Importance,
        rr_depth,
        &mut path,
        stats,
    );
    for s in 2..=path.len() {
        if let Some((c, raster, _)) =
            connect_to_camera(scene, camera, &path, s, &lambda, rng.next_2d(), stats)
        {
            let v = c.0[0] as f64 / iy;
            splat(raster, bar.map(|b| b * v));
        }
    }
}

/// One light path (or beam) of light tracing, splatted through `splat`. Returns the number of
/// non-finite contributions dropped.
#[allow(clippy::too_many_arguments)]
fn trace_light_path(
    scene: &Scene,
    camera: &dyn Camera,
    sensor: &Sensor,
    mixture: &WavelengthMixture,
    settings: &RenderSettings,
    rng: &mut SampleRng,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    splat: &mut dyn FnMut(Vec2, [f64; 3]),
) {
    let lambda = mixture.sample(rng);
    let max_depth = settings.tracer.max_depth;
    let rr = settings.tracer.rr_depth;
    match generate_light_subpath(scene, &lambda, rng, max_depth as usize + 1, rr, path, stats) {
        LightStart::None => {}
        LightStart::Beams { index, pmf } => {
            trace_beam(
                scene, camera, sensor, index, pmf, max_depth, rr, rng, stats, splat,
            );
        }
        LightStart::Path => {
            let weights = XyzWeights::new(sensor, &lambda);
            for s in 1..=path.len() {
                if let Some((c, raster, _)) =
                    connect_to_camera(scene, camera, path, s, &lambda, rng.next_2d(), stats)
                {
                    splat(raster, weights.xyz(&c, path[s - 1].dispersed));
                }
            }
        }
    }
}

/// Render `scene` by light tracing: `spp × width × height` light paths (or a time budget), the
/// image being the splat sums divided by the light paths per pixel.
pub fn render_light_tracing(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let camera = cam.camera.as_ref();
    let (width, height) = camera.resolution();
    let pixels = width as u64 * height as u64;
    let pool = super::tiled::thread_pool(settings.threads)?;
    let sensor = Sensor::new(scene.observer.clone());
    let mixture = WavelengthMixture::new(scene);
    let mut film = FilmState::new(width, height, true);
    let rays = AtomicU64::new(0);
    let pixel_max = PixelMaxY::new(width, height);
    let done = AtomicU64::new(0);
    let start = Instant::now();
    let mut spp_done = 0u32;
    let mut schedule = super::tiled::PassSchedule::new(settings.budget);
    let mut total_units = 0u64;
    while let Some(pass_spp) = schedule.next(spp_done, start.elapsed()) {
        let first = (settings.budget.first_sample() + spp_done) as u64 * pixels;
        let splats = SplatFilm::new(width, height);
        let count = pass_spp as u64 * pixels;
        let chunks = count.div_ceil(CHUNK);
        total_units += chunks;
        let cancelled = pool.install(|| {
            (0..chunks)
                .into_par_iter()
                .map(|c| {
                    if cancel.is_some_and(|f| f.load(Ordering::Relaxed)) {
                        return true;
                    }
                    let mut stats = PathStats::default();
                    let mut path = Vec::with_capacity(16);
                    let mut splat = |raster: Vec2, xyz: [f64; 3]| {
                        pixel_max.record(raster.x, raster.y, xyz[1]);
                        // The film's guard refuses and counts NaN/Inf/negative contributions.
                        splats.splat_as(raster.x, raster.y, xyz, "lt light path (t = 1)");
                    };
                    let lo = first + c * CHUNK;
                    let hi = (lo + CHUNK).min(first + count);
                    for k in lo..hi {
                        let mut rng = SampleRng::for_sample(settings.seed, k, LIGHT_PATH_STREAM);
                        trace_light_path(
                            scene, camera, &sensor, &mixture, settings, &mut rng, &mut path,
                            &mut stats, &mut splat,
                        );
                    }
                    rays.fetch_add(stats.rays + stats.shadow_rays, Ordering::Relaxed);
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(d, total_units);
                    false
                })
                .collect::<Vec<bool>>()
                .into_iter()
                .any(|c| c)
        });
        if cancelled {
            // A partial pass would leave some pixels short of paths: drop it, so the film
            // holds whole sample indices (what a checkpoint resumes from).
            break;
        }
        let (sums, rejected) = splats.into_sums();
        film.add_splats(&sums);
        film.record_rejected(&rejected);
        film.spp += pass_spp as u64;
        spp_done += pass_spp;
        if cancel.is_some_and(|f| f.load(Ordering::Relaxed)) {
            break;
        }
    }
    let elapsed = start.elapsed();
    let image = film.image();
    Ok(IntegratorOutput {
        result: RenderResult {
            image,
            spp: spp_done,
            samples: spp_done as u64 * pixels,
            rays: rays.load(Ordering::Relaxed),
            elapsed,
        },
        strategy_images: Vec::new(),
        non_finite: film.rejected.total(),
        max_sample_y: pixel_max.values(),
        film,
    })
}
