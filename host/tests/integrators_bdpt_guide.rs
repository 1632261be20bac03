//! BDPT's s = 1 strategy (a fresh light point joined to camera vertex t) drawing its light
//! point with the path tracer's visibility guide (`integrator::nee_guide`), and the MIS weights
//! that carry the guide's factor wherever that strategy's density enters
//! (`integrator::bdpt::mis::s1_guide_factor`). On the bench's window room at 40 × 30 (a sky
//! panel seen through a window, the guide on by itself) and the Cornell box (the guide off by
//! itself).
//!
//! Run: `cargo test --release -p spectrace --test integrators_bdpt_guide`

mod common_nee_guide;

use common_nee_guide::mean_sd;
use spectrace::integrator::bdpt::{Bdpt, LIGHT_PATHS};
use spectrace::integrator::driver::{Integrator, IntegratorOutput};
use spectrace::integrator::{EffectsRequest, LightSubpaths, RenderPlan, SamplerKind, Switch};
use spectrace::integrator::{PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A scene file of `scenes/` with its resolution replaced.
fn scene(rel: &str, from: &str, to: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(rel);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{from} not in {rel}");
    let text = text.replace(from, to);
    let desc = parse_scene_str(&text, &path).unwrap();
    build_scene(&desc, path.parent().unwrap(), &path, &[&BuiltinFactory]).unwrap()
}

/// The window room at 40 × 30 pixels.
fn window_room() -> Scene {
    scene(
        "bench/window_room.ron",
        "resolution: (160, 120)",
        "resolution: (40, 30)",
    )
}

/// The Cornell box at 32 × 32 pixels.
fn cornell() -> Scene {
    scene(
        "cornell_box.ron",
        "\"resolution\": [256.0, 256.0]",
        "\"resolution\": [32.0, 32.0]",
    )
}

/// The window room with its sky panel replaced by the constant environment (D65,
/// 30 W/(m²·sr)) seen through the window, at 40 × 30: the guide's cells are patches of sky.
fn window_room_environment() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/bench/window_room.ron");
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in [
        ("resolution: (160, 120)", "resolution: (40, 30)"),
        (
            "lights: []",
            "lights: [(name: \"sky\", type: \"environment\", params: (radiance: \"d65\", scale: 30.0))]",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    // The sky panel's object goes (its name line and its parameters).
    let start = text.find("(name: \"sky\", type: \"quad\"").unwrap();
    let end = start + text[start..].find("0))),").unwrap() + "0))),".len();
    text.replace_range(start..end, "");
    let desc = parse_scene_str(&text, &path).unwrap();
    build_scene(&desc, path.parent().unwrap(), &path, &[&BuiltinFactory]).unwrap()
}

/// BDPT of `scene` at `spp` under `seed`; `guide`: `None` as the plan decides, else forced;
/// every camera sample traces its light subpaths (q = 1: no pilot, the same counts for both).
fn render(
    scene: &Scene,
    guide: Option<bool>,
    spp: u32,
    seed: u64,
    threads: Option<usize>,
) -> IntegratorOutput {
    let forced = guide.map_or_else(Vec::new, |on| vec![(Switch::VisibilityGuide, on)]);
    let plan = RenderPlan::new(
        scene,
        &EffectsRequest {
            forced,
            light_subpaths: LightSubpaths::Fraction(1.0),
            ..Default::default()
        },
    );
    let tracer = PathTracer {
        max_depth: scene.options.max_depth,
        ..Default::default()
    };
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        threads,
        camera: None,
        tile_size: 16,
        tracer,
        sampler: SamplerKind::default(),
    };
    Bdpt {
        max_depth: scene.options.max_depth,
        rr_depth: tracer.rr_depth,
        strategy_images: false,
        spectral: None,
        light_paths: LIGHT_PATHS,
    }
    .render(scene, &plan, &settings, &|_, _| {}, None)
    .unwrap()
}

/// Image mean of Y.
fn mean_y(o: &IntegratorOutput) -> f64 {
    common_nee_guide::mean_y(&o.result.image)
}

/// Mean and standard error of per-seed values.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let (m, sd) = mean_sd(v);
    (m, sd / (v.len() as f64).sqrt())
}

/// Asserts that `scene`'s guide is on with `guide` (None: the plan's own decision) and that
/// the image mean of Y over 16 seeds × 16 spp, guided (seeds 100…) and forced uniform (seeds
/// 200…), agree within 3 standard errors of their difference, each side's error from its 16
/// seed means; prints both and z under `what`.
fn assert_guided_mean_equals_uniform(what: &str, scene: &Scene, guide: Option<bool>) {
    let on = render(scene, guide, 1, 1, Some(2));
    assert!(
        on.notes.iter().any(|n| n.contains("visibility-guide on")),
        "{what}: the guide should be on: notes {:?}",
        on.notes
    );
    let (mut guided, mut uniform) = (Vec::new(), Vec::new());
    for seed in 0..16 {
        guided.push(mean_y(&render(scene, guide, 16, 100 + seed, None)));
        uniform.push(mean_y(&render(scene, Some(false), 16, 200 + seed, None)));
    }
    let (mg, sg) = mean_se(&guided);
    let (mu, su) = mean_se(&uniform);
    let z = (mg - mu) / (sg * sg + su * su).sqrt();
    eprintln!(
        "{what} bdpt mean Y: guided {mg:.6} ± {sg:.6}, uniform {mu:.6} ± {su:.6}, z = {z:.2}"
    );
    assert!(
        z.abs() < 3.0,
        "{what}: guided {mg} vs uniform {mu}: z = {z:.2}"
    );
}

