//! Rendering helpers of the integration tests: fixed-spp settings at the scene's own depth
//! ([`spp_settings`]), and BDPT's own estimator ([`every_light_subpath`], [`render`]).
//!
//! BDPT's pilot may hand every camera sample to
//! the path tracer where light subpaths do not pay (`--effect light-subpaths`, q = 0,
//! `host/src/integrator/bdpt/path_traced.rs`); a test about BDPT's estimator (its agreement
//! with pt or lt, its handling of a feature) would then compare the path tracer with itself.
//! So such tests render with light subpaths in every camera sample (`light-subpaths=1`; the
//! pilot still chooses how many where delta surfaces make caustics); for pt and lt the setting
//! changes nothing.
#![allow(dead_code)] // each test file uses a part

use spectrace::integrator::select::render_planned;
use spectrace::integrator::{
    EffectsRequest, IntegratorKind, IntegratorOutput, LightSubpaths, PathTracer, RenderError,
    RenderPlan, RenderSettings, SampleBudget,
};
use spectrace::scene::Scene;

/// The effects request of `--effect light-subpaths=1`, everything else automatic.
pub fn every_light_subpath() -> EffectsRequest {
    EffectsRequest {
        light_subpaths: LightSubpaths::Fraction(1.0),
        ..Default::default()
    }
}

/// `render_with(scene, settings, kind, false, …)` with BDPT tracing light subpaths in every
/// camera sample.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
) -> Result<IntegratorOutput, RenderError> {
    let plan = RenderPlan::new(scene, &every_light_subpath());
    render_planned(scene, &plan, settings, kind, false, &|_, _| {}, None)
}

/// A render of `spp` samples per pixel with `seed`, the path depth the scene declares, and the
/// defaults otherwise (all threads, 16-pixel tiles, the first camera, the Sobol' sampler).
pub fn spp_settings(scene: &Scene, spp: u32, seed: u64) -> RenderSettings {
    RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        tracer: PathTracer {
            max_depth: scene.options.max_depth,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    }
}
