//! Independent wavelength-sampling strategies of the path tracer (uniform, visible-importance
//! and observer × emission), and of bdpt and light tracing (uniform, observer × emission),
//! estimate the same image: each lane divides by the density it was drawn with, so only the
//! noise may differ.

mod common_render;
use spectrace::integrator::{
    render, IntegratorKind, PathTracer, RenderSettings, SampleBudget, WavelengthSampling,
};
use spectrace::scene::{build_scene, default_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

fn mean_y_per_seed(w: WavelengthSampling) -> Vec<[f64; 3]> {
    let scene = default_scene().unwrap();
    (0..4)
        .map(|seed| {
            let settings = RenderSettings {
                // 32 spp: at 8 the blue channel's 4-seed standard error under observer ×
                // emission sampling (which puts few wavelengths where the Cornell light is
                // weak) was 0.36% of its mean, so the 1% cap below sat at 2.8σ and a chance
                // 3.6σ spread failed it; at 32 spp the cap is about 5σ.
                budget: SampleBudget::Spp(32),
                seed: 100 + seed,
                threads: Some(2),
                tracer: PathTracer {
                    wavelengths: w,
                    ..PathTracer::default()
                },
                ..RenderSettings::default()
            };
            let img = render(&scene, &settings, &|_, _| {}, None).unwrap().image;
            assert_eq!(img.non_finite_count(), 0);
            img.mean_xyz()
        })
        .collect()
}

/// The three channels of the mean XYZ of `a` and `b` (4 seeds each) agree within 5 standard
/// errors of the difference (seed-to-seed spread), at most 1% of the mean.
fn assert_agree(na: &str, a: &[[f64; 3]], nb: &str, b: &[[f64; 3]]) {
    for c in 0..3 {
        let mean = |v: &[[f64; 3]]| v.iter().map(|x| x[c]).sum::<f64>() / v.len() as f64;
        let var = |v: &[[f64; 3]], m: f64| {
            v.iter().map(|x| (x[c] - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64
        };
        let (ma, mb) = (mean(a), mean(b));
        // Standard error of the difference of the two 4-seed means, from the seeds' spread.
        let se = ((var(a, ma) + var(b, mb)) / 4.0).sqrt();
        // 5σ with a 4-seed variance estimate (Student t, 6 dof: p ≈ 0.002), plus a floor of
        // 1e-4 relative for f32 accumulation, and never looser than 1% of the mean.
        let tol = (5.0 * se + 1e-4 * ma).min(0.01 * ma);
        eprintln!(
            "channel {c}: {na} {ma:.6} {nb} {mb:.6} diff {:.2e} se {se:.2e} tol {tol:.2e}",
            (ma - mb).abs()
        );
        assert!(
            (ma - mb).abs() <= tol,
            "channel {c}: {na} {ma} vs {nb} {mb} (σ_diff {se})"
        );
    }
}

#[test]
fn visible_and_uniform_wavelength_sampling_agree() {
    let a = mean_y_per_seed(WavelengthSampling::Visible);
    let b = mean_y_per_seed(WavelengthSampling::Uniform);
    assert_agree("visible", &a, "uniform", &b);
}

// Observer × emission (the default) against uniform: on the Cornell box its density follows
// the light (none at 400 nm, most at 700 nm), the strongest departure from uniform of the
// three, so a density stored wrongly would show here first.
#[test]
fn product_and_uniform_wavelength_sampling_agree() {
    let a = mean_y_per_seed(WavelengthSampling::Product);
    let b = mean_y_per_seed(WavelengthSampling::Uniform);
    assert_agree("product", &a, "uniform", &b);
}

/// The Cornell box at 64×64 pixels (source: scenes/cornell_box.ron), so that bdpt's and the
/// light tracer's seeds cost about a second each.
fn small_cornell() -> Scene {
    let text = include_str!("../../scenes/cornell_box.ron");
    let from = "\"resolution\": [256.0, 256.0]";
    assert!(
        text.contains(from),
        "resolution pattern {from} not in the scene"
    );
    let text = text.replace(from, "\"resolution\": [64.0, 64.0]");
    let file = Path::new("cornell_box_64.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Mean XYZ of `kind`'s image of the small Cornell box with wavelength sampling `w`, seeds
/// 100–103 at `spp` each.
fn mean_xyz_per_seed_with(kind: IntegratorKind, spp: u32, w: WavelengthSampling) -> Vec<[f64; 3]> {
    let scene = small_cornell();
    (0..4)
        .map(|seed| {
            let settings = RenderSettings {
                budget: SampleBudget::Spp(spp),
                seed: 100 + seed,
                threads: Some(2),
                tracer: PathTracer {
                    wavelengths: w,
                    ..PathTracer::default()
                },
                ..RenderSettings::default()
            };
            let img = common_render::render(&scene, &settings, kind)
                .unwrap()
                .result
                .image;
            assert_eq!(img.non_finite_count(), 0);
            img.mean_xyz()
        })
        .collect()
}

// bdpt's pairs drawn from observer × √emission (the default) against uniform: both subpaths
// share the lanes, so a density stored wrongly, or one the MIS weights or the flat-path colour
// read differently from the film, would bias the image (tolerance as above: 5 standard errors
// of the 4-seed means, at most 1%).
#[test]
fn bdpt_product_and_uniform_wavelength_sampling_agree() {
    let a = mean_xyz_per_seed_with(IntegratorKind::Bdpt, 64, WavelengthSampling::Product);
    let b = mean_xyz_per_seed_with(IntegratorKind::Bdpt, 64, WavelengthSampling::Uniform);
    assert_agree("bdpt product", &a, "bdpt uniform", &b);
}

// The same for the light tracer, whose light paths draw their lanes the same way.
#[test]
fn lt_product_and_uniform_wavelength_sampling_agree() {
    let a = mean_xyz_per_seed_with(IntegratorKind::Lt, 128, WavelengthSampling::Product);
    let b = mean_xyz_per_seed_with(IntegratorKind::Lt, 128, WavelengthSampling::Uniform);
    assert_agree("lt product", &a, "lt uniform", &b);
}
