//! What the visibility guide's tests share (`integrators_nee_guide`, on area lights, and
//! `integrators_nee_guide_env`, on environments): a path-traced render with the guide forced on
//! or off, and the two statistical comparisons of guided and uniform renders.
#![allow(dead_code)] // each test file uses a part

use glam::Vec2;
use spectrace::film::XyzImage;
use spectrace::integrator::nee_guide::CELLS;
use spectrace::integrator::select::render_planned;
use spectrace::integrator::{
    EffectsMode, EffectsRequest, IntegratorKind, PathTracer, RenderPlan, RenderSettings,
    SampleBudget, Switch,
};
use spectrace::scene::Scene;

/// Whether light sample coordinates `u` lie near a cell boundary of the guide's grid (within
/// 10⁻³ × `CELLS` cells of it), where the density recomputed from the light point may fall in
/// the neighbouring cell by rounding (such points are counted, not compared).
pub fn near_cell_edge(u: Vec2) -> bool {
    [u.x, u.y].iter().any(|c| {
        let x = c * CELLS as f32;
        (x - x.round()).abs() < 1e-3 * CELLS as f32
    })
}

/// Render `scene` by path tracing (`max_depth`, `spp` at `seed`, on `threads` or all) with the
/// guide forced on or off. The render must say that the guide is on exactly when forced on,
/// and give finite pixels only.
pub fn render(
    scene: &Scene,
    guide: bool,
    spp: u32,
    seed: u64,
    max_depth: u32,
    threads: Option<usize>,
) -> XyzImage {
    let plan = RenderPlan::new(
        scene,
        &EffectsRequest {
            mode: EffectsMode::Auto,
            forced: vec![(Switch::VisibilityGuide, guide)],
            ..Default::default()
        },
    );
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth,
            ..PathTracer::default()
        },
    };
    let out = render_planned(
        scene,
        &plan,
        &settings,
        IntegratorKind::Pt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap();
    assert_eq!(out.notes.len(), usize::from(guide), "{:?}", out.notes);
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image
}

/// The image's mean of Y.
pub fn mean_y(img: &XyzImage) -> f64 {
    img.xyz.iter().map(|p| p[1]).sum::<f64>() / img.xyz.len() as f64
}

/// Mean and sample standard deviation.
pub fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, var.sqrt())
}

/// Asserts that the image mean of Y over 16 seeds × `spp`, guided (seeds 1000…) and uniform
/// (seeds 2000…), agree within 4 standard errors of their difference, each side's error from
/// its 16 seed means; prints both and the difference in standard errors.
pub fn assert_guided_mean_equals_uniform(name: &str, scene: &Scene, spp: u32, depth: u32) {
    let (mut on, mut off) = (Vec::new(), Vec::new());
    for s in 0..16u64 {
        on.push(mean_y(&render(scene, true, spp, 1000 + s, depth, None)));
        off.push(mean_y(&render(scene, false, spp, 2000 + s, depth, None)));
    }
    let (m1, s1) = mean_sd(&on);
    let (m0, s0) = mean_sd(&off);
    let se = ((s1 * s1 + s0 * s0) / 16.0).sqrt();
    eprintln!(
        "{name}, depth {depth}: guided {m1:.6e} ± {:.1e}, uniform {m0:.6e} ± {:.1e}: {:.2} se",
        s1 / 4.0,
        s0 / 4.0,
        (m1 - m0) / se
    );
    assert!(
        (m1 - m0).abs() < 4.0 * se,
        "{name}, depth {depth}: guided {m1:.6e} vs uniform {m0:.6e}, {:.2} standard errors",
        (m1 - m0) / se
    );
}

/// The mean over pixels of the per-pixel variance of Y across 8 renders (16 spp, seeds
/// 300…307) at `depth`, guided or not, and the renders' wall-clock seconds.
pub fn per_pixel_variance(scene: &Scene, guide: bool, depth: u32) -> (f64, f64) {
    let t = std::time::Instant::now();
    let imgs: Vec<XyzImage> = (0..8)
        .map(|s| render(scene, guide, 16, 300 + s, depth, None))
        .collect();
    let secs = t.elapsed().as_secs_f64();
    let n = imgs[0].xyz.len();
    let var = (0..n)
        .map(|i| {
            mean_sd(&imgs.iter().map(|im| im.xyz[i][1]).collect::<Vec<_>>())
                .1
                .powi(2)
        })
        .sum::<f64>()
        / n as f64;
    (var, secs)
}
