//! BDPT and light tracing against path tracing through the dispersive N-SF11 prism.
//!
//! Why the bundled scenes/prism.ron is hard for this comparison: its light is a 1 cm slit behind
//! a 2 cm aperture, and path tracing reaches it only by BSDF sampling from the diffuse screen
//! through the prism (two specular refractions, the secondary wavelength lanes terminated at
//! the first) and the aperture onto the slit: a rare event with a large contribution, so the
//! estimate is heavy-tailed. BDPT and light tracing start at the slit and are fine there.
//! No estimator is at fault: what limits the comparison is the probability `p` that a
//! cosine-sampled direction from the screen passes both faces of the prism (incidence
//! between about 51° and 90° on each face, the only directions N-SF11 lets through both) and
//! then meets the light; the per-sample relative variance of the caustic is about `1/p`.
//!
//! The variant here keeps the screen, the prism and the camera's side of scenes/prism.ron and
//! replaces slit and baffle with a 0.54 m × 0.8 m D65 panel below-left of the prism, facing it
//! along the beam axis, so `p` is that of the prism's pass band itself (not the slit's tiny
//! share of it). The screen is lit directly as well as through the prism (dispersive events,
//! hero lane only); through the prism is where nearly all the variance is: with the glass
//! replaced by the screen's diffuse material the path tracer's per-tile standard error at 8
//! seeds × 1024 spp drops from 0.3–0.9% to 0.015–0.04%.
//! The image is 8×6 pixels (four 4×3 tiles) so that many samples per tile are cheap.
//!
//! Default suite: [`bdpt_and_lt_agree_with_pt_through_the_prism_within_noise`] (seconds).
//! Long runs (`#[ignore]`):
//! `cargo test --release -p spectrace --test effects_prism_agreement -- --ignored --nocapture`:
//! [`bdpt_and_lt_agree_with_pt_through_the_prism_within_half_a_percent`] (the issue's 0.5% with
//! 3σ < 0.5%, a few minutes) and [`bundled_prism_scene_long_run`] (scenes/prism.ron itself).

mod common_render;
use spectrace::integrator::{IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

const WIDE: &str = r#"(
    observer: "cie1931-2",
    output: (spp: 64, max_depth: 12, rgb_space: "srgb"),
    materials: [
        (name: "screen", type: "lambertian", params: (reflectance: 0.8)),
        (name: "glass", type: "dielectric", params: (ior: "N-SF11")),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 200.0)),
    ],
    objects: [
        (name: "screen", type: "quad", material: "screen",
         params: (corner: (1.0, -1.5, -0.6), edge0: (0, 0, 1.2), edge1: (0, 2.5, 0))),
        (name: "prism", type: "mesh", material: "glass",
         params: (
            positions: [(-0.2, 0, -0.25), (0.2, 0, -0.25), (0, 0.34641016, -0.25),
                        (-0.2, 0, 0.25), (0.2, 0, 0.25), (0, 0.34641016, 0.25)],
            indices: [(0, 2, 1), (3, 4, 5), (0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4),
                      (2, 0, 3), (2, 3, 5)],
         )),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.9, -0.6, -0.4), edge0: (0.3, 0.45, 0), edge1: (0, 0, 0.8))),
    ],
    cameras: [
        (name: "screen_view", type: "perspective",
         params: (position: (-0.2, -0.42, 0), look_at: (1.0, -0.42, 0), fov: 30,
                  resolution: (8, 6))),
    ],
)"#;

