//! Light tracing (the t = 1 strategies alone): paths start at lights and every vertex is
//! connected to a lens point sampled by the camera; the camera's importance `We` turns the
//! flux carried by the path into a pixel measurement, splatted onto a thread-safe film and
//! scaled by 1/(light paths per pixel).
//!
//! Lights flagged `BEAMS_ONLY` (only the seed's `next_beam`) are rendered here too, by
//! [`trace_beam_with`](super::subpath::beam::trace_beam_with), with the beam's uniforms from the light
//! path's sequence. Wavelengths: one set per light path, drawn as bdpt draws a pair's
//! ([`PairWavelengths`]).
//!
//! Determinism: light path `k` draws its random numbers from `(seed, k)` only, and the splat
//! film's sums are exact, so the image is identical for any thread count. Sample index `s`
//! (the unit of slices and checkpoints) is the block of light paths `s·pixels .. (s+1)·pixels`:
//! a slice of sample indices is a contiguous range of light paths, and the film of a whole
//! render is the exact sum of its slices' films.
//!
//! | parameter   | unit     | default | meaning                                              |
//! |-------------|----------|---------|------------------------------------------------------|
//! | `max_depth` | bounces  | 64      | longest light path, `--max-depth`                    |
//! | `rr_depth`  | vertices | 3       | path length from which Russian roulette may stop it  |

use super::driver::{Integrator, IntegratorInfo, IntegratorOutput, Registration};
use super::pixel_max::PixelMaxY;
use super::render::ProgressFn;
use super::subpath::beam::trace_beam_with;
use super::subpath::camera_connection::{connect_to_camera, SplatFn};
use super::subpath::light_subpath::{generate_light_subpath_with, LightStart};
use super::subpath::random_walk::WalkShift;
use super::subpath::vertex::Vertex;
use super::wavelengths::flat_colour::FlatColour;
use super::wavelengths::pairs::PairWavelengths;
use super::wavelengths::xyz_weights::XyzWeights;
use super::{PathStats, PixelSampler, RenderError, RenderResult, RenderSettings};
use crate::camera::Camera;
use crate::film::spectral::SpectralBins;
use crate::film::spectral_film::{LaneEnergies, SpectralFilm, SpectralSums};
use crate::film::{FilmState, Sensor, SplatFilm};
use crate::integrator::plan::RenderPlan;
use crate::light::LightFlags;
use crate::scene::Scene;
use crate::spectrum::LaneMask;
use glam::Vec2;
use rayon::prelude::*;
use spectrace_plugin_api::ParamDoc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Type information of light tracing.
pub const INFO: IntegratorInfo = IntegratorInfo {
    name: "lt",
    aliases: &["light"],
    version: 1,
    description: "light tracing: light paths connected to the camera (t = 1) only",
    params: &[
        ParamDoc::optional(
            "max_depth",
            "bounces",
            "64",
            "longest light path; --max-depth or the scene's max_depth",
        ),
        ParamDoc::optional(
            "rr_depth",
            "vertices",
            "3",
            "path length from which Russian roulette may end a path",
        ),
    ],
};

/// Light tracing's registration.
pub const REGISTRATION: Registration = Registration {
    info: &INFO,
    build: |settings, options| {
        Ok(Box::new(LightTracer {
            max_depth: settings.tracer.max_depth,
            rr_depth: settings.tracer.rr_depth,
            spectral: options.spectral,
        }))
    },
};

/// Light tracing settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTracer {
    /// Maximum number of bounces of a light path.
    pub max_depth: u32,
    /// Path vertex count from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Also accumulate a spectral image at these nodes.
    pub spectral: Option<SpectralBins>,
}

impl Integrator for LightTracer {
    fn info(&self) -> &'static IntegratorInfo {
        &INFO
    }

    fn render(
        &self,
        scene: &Scene,
        plan: &RenderPlan,
        settings: &RenderSettings,
        progress: &ProgressFn<'_>,
        cancel: Option<&AtomicBool>,
    ) -> Result<IntegratorOutput, RenderError> {
        render_light_tracing(self, scene, plan, settings, progress, cancel)
    }

    fn light_strategy(&self, flags: LightFlags) -> &'static str {
        if flags.contains(LightFlags::BEAMS_ONLY) {
            "light tracing of its beams (t = 1 splats, unweighted)"
        } else {
            "lt: light paths connected to the camera (t = 1)"
        }
    }
}

