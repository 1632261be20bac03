//! BDPT's light-tracing strategy (t = 1) with several light subpaths per camera sample
//! (`Bdpt::light_paths`, default `LIGHT_PATHS`): on the glass-sphere caustic
//! (`scenes/bench/glass_sphere.ron`) the core of the caustic on the floor is made almost
//! entirely by light tracing (`s = 4, t = 1`, see `integrators_caustic_mis.rs`), while one
//! camera sample of BDPT costs about four light paths of `lt` (callgrind, docs/performance.md).
//! With one light subpath per camera sample BDPT's efficiency in the core was 0.22× that of
//! light tracing; tracing `light_paths` light subpaths per camera sample, all joined to the
//! camera and counted `light_paths` times in the power heuristic, divides the variance of
//! that strategy by about `light_paths` for a fraction of the sample's cost.
//!
//! Run: `cargo test --release -p spectrace --test integrators_bdpt_light_paths` (about 10 s).

mod common_render;
use spectrace::integrator::bdpt::{light_paths_for, Bdpt, LIGHT_PATHS};
use spectrace::integrator::driver::{Integrator, IntegratorOutput};
use spectrace::integrator::{EffectsRequest, LightSubpathCount, LightSubpaths, RenderPlan};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

fn scene() -> Scene {
    let file = Path::new("glass_sphere.ron");
    let text = include_str!("../../scenes/bench/glass_sphere.ron");
    let desc = parse_scene_str(text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Core pixels of the caustic (x 63..=80, y 87..=90 of 160×120, as in
/// `integrators_caustic_mis.rs`: inside the part brighter than a quarter of its peak).
fn core_pixels() -> impl Iterator<Item = usize> {
    (87..=90).flat_map(|y| (63..=80).map(move |x| y * 160 + x))
}

/// BDPT with `light_paths` as its default count (`Bdpt::light_paths`), forced by the plan too
/// (`--effect light-subpath-count`) when `forced` (else the pilot may choose another).
fn render(scene: &Scene, light_paths: u32, spp: u32, seed: u64, forced: bool) -> IntegratorOutput {
    // Every camera sample traces its light subpaths (auto could path trace them all).
    let request = EffectsRequest {
        light_subpaths: LightSubpaths::Fraction(1.0),
        light_subpath_count: if forced {
            LightSubpathCount::Count(light_paths)
        } else {
            LightSubpathCount::Auto
        },
        ..Default::default()
    };
    let plan = RenderPlan::new(scene, &request);
    let settings = common_render::spp_settings(scene, spp, seed);
    let bdpt = Bdpt {
        max_depth: settings.tracer.max_depth,
        rr_depth: settings.tracer.rr_depth,
        strategy_images: false,
        spectral: None,
        light_paths,
    };
    bdpt.render(scene, &plan, &settings, &|_, _| {}, None)
        .unwrap()
}

/// Per-pixel variance of Y in the core from two seeds ((A − B)²/2 averaged over the pixels),
/// the core's mean Y, and the pixel count.
fn core_stats(a: &IntegratorOutput, b: &IntegratorOutput) -> (f64, f64, f64) {
    let (a, b) = (&a.result.image.xyz, &b.result.image.xyz);
    let n = core_pixels().count() as f64;
    let var = core_pixels()
        .map(|i| (a[i][1] - b[i][1]).powi(2) / 2.0)
        .sum::<f64>()
        / n;
    let mean = core_pixels().map(|i| a[i][1] + b[i][1]).sum::<f64>() / (2.0 * n);
    (var, mean, n)
}

/// Quantity: the caustic core's per-pixel variance at equal camera samples (16 spp), BDPT with
/// one light subpath per camera sample (the behaviour before) over BDPT with the default
/// `LIGHT_PATHS`, each variance from two seeds' images.
///
/// Expected: the core's value is ~95% light tracing (`integrators_caustic_mis.rs`), whose
/// variance falls by the factor `LIGHT_PATHS` = 4, so the ratio is about 1/(0.05 + 0.95/4)
/// ≈ 3.5; measured 2.8 with these seeds (and 3.8 on the mesh ball, four seeds at 64 spp).
/// A camera sample then costs 1.6× the instructions (callgrind, docs/performance.md), so
/// the efficiency gain is about 2.8/1.6 = 1.8. Limit 2.0: each 72-pixel variance estimate from
/// one seed pair scatters by about ±30% (heavier tails than Gaussian), so a ratio whose
/// expectation is 1 (one light subpath, the failure) stays under 2 practically always, and
/// 2.0 is a variance gain that pays for the cost. Also: the two core means within 4 standard
/// errors (the counts in the weights keep BDPT unbiased), and more rays traced (the extra
/// subpaths are really traced; rays are not the cost measure, a shadow ray to the lens costs
/// far fewer instructions than a random-walk step).
#[test]
fn more_light_paths_per_camera_sample_make_the_caustic_core_cheaper() {
    let scene = scene();
    let spp = 16;
    let one = [
        render(&scene, 1, spp, 1, true),
        render(&scene, 1, spp, 2, true),
    ];
    let many = [
        render(&scene, LIGHT_PATHS, spp, 1, true),
        render(&scene, LIGHT_PATHS, spp, 2, true),
    ];
    let (var_1, mean_1, n) = core_stats(&one[0], &one[1]);
    let (var_n, mean_n, _) = core_stats(&many[0], &many[1]);
    let rays = |o: &[IntegratorOutput; 2]| o[0].result.rays + o[1].result.rays;
    let (rays_1, rays_n) = (rays(&one), rays(&many));
    let ratio = var_1 / var_n;
    let se = (var_1 / (2.0 * n) + var_n / (2.0 * n)).sqrt();
    println!(
        "core: variance {var_1:.4} (1 light path) {var_n:.4} ({LIGHT_PATHS}), ratio {ratio:.2}; \
         rays ratio {:.2}; means {mean_1:.4} {mean_n:.4} ({:+.2} standard errors)",
        rays_n as f64 / rays_1 as f64,
        (mean_n - mean_1) / se
    );
    const { assert!(LIGHT_PATHS > 1, "the default traces one light subpath") };
    assert!(rays_n > rays_1, "the extra light subpaths trace no rays");
    assert!(
        ratio > 2.0,
        "the caustic core's variance only {ratio:.2}× lower than with one light subpath"
    );
    assert!(
        (mean_n - mean_1).abs() < 4.0 * se,
        "core means differ: {mean_n} against {mean_1} (standard error {se})"
    );
}

/// Quantity: the light subpaths per camera sample chosen for a scene, and the Cornell box's
/// image. A scene without delta surfaces (the Cornell box: all diffuse) gets one
/// (`light_paths_for`), so its image is bit-identical whatever `Bdpt::light_paths` (the
/// default count) says, the count not forced; the glass-sphere scene gets the setting.
/// Tolerance: none (the same computation).
#[test]
fn scenes_without_delta_surfaces_keep_one_light_path() {
    let file = Path::new("cornell_box.ron");
    let text = include_str!("../../scenes/cornell_box.ron");
    let desc = parse_scene_str(text, file).unwrap();
    let cornell = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
    assert_eq!(light_paths_for(&cornell, LIGHT_PATHS), 1);
    assert_eq!(light_paths_for(&scene(), LIGHT_PATHS), LIGHT_PATHS);
    let a = render(&cornell, 1, 1, 7, false);
    let b = render(&cornell, LIGHT_PATHS, 1, 7, false);
    assert!(a.result.image.xyz == b.result.image.xyz);
    assert_eq!(a.result.rays, b.result.rays);
}
