//! BDPT and light tracing on scenes with delta lights (a spot) and delta BSDFs (mirror, smooth
//! glass): no NaN/Inf, no firefly beyond a stated bound, per-strategy images summing to the
//! image, and bitwise determinism across thread counts.
//! Run: `cargo test --release -p spectrace --test integrators_robustness`
//! (`-- --ignored` adds the 10⁷-path runs).

use spectrace::integrator::{
    render_with, IntegratorKind, IntegratorOutput, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

fn small(text: &str, res: &str) -> Scene {
    let text = text.replace("resolution: (160, 120)", res);
    let file = Path::new("test.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn caustic() -> Scene {
    small(
        include_str!("../../scenes/caustic.ron"),
        "resolution: (40, 30)",
    )
}

fn spot_mirror() -> Scene {
    small(
        include_str!("../../scenes/spot_mirror.ron"),
        "resolution: (40, 30)",
    )
}

fn run(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    threads: usize,
    strat: bool,
) -> IntegratorOutput {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed: 11,
        threads: Some(threads),
        camera: None,
        tile_size: 8,
        tracer: PathTracer {
            max_depth: 16,
            ..PathTracer::default()
        },
    };
    render_with(scene, &settings, kind, strat, &|_, _| {}, None).unwrap()
}

/// Firefly bound: in every pixel whose mean Y is at least 1% of the image mean and which does
/// not look at a delta BSDF (see [`sees_no_delta_bsdf`]), no single
/// sample's contribution (luminance Y, before the 1/spp scaling) exceeds `FIREFLY_BOUND ×` that
/// pixel's mean. Correct weights stay below it (measured maxima 50 / 64 on spot_mirror /
/// caustic at 1.2·10⁶ path pairs, 105 / 70 at 10⁷; the maximum grows slowly with the number
/// of samples, as the tail of any Monte Carlo estimator does);
/// broken MIS weights, e.g. full weight on a camera path that found the tiny caustic lamp
/// through the glass (radiance 4.8·10⁵ against floor radiances of order 0.1–10), give samples
/// 10³–10⁵ times the pixel mean. Darker pixels are skipped: there a single legitimate rare path
/// can dominate the mean.
const FIREFLY_BOUND: f64 = 500.0;

/// Pixels whose footprint (3×3 points over the pixel and half its neighbours) sees no delta
/// BSDF directly. Through the glass the camera sees the floor's caustic: specular–diffuse–
/// specular paths that no BDPT connection can sample (only camera paths that happen to hit the
/// lamp), whose rare large samples are inherent to every unbiased estimator here; the firefly
/// bound is about MIS weights and is checked elsewhere.
fn sees_no_delta_bsdf(scene: &Scene) -> Vec<bool> {
    spectrace::analysis::specular_view_mask(scene)
        .into_iter()
        .map(|specular| !specular)
        .collect()
}

/// Luminance Y (film convention: `∫ L ȳ dλ / ∫ ȳ dλ`) of the caustic scene's lamp (object 3 of
/// scenes/caustic.ron), by a 1 nm midpoint sum over 360–830 nm.
fn caustic_lamp_y(scene: &Scene) -> f64 {
    let lamp = scene.objects.material(3);
    assert!(lamp
        .flags()
        .contains(spectrace::material::MaterialFlags::EMISSIVE));
    let sensor = spectrace::film::Sensor::new(scene.observer.clone());
    let (n, lo, hi) = (470usize, 360.0f32, 830.0f32);
    let mut y = 0.0;
    for k in 0..n {
        // One lane per 1 nm bin, density 1/(hi − lo): each to_xyz call is one MC term.
        let l = lo + (k as f32 + 0.5) * (hi - lo) / n as f32;
        let lambda = spectrace::spectrum::SampledWavelengths {
            lambda: [l; spectrace::spectrum::LANES],
            pdf: [1.0 / (hi - lo); spectrace::spectrum::LANES],
            lanes: spectrace::spectrum::LaneMask::ALL,
        };
        let le = lamp.emitted(
            glam::Vec3A::Z,
            &spectrace::material::ShadingContext::default(),
            &lambda,
        );
        y += sensor.to_xyz(&le, &lambda)[1] / n as f64;
    }
    y
}

/// Absolute firefly bound anywhere in the caustic image, glass pixels included: no single BDPT
/// sample's Y exceeds `LAMP_Y_BOUND ×` the lamp's luminance. On and through the glass the
/// camera sees the lamp by s = 0 paths only (weight 1), whose value is the camera throughput
/// (at most 1/(1 − 0.05) with Russian roulette that ignores refraction's 1/η², see
/// `bdpt::tests`) times the lamp's radiance, times the colour noise of one 4-lane spectral
/// estimate; measured 0.89× (1.2·10⁶ paths) and 1.21× (10⁷ paths), both the lamp's direct
/// reflection in the sphere. A roulette that counted the 1/η² of entering the glass as a loss
/// gave samples of 2.7× the lamp's Y through the sphere at 160×120 (pixel (80, 26), seed 0,
/// sample 92); at this test's 40×30 such paths happened not to be the largest sample, and the
/// sign of that bug here is the relative bound above (149.7 before, 68.2 after, at 10⁷ paths,
/// before BDPT took its first dimensions from the stratified sampler).
const LAMP_Y_BOUND: f64 = 2.0;

fn check_paths(scene: &Scene, name: &str, kind: IntegratorKind, spp: u32) {
    let out = run(scene, kind, spp, 2, false);
    let img = &out.result.image;
    let mean_y = img.mean_xyz()[1];
    let paths = out.result.samples;
    let mask = sees_no_delta_bsdf(scene);
    let mut worst = 0.0f64;
    for ((p, &m), &keep) in img.xyz.iter().zip(&out.max_sample_y).zip(&mask) {
        if keep && p[1] >= 0.01 * mean_y {
            worst = worst.max(m / p[1]);
        }
    }
    // Everywhere, including through the glass: the largest single sample (absolute Y).
    let (mut top, mut top_at) = (0.0f64, 0usize);
    for (i, &m) in out.max_sample_y.iter().enumerate() {
        if m > top {
            (top, top_at) = (m, i);
        }
    }
    eprintln!(
        "{name} {kind}: {paths} paths, non-finite {}, max over pixels of (largest sample Y / pixel mean Y) = {worst:.1}; largest sample anywhere Y = {top:.1} at pixel {top_at} (mean there {:.3})",
        out.non_finite, img.xyz[top_at][1],
    );
    assert_eq!(out.non_finite, 0, "{name} {kind}: NaN/Inf contributions");
    assert_eq!(img.non_finite_count(), 0);
    assert!(mean_y > 0.0);
    // Light tracing has no MIS weights to break, and its splats are legitimately sparse in
    // pixels lit only by long paths: the bound applies to BDPT.
    assert!(
        kind != IntegratorKind::Bdpt || worst <= FIREFLY_BOUND,
        "{name} {kind}: a sample of {worst} × its pixel mean"
    );
    if name == "caustic" && kind == IntegratorKind::Bdpt {
        let lamp_y = caustic_lamp_y(scene);
        eprintln!(
            "caustic lamp Y {lamp_y:.1}: largest sample {:.3} × that",
            top / lamp_y
        );
        assert!(
            top <= LAMP_Y_BOUND * lamp_y,
            "caustic bdpt: a sample of Y {top} > {LAMP_Y_BOUND} × the lamp's Y {lamp_y}"
        );
    }
}

/// 40·30·1000 = 1.2·10⁶ camera+light path pairs per scene for BDPT, as many light paths for LT.
#[test]
fn no_nan_no_fireflies_delta_lights_and_bsdfs() {
    for (name, scene) in [("spot_mirror", spot_mirror()), ("caustic", caustic())] {
        check_paths(&scene, name, IntegratorKind::Bdpt, 1000);
        check_paths(&scene, name, IntegratorKind::Lt, 1000);
    }
}

/// The same with 40·30·8334 ≈ 10⁷ path pairs per scene and integrator (minutes).
#[test]
#[ignore = "long: run with --ignored in release"]
fn no_nan_no_fireflies_ten_million_paths() {
    for (name, scene) in [("spot_mirror", spot_mirror()), ("caustic", caustic())] {
        check_paths(&scene, name, IntegratorKind::Bdpt, 8334);
        check_paths(&scene, name, IntegratorKind::Lt, 8334);
    }
}

/// The per-strategy images (each (s, t) with its MIS weight, plus one for longer paths) add up
/// to the combined image. Both are sums of the same f64 values in different groupings, the
/// strategy images in the splat film's 2⁻³² fixed point: per pixel the difference is bounded by
/// (number of contributions) × 2⁻³² / spp, far below the tolerance 1e-9 + 1e-9·|value|.
/// Also: strategies with s ≥ 1 and t ≥ 2 (connections) and s = 0 both contribute, i.e. the
/// images are not trivially one strategy.
#[test]
fn strategy_images_sum_to_the_image() {
    for scene in [spot_mirror(), caustic()] {
        let out = run(&scene, IntegratorKind::Bdpt, 8, 2, true);
        let img = &out.result.image;
        assert!(out.strategy_images.len() > 10);
        let mut sum = vec![[0.0f64; 3]; img.xyz.len()];
        let mut nonzero = 0;
        for (_, si) in &out.strategy_images {
            if si.mean_xyz()[1] > 0.0 {
                nonzero += 1;
            }
            for (acc, p) in sum.iter_mut().zip(&si.xyz) {
                for c in 0..3 {
                    acc[c] += p[c];
                }
            }
        }
        assert!(nonzero >= 3, "only {nonzero} strategies contribute");
        for (a, b) in sum.iter().zip(&img.xyz) {
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-9 + 1e-9 * b[c].abs(),
                    "{a:?} vs {b:?}"
                );
            }
        }
    }
}

/// Same seed, 1 or 2 threads: bitwise identical images (counter-based random numbers per
/// sample/light path, tiles merged in order, splats in fixed point).
#[test]
fn same_seed_same_image_any_thread_count() {
    let scene = caustic();
    for kind in [IntegratorKind::Bdpt, IntegratorKind::Lt] {
        let a = run(&scene, kind, 4, 1, false).result.image;
        let b = run(&scene, kind, 4, 2, false).result.image;
        assert_eq!(a.xyz, b.xyz, "{kind}");
    }
}