/// Dimensions of a light path's sequence ([`PixelSampler::for_light_path`]): wavelengths
/// (0–2) and the start (3–5) in order, then the walk, 3 requests a bounce (4 with
/// fluorescence), from [`WALK`], and the t = 1 lens point of vertex `s` at `T1 + s − 1`
/// (each its own block, see [`PixelSampler::set_block`]; none for a pinhole): so each request keeps its
/// dimension across light paths whatever the path's length. The first [`WALK`]`.1 / 3`
/// bounces and [`T1_LD`] lens points are Sobol' points, the rest PCG.
const WALK: (u32, u32) = (6, 16);
const T1: u32 = 22;
const T1_LD: usize = 4;
/// Start of the PCG-only blocks of deeper lens points and of a beam's walk.
const FAR: u32 = 1 << 24;

/// Light paths per parallel work unit.
const CHUNK: u64 = 4096;

/// One light path (or beam) of light tracing, splatted through `splat`. Returns the number of
/// non-finite contributions dropped.
#[allow(clippy::too_many_arguments)]
fn trace_light_path(
    scene: &Scene,
    camera: &dyn Camera,
    sensor: &Sensor,
    pair: &PairWavelengths<'_>,
    lt: &LightTracer,
    ld: &mut PixelSampler,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    splat: &mut SplatFn<'_>,
    flat: Option<&FlatColour>,
) {
    // Every number comes from the light path's stratified sequence (layout: [`WALK`]).
    let lambda = pair.sample(ld);
    let max_depth = lt.max_depth;
    let rr = lt.rr_depth;
    let u_start = (ld.next_1d(), ld.next_2d(), ld.next_2d());
    ld.set_block(WALK.0, WALK.1);
    match generate_light_subpath_with(
        scene,
        &lambda,
        u_start,
        ld,
        max_depth as usize + 1,
        rr,
        path,
        stats,
        WalkShift::LightLanes,
    ) {
        LightStart::None => {}
        LightStart::Beams { index, pmf } => {
            // The beam's origin, direction and wavelength from the sequence too (2D pairs
            // (u₀, u₁), (u₂, u₃), then single dimensions) in the walk's block (a beams-only
            // light made no walk); its walk and lens points PCG.
            let (a, b) = (ld.next_2d(), ld.next_2d());
            let mut u = [a.x, a.y, b.x, b.y, 0.0, 0.0, 0.0, 0.0].map(f64::from);
            for x in &mut u[4..] {
                *x = ld.next_1d() as f64;
            }
            ld.set_block(FAR, 0);
            trace_beam_with(
                scene, camera, sensor, index, pmf, max_depth, rr, u, ld, stats, splat,
            );
        }
        LightStart::Path => {
            let weights = XyzWeights::new(sensor, &lambda);
            // Spectrally flat so far (vertices 0..s), and the emitter (see `FlatColour`).
            let mut flat_so_far = flat.is_some();
            let emitter = path.first().and_then(|v| v.light_index(scene));
            let pinhole = camera.pinhole();
            for s in 1..=path.len() {
                if let Some(fc) = flat {
                    flat_so_far = flat_so_far && fc.vertex_is_flat(&path[s - 1]);
                }
                // A pinhole's lens point needs no numbers.
                let u = if pinhole {
                    Vec2::ZERO
                } else {
                    if s <= T1_LD {
                        ld.set_block(T1 + s as u32 - 1, 1);
                    } else {
                        ld.set_block(FAR + s as u32, 0);
                    }
                    ld.next_2d()
                };
                if let Some((c, raster, _)) =
                    connect_to_camera(scene, camera, path, s, &lambda, u, stats)
                {
                    let v = &path[s - 1];
                    let exact = match (flat, emitter) {
                        (Some(fc), Some(e)) if flat_so_far => fc.xyz(e, &c, &lambda),
                        _ => None,
                    };
                    if let Some(xyz) = exact {
                        // The spectral film keeps the per-lane estimate.
                        splat(raster, xyz, &|| weights.energies(&c, LaneMask::ALL));
                        continue;
                    }
                    let lanes = v.lanes;
                    // Shifted by fluorescence: the observer weighs the wavelengths that reach
                    // the camera, each divided by its lane's original density.
                    let shifted_weights;
                    let w = match v.shifted {
                        Some(_) => {
                            shifted_weights = XyzWeights::new(sensor, &v.wavelengths(&lambda));
                            &shifted_weights
                        }
                        None => &weights,
                    };
                    splat(raster, w.xyz(&c, lanes), &|| w.energies(&c, lanes));
                }
            }
        }
    }
}

