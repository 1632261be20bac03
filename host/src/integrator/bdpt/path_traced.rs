//! BDPT's light-subpath fraction `q = 0`: no light subpaths, every camera sample path traced.
//! In the limit `q → 0` BDPT's estimator keeps s = 0 and s = 1 alone, which the path tracer
//! (`super::super::path`) computes more cheaply, with its own MIS between them and its
//! visibility guide; so `q = 0` delegates the render to the path tracer, with BDPT's depth and
//! the path tracer's own roulette, wavelength sampling and guide (the guide BDPT built: its
//! pre-pass runs once).
//!
//! **When it may stand for BDPT** ([`refusal`]): only where path tracing samples every path
//! BDPT samples, so that `q = 0` never loses light. Not with
//! - a light that rays cannot hit (delta in position or direction: point, spot, photometric,
//!   directional; or a light without a surface) together with any surface with a delta lobe:
//!   paths light → specular → diffuse → camera then come from light subpaths alone (next-event
//!   estimation cannot pass the delta vertex, BSDF sampling cannot find the light);
//! - beams-only lights or fluorescence (the fraction stays 1: `fraction_stays_one`);
//! - `--strategy-images` (BDPT's per-strategy images);
//! - spectral lines in the lights while narrowband emission is off (the path tracer then draws
//!   no wavelength on a line).
//!
//! The specular-chain and camera-chain connections compete with s = 0 only, so the path
//! tracer's s = 0 makes their paths too; lens cameras, dispersion, thin films and the spectral
//! image are the path tracer's as well.
//!
//! Its wavelengths are the path tracer's own draws (observer × emission, or with
//! `narrowband-emission` half from the lights' spectra), not BDPT's pair; spectrally flat paths
//! get their emitter's exact colour there as in BDPT (`wavelengths::flat_colour`).
//!
//! **The pilot's estimate** ([`pilot`]): the path tracer on the same pilot pixels, samples and
//! seed as BDPT's pilot (fixed chunks reduced in order: the same at any thread count); per
//! camera sample its luminance `Y` (0 where the camera ray's first hit is an emitter, as BDPT's
//! pilot leaves those paths out) and its rays and shadow rays, priced by
//! [`PT_COST_WEIGHTS`](super::light_fraction::PT_COST_WEIGHTS).

use super::super::nee_guide::NeeGuide;
use super::super::path::{
    camera_sample, film_xyz, flat_colour, guide_notes, render_prepared, Prepared,
};
use super::super::pixel_max::PixelMaxY;
use super::super::render::{PathTracer, ProgressFn};
use super::super::wavelengths::groups::{PathWavelengthSampler, PathWavelengths};
use super::super::{PathStats, PixelSampler, RenderError, RenderSettings};
use super::light_fraction::{self, PartCost, PtPilotSums, PT_COST_WEIGHTS};
use crate::camera::manager::NamedCamera;
use crate::film::spectral::SpectralBins;
use crate::film::Sensor;
use crate::geometry::Ray;
use crate::integrator::driver::IntegratorOutput;
use crate::integrator::plan::RenderPlan;
use crate::scene::Scene;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// What of BDPT's settings the path tracer standing for it reads (BDPT hands them over, so
/// this module does not import its parent).
#[derive(Clone, Copy, Debug)]
pub struct BdptSettings {
    /// Maximum number of bounces of a full path.
    pub max_depth: u32,
    /// BDPT's per-strategy images were asked for.
    pub strategy_images: bool,
    /// The spectral image's nodes, if one is accumulated.
    pub spectral: Option<SpectralBins>,
}

/// Why the path tracer cannot stand for BDPT in `scene` (see the module docs), if it cannot.
/// `fraction_stays_one`'s reasons are checked by the caller first.
pub fn refusal(bdpt: &BdptSettings, scene: &Scene, plan: &RenderPlan) -> Option<&'static str> {
    if bdpt.strategy_images {
        return Some("--strategy-images asks for bdpt's per-strategy images");
    }
    let unreachable_light = scene
        .lights
        .lights()
        .iter()
        .any(|l| !l.flags().can_be_hit());
    let delta_surface = (0..scene.geometry.object_count() as u32)
        .any(|o| scene.objects.material(o).flags().is_specular());
    if unreachable_light && delta_surface {
        return Some(
            "a light that rays cannot hit (point, spot, photometric, directional) and a surface \
             with a delta (specular) lobe: paths light → specular → diffuse come from light \
             subpaths alone",
        );
    }
    if !scene.lights.delta_lines().is_empty() && !plan.emission_wavelengths() {
        return Some(
            "the lights have spectral lines and narrowband-emission is off: the path tracer \
             would draw no wavelength on a line",
        );
    }
    None
}

/// The path tracer's settings standing for `bdpt`: BDPT's depth, full transport (BDPT has no
/// direct-only mode), everything else as given (roulette as the path tracer reads it).
fn tracer(bdpt: &BdptSettings, settings: &RenderSettings) -> PathTracer {
    PathTracer {
        max_depth: bdpt.max_depth,
        direct_only: false,
        ..settings.tracer
    }
    .for_path_tracing()
}