fn wide_scene() -> Scene {
    let file = Path::new("prism_wide.ron");
    let desc = parse_scene_str(WIDE, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// scenes/prism.ron with its camera at 16×12 pixels (the same view; each pixel the mean of
/// 10×10 of the bundled resolution), so that many samples per pixel are affordable.
fn bundled_scene() -> Scene {
    let text = include_str!("../../scenes/prism.ron").replace("(160, 120)", "(16, 12)");
    assert!(text.contains("(16, 12)"), "prism.ron's resolution changed");
    let file = Path::new("scenes/prism.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("scenes"), file, &[&BuiltinFactory]).unwrap()
}

/// Image-mean Y and the mean Y of the four quarter tiles, one seed.
fn render(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> [f64; 5] {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: 12,
            ..PathTracer::default()
        },
    };
    let out = common_render::render(scene, &settings, kind).unwrap();
    let img = &out.result.image;
    assert_eq!(img.non_finite_count(), 0, "{kind}: non-finite");
    let (w, h) = (img.width as usize, img.height as usize);
    let mut v = [0.0; 5];
    v[0] = img.mean_xyz()[1];
    for y in 0..h {
        for x in 0..w {
            let t = 1 + (2 * y / h) * 2 + 2 * x / w;
            v[t] += img.xyz[y * w + x][1] / (w * h / 4) as f64;
        }
    }
    v
}

/// Mean and standard error (seed spread) of each of the five quantities.
fn mean_and_se(runs: &[[f64; 5]]) -> ([f64; 5], [f64; 5]) {
    let k = runs.len() as f64;
    let mut m = [0.0; 5];
    let mut se = [0.0; 5];
    for i in 0..5 {
        m[i] = runs.iter().map(|r| r[i]).sum::<f64>() / k;
        let var = runs.iter().map(|r| (r[i] - m[i]).powi(2)).sum::<f64>() / (k - 1.0);
        se[i] = (var / k).sqrt();
    }
    (m, se)
}

/// Relative difference of each integrator of `others` to pt and its standard error (the two
/// runs' relative standard errors combined), printed: `(kind, quantity, diff, sigma)`.
fn compare(
    scene: &Scene,
    seeds: u64,
    pt_spp: u32,
    others: &[(IntegratorKind, u32)],
) -> Vec<(IntegratorKind, String, f64, f64)> {
    let runs =
        |kind, spp| -> Vec<[f64; 5]> { (1..=seeds).map(|s| render(scene, kind, spp, s)).collect() };
    let (pt, pt_se) = mean_and_se(&runs(IntegratorKind::Pt, pt_spp));
    let mut out = Vec::new();
    for &(kind, spp) in others {
        let (m, se) = mean_and_se(&runs(kind, spp));
        for i in 0..5 {
            let what = if i == 0 {
                "image".to_string()
            } else {
                format!("tile {i}")
            };
            let diff = m[i] / pt[i] - 1.0;
            let sigma = (se[i] / m[i]).hypot(pt_se[i] / pt[i]);
            eprintln!(
                "prism {kind} vs pt, {what}: {:+.3}% ± {:.3}% (pt {:.5} se {:.3}%, {kind} {:.5} se {:.3}%)",
                100.0 * diff,
                100.0 * sigma,
                pt[i],
                100.0 * pt_se[i] / pt[i],
                m[i],
                100.0 * se[i] / m[i]
            );
            out.push((kind, what, diff, sigma));
        }
    }
    out
}

/// Quantities: image-mean Y and each 4×3 tile's mean Y of the wide-source variant over 16
/// seeds (pt 1024 spp, bdpt 512, lt 2048 light paths per pixel; a few seconds). Tolerance:
/// bdpt and lt within 4 standard errors of pt (seeds' spread, both runs combined; measured
/// σ 0.3–2%), so a bias of a few percent in either fails here and the 0.5% claim is the long
/// run's; a 4σ bound is exceeded by chance with probability 6e-5 per quantity if the seeds'
/// spread is a good estimate. 16 seeds, not 8: the estimate through the prism is heavy-tailed,
/// and 8 seeds' spread can understate it (bdpt with its wavelengths from observer × √emission
/// gave +3.3% at an estimated σ of 0.8% in one tile over seeds 1–8, while 24 seeds of bdpt at
/// 512 spp and pt at 2048 agree in every tile within 0.6%, standard errors 0.2–0.8%).
#[test]
fn bdpt_and_lt_agree_with_pt_through_the_prism_within_noise() {
    let scene = wide_scene();
    let rows = compare(
        &scene,
        16,
        1024,
        &[(IntegratorKind::Bdpt, 512), (IntegratorKind::Lt, 2048)],
    );
    for (kind, what, diff, sigma) in rows {
        assert!(
            sigma < 0.03,
            "{kind} {what}: σ {:.3}% too large",
            100.0 * sigma
        );
        assert!(
            diff.abs() < 4.0 * sigma,
            "{kind} {what}: {:+.3}% beyond 4σ ({:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
    }
}

/// The issue's claim. Quantities: image-mean Y and each 4×3 tile's mean Y of the wide-source
/// variant over 16 seeds: pt 65536 spp, bdpt 49152 spp, lt 163840 light paths per pixel (sized
/// from the measured per-sample variances so every combined σ is below 0.167%). bdpt and lt
/// must be within 0.5% of pt and within 4σ, and σ < 0.5%/3 so that the 0.5% test can fail.
/// A few minutes on 2 cores: `#[ignore]`.
#[test]
#[ignore]
fn bdpt_and_lt_agree_with_pt_through_the_prism_within_half_a_percent() {
    let scene = wide_scene();
    let rows = compare(
        &scene,
        16,
        65536,
        &[(IntegratorKind::Bdpt, 49152), (IntegratorKind::Lt, 163840)],
    );
    for (kind, what, diff, sigma) in rows {
        assert!(
            3.0 * sigma < 0.005,
            "{kind} {what}: 3σ = {:.3}% is not below 0.5%",
            300.0 * sigma
        );
        assert!(diff.abs() < 0.005, "{kind} {what}: {:+.3}%", 100.0 * diff);
        assert!(
            diff.abs() < 4.0 * sigma,
            "{kind} {what}: {:+.3}% beyond 4σ ({:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
    }
}

/// scenes/prism.ron itself (16×12 pixels, 16 seeds; pt 16384 spp, bdpt 4096, lt 16384):
/// bdpt and lt must agree with pt within 4σ (seeds' spread). The path tracer's σ here is
/// large (it reaches the slit only through prism and aperture), so this run states the
/// numbers (printed) rather than the 0.5% claim, which the wide-source variant carries.
#[test]
#[ignore]
fn bundled_prism_scene_long_run() {
    let scene = bundled_scene();
    let rows = compare(
        &scene,
        16,
        16384,
        &[(IntegratorKind::Bdpt, 4096), (IntegratorKind::Lt, 16384)],
    );
    for (kind, what, diff, sigma) in rows {
        assert!(
            diff.abs() < 4.0 * sigma,
            "{kind} {what}: {:+.3}% beyond 4σ ({:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
    }
}