/// Render `scene` by light tracing: `spp × width × height` light paths (or a time budget), the
/// image being the splat sums divided by the light paths per pixel.
fn render_light_tracing(
    lt: &LightTracer,
    scene: &Scene,
    plan: &RenderPlan,
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
    let pair = PairWavelengths::new(plan, scene, settings.tracer.wavelengths);
    let flat = plan.flat_colour(scene, sensor.observer().as_ref(), &|l| pair.pdf(l));
    let mut film = FilmState::new(width, height, true);
    film.spectral = lt.spectral.map(|b| SpectralSums::new(b, width, height));
    let pass_spectral = lt.spectral.map(|b| SpectralFilm::new(b, width, height));
    let rays = AtomicU64::new(0);
    let pixel_max = PixelMaxY::new(width, height);
    let done = AtomicU64::new(0);
    let start = Instant::now();
    let mut spp_done = 0u32;
    let mut schedule = super::tiled::PassSchedule::new(settings.budget);
    let mut total_units = 0u64;
    let deadline = super::tiled::PassDeadline::new(settings.budget, start);
    let mut dropped_pass = None;
    while let Some(pass_spp) = schedule.next(spp_done, start.elapsed()) {
        let pass_start = Instant::now();
        let first = (settings.budget.first_sample() + spp_done) as u64 * pixels;
        let splats = SplatFilm::new(width, height);
        let count = pass_spp as u64 * pixels;
        let chunks = count.div_ceil(CHUNK);
        total_units += chunks;
        let cancelled = pool.install(|| {
            (0..chunks)
                .into_par_iter()
                .map(|c| {
                    if cancel.is_some_and(|f| f.load(Ordering::Relaxed))
                        || deadline.passed(spp_done)
                    {
                        return true;
                    }
                    let mut stats = PathStats::default();
                    let mut path = Vec::with_capacity(16);
                    let mut splat = |raster: Vec2, xyz: [f64; 3], e: &dyn Fn() -> LaneEnergies| {
                        pixel_max.record(raster.x, raster.y, xyz[1]);
                        // The film's guard refuses and counts NaN/Inf/negative contributions.
                        splats.splat_as(raster.x, raster.y, xyz, "lt light path (t = 1)");
                        if let Some(sf) = &pass_spectral {
                            sf.splat(raster.x, raster.y, &xyz, &e());
                        }
                    };
                    let lo = first + c * CHUNK;
                    let hi = (lo + CHUNK).min(first + count);
                    for k in lo..hi {
                        let mut ld =
                            PixelSampler::for_light_path(settings.sampler, settings.seed, k);
                        trace_light_path(
                            scene,
                            camera,
                            &sensor,
                            &pair,
                            lt,
                            &mut ld,
                            &mut path,
                            &mut stats,
                            &mut splat,
                            flat.as_ref(),
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
            if !cancel.is_some_and(|f| f.load(Ordering::Relaxed)) {
                dropped_pass = Some(super::render::DroppedPass {
                    spp: pass_spp,
                    after: pass_start.elapsed(),
                });
            }
            break;
        }
        let (sums, rejected) = splats.into_sums();
        film.add_splats(&sums);
        film.record_rejected(&rejected);
        if let (Some(pass), Some(sums)) = (&pass_spectral, &mut film.spectral) {
            pass.drain_into(sums);
        }
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
            dropped_pass,
        },
        strategy_images: Vec::new(),
        non_finite: film.rejected.total(),
        max_sample_y: pixel_max.values(),
        notes: Vec::new(),
        film,
    })
}