/// True when `ray`'s first hit is an emitter (a surface with a light, or the environment on
/// escape): the camera sample the pilots leave out.
fn sees_emitter(scene: &Scene, ray: &Ray) -> bool {
    match scene.geometry.intersect(ray, f32::INFINITY) {
        Some(hit) => scene.lights.light_of_object(hit.object).is_some(),
        None => scene.lights.environment().is_some(),
    }
}

/// The path tracer's pilot sums (see the module docs) under the render's `guide`.
pub fn pilot_sums(
    bdpt: &BdptSettings,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &NamedCamera,
    guide: Option<&NeeGuide>,
) -> Result<PtPilotSums, RenderError> {
    let tracer = tracer(bdpt, settings);
    let (width, height) = cam.camera.resolution();
    let wavelengths = PathWavelengthSampler::new(
        plan,
        tracer.wavelengths,
        tracer.wavelengths_per_path,
        scene.objects.fluorescence(),
    )
    .map_err(RenderError::Setup)?;
    let sensor = Sensor::new(scene.observer.clone());
    // The render's flat-path colour (`path::render_prepared`), so the pilot sees its noise.
    let flat = flat_colour(scene, plan, &sensor, &wavelengths);
    let pool = super::super::tiled::thread_pool(settings.threads)?;
    let seed = light_fraction::pilot_seed(settings.seed);
    let pinhole = cam.camera.pinhole();
    Ok(light_fraction::run_pilot(&pool, width, height, |pixels| {
        let mut sums = PtPilotSums::default();
        let mut stats = PathStats::default();
        let mut lambdas = PathWavelengths::default();
        for &(x, y) in pixels {
            let pixel = y as u64 * width as u64 + x as u64;
            for si in 0..light_fraction::PILOT_SPP {
                // The path tracer's camera sample (`path::render_prepared`'s order of numbers).
                let mut rng = PixelSampler::with_kind(settings.sampler, seed, pixel, si);
                wavelengths.sample_into(&mut rng, &mut lambdas);
                let sample = camera_sample(cam, pinhole, &mut rng, (x, y));
                let before = stats;
                let lum = cam.camera.generate_ray(&sample).map_or(0.0, |r| {
                    let (flat, stats) = (flat.as_ref(), &mut stats);
                    let l =
                        tracer.li_film(scene, guide, flat, r.ray, &mut lambdas, &mut rng, stats);
                    if sees_emitter(scene, &r.ray) {
                        0.0
                    } else {
                        film_xyz(&sensor, &l, &lambdas, r.weight)[1]
                    }
                });
                let cost = PartCost {
                    rays: stats.rays - before.rays,
                    shadow_rays: stats.shadow_rays - before.shadow_rays,
                    connections: 0,
                };
                sums.add_sample(lum, cost);
            }
            sums.finish_pixel();
        }
        sums
    }))
}

/// The estimate of `q = 0` from [`pilot_sums`] and BDPT's pilot sums `bdpt_sums`, with the
/// path tracer's rays and shadow rays per camera sample.
#[allow(clippy::too_many_arguments)]
pub fn pilot(
    bdpt: &BdptSettings,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &NamedCamera,
    guide: Option<&NeeGuide>,
    bdpt_sums: &light_fraction::PilotSums,
) -> Result<(light_fraction::Estimate, (f64, f64)), RenderError> {
    let sums = pilot_sums(bdpt, scene, plan, settings, cam, guide)?;
    Ok((
        sums.estimate(&PT_COST_WEIGHTS, bdpt_sums),
        sums.counts_per_sample(),
    ))
}

/// Renders `scene` at `q = 0`: the path tracer's render with `bdpt`'s depth, the guide BDPT
/// built (`guide`), `before` (pilot and pre-pass) counted in its time, BDPT's outputs (the
/// largest sample luminance per pixel, the non-finite count, the spectral film) and `notes`
/// after the guide's.
#[allow(clippy::too_many_arguments)]
pub fn render(
    bdpt: &BdptSettings,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    (progress, cancel): (&ProgressFn<'_>, Option<&AtomicBool>),
    guide: Option<&NeeGuide>,
    before: Duration,
    notes: Vec<String>,
) -> Result<IntegratorOutput, RenderError> {
    let settings = RenderSettings {
        tracer: tracer(bdpt, settings),
        ..settings.clone()
    };
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let (width, height) = cam.camera.resolution();
    let pixel_max = PixelMaxY::new(width, height);
    let prepared = Prepared {
        guide,
        prepass: before,
        pixel_max: Some(&pixel_max),
    };
    let (result, film) = render_prepared(
        scene,
        plan,
        &settings,
        progress,
        cancel,
        bdpt.spectral,
        prepared,
    )?;
    let mut all = guide_notes(scene, guide);
    all.extend(notes);
    Ok(IntegratorOutput {
        result,
        strategy_images: Vec::new(),
        non_finite: film.rejected.total(),
        max_sample_y: pixel_max.values(),
        notes: all,
        film,
    })
}
