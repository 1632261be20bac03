//! BDPT takes every number of a camera sample from the pixel's stratified sampler (Sobol'
//! points in a fixed block of dimensions per walk and connection, `integrator/bdpt/dimensions.rs`):
//! the camera subpath's bounces, the light subpath's, next-event estimation (s = 1) and the
//! t = 1 lens points, not only the wavelengths, film, lens and light start.
//!
//! Run: `cargo test --release -p spectrace --test integrators_bdpt_stratified` (about 10 s).

use spectrace::integrator::bdpt::{Bdpt, LIGHT_PATHS};
use spectrace::integrator::driver::{Integrator, IntegratorOutput};
use spectrace::integrator::{EffectsRequest, LightSubpaths, RenderPlan, SamplerKind};
use spectrace::integrator::{PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// The window room of the bench suite (all diffuse, lit through a small opening), as shipped.
fn scene() -> Scene {
    let file = Path::new("window_room.ron");
    let text = include_str!("../../scenes/bench/window_room.ron");
    let desc = parse_scene_str(text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn render(scene: &Scene, sampler: SamplerKind, spp: u32, seed: u64) -> IntegratorOutput {
    render_on(scene, sampler, spp, seed, None)
}

/// BDPT with its light subpaths in 1/16 of the camera samples, on `threads` worker threads
/// (`None`: all).
fn render_on(
    scene: &Scene,
    sampler: SamplerKind,
    spp: u32,
    seed: u64,
    threads: Option<usize>,
) -> IntegratorOutput {
    // Light subpaths in 1/16 of the camera samples, what auto chose here before it could
    // path trace them all (q = 0).
    let request = EffectsRequest {
        light_subpaths: LightSubpaths::Fraction(0.0625),
        ..Default::default()
    };
    let plan = RenderPlan::new(scene, &request);
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        threads,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: scene.options.max_depth,
            ..PathTracer::default()
        },
        sampler,
    };
    let bdpt = Bdpt {
        max_depth: settings.tracer.max_depth,
        rr_depth: settings.tracer.rr_depth,
        strategy_images: false,
        spectral: None,
        light_paths: LIGHT_PATHS,
    };
    bdpt.render(scene, &plan, &settings, &|_, _| {}, None)
        .unwrap()
}

/// Mean over pixels of the per-pixel variance of Y (unbiased, across the seeds' images), and
/// each image's mean Y.
fn stats(images: &[IntegratorOutput]) -> (f64, Vec<f64>) {
    let k = images.len() as f64;
    let n = images[0].result.image.xyz.len();
    let var = (0..n)
        .map(|i| {
            let ys: Vec<f64> = images.iter().map(|o| o.result.image.xyz[i][1]).collect();
            let m = ys.iter().sum::<f64>() / k;
            ys.iter().map(|y| (y - m).powi(2)).sum::<f64>() / (k - 1.0)
        })
        .sum::<f64>()
        / n as f64;
    let means = images
        .iter()
        .map(|o| o.result.image.xyz.iter().map(|p| p[1]).sum::<f64>() / n as f64)
        .collect();
    (var, means)
}

/// Quantity: the per-pixel variance of Y at 16 spp on the window room, BDPT with
/// `--sampler independent` over BDPT with the Sobol' sampler, each from four seeds' images
/// (19 200 pixels × 3 degrees of freedom, so the pixel-averaged estimates scatter by a few
/// per cent; neighbouring pixels are correlated only through the scene).
///
/// Expected: measured 2.5× at 64 spp (before, when only the first requests were Sobol' and
/// every bounce and next-event estimate PCG: 1.01× at 64 spp, 0.99× at 16 spp; this scene is
/// lit indirectly, so the first bounces carry the noise); at 16 spp this test measures 1.88×.
/// Limit 1.45, about the geometric mean of 1.0 (numbers stratified only in the first
/// dimensions, the failure) and the measured ratio: room for the scatter of the estimate and
/// for changes of the scene's other noise either way.
///
/// Also: the image means of the two samplers agree within 4 standard errors (from the seeds'
/// scatter), so the stratified numbers move no mean.
#[test]
fn stratified_bounces_lower_bdpt_variance_on_diffuse_interreflection() {
    let scene = scene();
    let spp = 16;
    let seeds = 1..=4u64;
    let sobol: Vec<_> = seeds
        .clone()
        .map(|s| render(&scene, SamplerKind::Sobol, spp, s))
        .collect();
    let independent: Vec<_> = seeds
        .map(|s| render(&scene, SamplerKind::Independent, spp, s))
        .collect();
    let (var_s, means_s) = stats(&sobol);
    let (var_i, means_i) = stats(&independent);
    let ratio = var_i / var_s;
    let avg = |m: &[f64]| m.iter().sum::<f64>() / m.len() as f64;
    let sd = |m: &[f64]| {
        let a = avg(m);
        (m.iter().map(|x| (x - a).powi(2)).sum::<f64>() / (m.len() as f64 - 1.0)).sqrt()
    };
    let se = (sd(&means_s).powi(2) / 4.0 + sd(&means_i).powi(2) / 4.0).sqrt();
    let (ms, mi) = (avg(&means_s), avg(&means_i));
    println!(
        "variance independent {var_i:.4e}, sobol {var_s:.4e}, ratio {ratio:.2}; \
         means {ms:.6e} {mi:.6e} ({:+.2} standard errors)",
        (ms - mi) / se
    );
    assert!(
        ratio > 1.45,
        "BDPT with the Sobol' sampler only {ratio:.2}x less variance than independent numbers"
    );
    assert!(
        (ms - mi).abs() < 4.0 * se,
        "image means differ: {ms} (sobol) against {mi} (independent), standard error {se}"
    );
}

/// Quantity: the image of the same seed and spp rendered by BDPT with one thread and with
/// three, for both samplers, on a scene with several light subpaths per camera sample (the
/// glass sphere: its extra subpaths read their own blocks). Tolerance: bit equality (every
/// number is a pure function of seed, pixel, sample and dimension).
#[test]
fn stratified_bdpt_is_the_same_for_any_thread_count() {
    let file = Path::new("glass_sphere.ron");
    let text = include_str!("../../scenes/bench/glass_sphere.ron");
    let desc = parse_scene_str(text, file).unwrap();
    let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        let run = |threads| {
            render_on(&scene, sampler, 2, 5, Some(threads))
                .result
                .image
                .xyz
        };
        assert!(run(1) == run(3), "{sampler}: 1 and 3 threads differ");
    }
}