/// Quantity: the whole image's mean Y of BDPT on the window room, guided (the plan's own
/// decision: on) and uniform (forced off), 16 seeds × 16 spp each, independent seeds.
/// Tolerance: 3 standard errors of the difference, each side's error from its 16 seed means
/// (a false alarm about 1 run in 370). Measured z = 1.2. Why it can fail: the guide changes
/// only the s = 1 strategy's density of its light point, and every strategy's weight must see
/// that density; with the factor left out of the other strategies' heuristic sums (kept in the
/// s = 1 strategy's own density) the guided mean came out 9% high, z = +37; with it left out
/// of the s = 1 strategy's own density only, 9% low, z = −39. (Left out of every weight alike,
/// the weights still sum to one: unbiased, caught by the variance test below.)
#[test]
fn guided_bdpt_mean_equals_uniform_mean() {
    let scene = window_room();
    assert_guided_mean_equals_uniform("window room", &scene, None);
}

/// Quantity: the guided BDPT image at 1 and at 2 threads, bit for bit (the pre-pass runs fixed
/// chunks reduced in order; the render's tiles are deterministic).
#[test]
fn guided_bdpt_is_the_same_at_any_thread_count() {
    let scene = window_room();
    let a = render(&scene, None, 4, 7, Some(1));
    let b = render(&scene, None, 4, 7, Some(2));
    assert!(a.notes.iter().any(|n| n.contains("visibility-guide on")));
    assert!(
        a.result.image.xyz == b.result.image.xyz,
        "1 and 2 threads differ"
    );
}

/// Quantity: the Cornell box's BDPT image as the plan decides (its lamp is visible from nearly
/// everywhere: the pre-pass keeps the guide off) and with the guide forced off, bit for bit;
/// and no guide note. The guided code path must leave unguided renders untouched.
#[test]
fn cornell_box_keeps_the_guide_off_and_the_same_image() {
    let scene = cornell();
    let auto = render(&scene, None, 4, 3, Some(2));
    let off = render(&scene, Some(false), 4, 3, Some(2));
    assert!(
        !auto.notes.iter().any(|n| n.contains("visibility-guide")),
        "notes {:?}",
        auto.notes
    );
    assert!(
        auto.result.image.xyz == off.result.image.xyz,
        "images differ"
    );
}

/// Mean over pixels of the per-pixel variance of Y across 16 seeds of `spp` each.
fn per_pixel_variance(scene: &Scene, guide: Option<bool>, spp: u32) -> f64 {
    let images: Vec<Vec<f64>> = (0..16)
        .map(|seed| {
            render(scene, guide, spp, 300 + seed, None)
                .result
                .image
                .xyz
                .iter()
                .map(|p| p[1])
                .collect()
        })
        .collect();
    let n = images.len() as f64;
    let pixels = images[0].len();
    (0..pixels)
        .map(|i| {
            let m = images.iter().map(|im| im[i]).sum::<f64>() / n;
            images.iter().map(|im| (im[i] - m).powi(2)).sum::<f64>() / (n - 1.0)
        })
        .sum::<f64>()
        / pixels as f64
}

/// Quantity: the mean over pixels of the per-pixel variance of Y across 16 seeds × 16 spp on
/// the window room, uniform (guide forced off) over guided (on by itself), both at q = 1.
/// Measured 2.23 (2.37 with another 16 seeds); with the guide's factor left out of every
/// weight (sampling guided, weights uniform: unbiased, but the heuristic then weighs the
/// s = 1 strategy by a density it does not have and hands the paths it samples well to the
/// camera paths that find the sky) 1.49 (1.55). Bound 1.85, between the two: the ratio moves
/// by about 6% between seed sets.
#[test]
fn guided_bdpt_lowers_the_variance() {
    let scene = window_room();
    let ratio = per_pixel_variance(&scene, Some(false), 16) / per_pixel_variance(&scene, None, 16);
    eprintln!("window room bdpt per-pixel variance uniform/guided: {ratio:.3}");
    assert!(ratio > 1.85, "variance ratio uniform/guided {ratio:.3}");
}

/// Quantity: the whole image's mean Y of BDPT on the fluorescence scene (`scenes/fluorescence.ron`
/// at 40 × 24: a UV lamp and a daylight panel over fluorescent patches, per-lane MIS weights
/// over both light-subpath modes, `bdpt/fluorescent_mis.rs`), the guide forced on (its lamps
/// are quads; unoccluded, so the learned densities follow the receivers' cosines, factors
/// between about 0.2 and 3) and forced off, 16 seeds × 16 spp, independent seeds. Tolerance: 3
/// standard errors of the difference. Why it can fail: the per-lane weights must carry the
/// guide's factor as the scalar ones do. Measured z = 0.5; with the factor left out of
/// the other strategies' sums there (kept in the s = 1 strategy's own density) 4.6% high,
/// z = +5.3.
#[test]
fn guided_fluorescent_bdpt_mean_equals_uniform_mean() {
    let scene = scene(
        "fluorescence.ron",
        "resolution: (160, 96)",
        "resolution: (40, 24)",
    );
    assert_guided_mean_equals_uniform("fluorescence", &scene, Some(true));
}

/// Quantity: as [`guided_bdpt_mean_equals_uniform_mean`], for the window room lit by the
/// constant environment through its window (the guide on by itself: the light vertex of a
/// path that escapes through the window, or of a light subpath from the sky, gives the guide
/// its direction). Tolerance: 3 standard errors of the difference. Measured z = 0.9; with
/// the factor left out of the other strategies' sums (kept in the s = 1 strategy's own density)
/// 74% high, z = +63.
#[test]
fn guided_bdpt_mean_equals_uniform_mean_under_an_environment() {
    let scene = window_room_environment();
    assert_guided_mean_equals_uniform("environment room", &scene, None);
}
