//! The image mean must not depend on the light-selection probabilities: next-event estimation
//! divides by the probability of the light it chose, and the MIS weights of light samples and
//! BSDF-found emission use the same probability, so any power-proportional (or other) choice
//! gives the same expected image. The tests render one scene twice per seed, once as built and
//! once with one light reporting a different power (everything else about it unchanged, see
//! [`ScaledPower`]), and compare the image means paired by seed.
//! Run: `cargo test --release -p spectrace --test integrators_light_selection`
//! (`-- --ignored --nocapture` for the long measurement on `scenes/materials.ron`, steered by
//! the environment variables FACTOR, DEPTH, SEEDS, SPP and KINDS).

use glam::{Vec2, Vec3A};
use spectrace::film::XyzImage;
use spectrace::geometry::{Aabb, Ray};
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::light::{
    Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext, LightSourceManager,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use std::path::Path;
use std::sync::Arc;

/// A light that behaves exactly like `inner` but reports `factor` times its power, so only the
/// light chooser's probabilities change.
#[derive(Debug)]
struct ScaledPower {
    inner: Arc<dyn Light>,
    factor: f64,
}

impl Light for ScaledPower {
    fn flags(&self) -> LightFlags {
        self.inner.flags()
    }
    fn power(&self) -> f64 {
        self.inner.power() * self.factor
    }
    fn spd(&self) -> Arc<dyn Spd> {
        self.inner.spd()
    }
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        self.inner.sample_li(ctx, u, lambda)
    }
    fn pdf_li(&self, ctx: &LightSampleContext, p: Vec3A, n: Vec3A) -> f32 {
        self.inner.pdf_li(ctx, p, n)
    }
    fn radiance(
        &self,
        p: Vec3A,
        n: Vec3A,
        uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        self.inner.radiance(p, n, uv, w, lambda)
    }
    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        self.inner.sample_le(u1, u2, lambda)
    }
    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        self.inner.pdf_le(ray, n)
    }
    fn escape_point(&self, ray: &Ray) -> Option<(Vec3A, Vec3A)> {
        self.inner.escape_point(ray)
    }
    fn object(&self) -> Option<u32> {
        self.inner.object()
    }
    fn preprocess(&self, b: &Aabb) {
        self.inner.preprocess(b)
    }
    fn preprocess_view(&self, b: &Aabb) {
        self.inner.preprocess_view(b)
    }
}

fn load(text: &str) -> Scene {
    let file = Path::new("test.ron");
    let desc = parse_scene_str(text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// `scene` with light `index`'s power (for selection only) scaled by `factor`.
fn with_scaled_power(scene: &Scene, index: usize, factor: f64) -> Scene {
    let lights: Vec<Arc<dyn Light>> = scene
        .lights
        .lights()
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i == index {
                Arc::new(ScaledPower {
                    inner: l.clone(),
                    factor,
                }) as Arc<dyn Light>
            } else {
                l.clone()
            }
        })
        .collect();
    let mut s = scene.clone();
    s.lights = LightSourceManager::new(lights, scene.objects.len());
    s
}

fn render(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64, max_depth: u32) -> XyzImage {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth,
            ..PathTracer::default()
        },
    };
    render_with(scene, &settings, kind, false, &|_, _| {}, None)
        .unwrap()
        .result
        .image
}

fn image_mean(img: &XyzImage) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in &img.xyz {
        for c in 0..3 {
            m[c] += p[c];
        }
    }
    m.map(|v| v / img.xyz.len() as f64)
}

fn mean_se(xs: &[f64]) -> (f64, f64) {
    let k = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / k;
    let v = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (k - 1.0);
    (m, (v / k).sqrt())
}

/// Paired per-seed relative differences `mean_B/mean_A − 1` of the image means, per channel.
fn paired_differences(
    a: &Scene,
    b: &Scene,
    kind: IntegratorKind,
    spp: u32,
    seeds: u64,
    max_depth: u32,
) -> [Vec<f64>; 3] {
    let mut d = [vec![], vec![], vec![]];
    for s in 0..seeds {
        let ia = image_mean(&render(a, kind, spp, 100 + s, max_depth));
        let ib = image_mean(&render(b, kind, spp, 100 + s, max_depth));
        for c in 0..3 {
            d[c].push(ib[c] / ia[c] - 1.0);
        }
    }
    d
}

/// A quad area light (D65) and a spot light (2856 K) over a diffuse floor and wall, a rough
/// conductor and a rough dielectric ball (both strategies of MIS matter there), 64×40 pixels.
const TWO_LIGHTS: &str = r#"(
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.6)),
        (name: "gold", type: "conductor", params: (metal: "gold", roughness: 0.2)),
        (name: "frosted", type: "rough_dielectric", params: (ior: 1.5, roughness: 0.3)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 400.0)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-3, 0, 3), edge0: (6, 0, 0), edge1: (0, 0, -6))),
        (name: "back", type: "quad", material: "floor",
         params: (corner: (-3, 0, -3), edge0: (6, 0, 0), edge1: (0, 4, 0))),
        (name: "gold_ball", type: "sphere", material: "gold", params: (center: (-0.6, 0.5, 0), radius: 0.5)),
        (name: "frosted_ball", type: "sphere", material: "frosted", params: (center: (0.6, 0.5, 0), radius: 0.5)),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.75, 3.5, -0.75), edge0: (1.5, 0, 0), edge1: (0, 0, 1.5))),
    ],
    lights: [
        (name: "spot", type: "spot",
         params: (position: (2, 3, 2), target: (0, 0, 0), inner_angle: 15, outer_angle: 25,
                  power: 1500, spd: "blackbody:2856")),
    ],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 6), look_at: (0, 0.6, 0), fov: 40, resolution: (64, 40))),
    ],
)"#;

/// Path tracing's image mean does not move when the area light's selection probability drops
/// from about 0.65 to 0.36 (its power for selection × 0.3). Quantity: per channel, the mean
/// over 24 seeds (32 spp, direct lighting: `max_depth` 1, where NEE and BSDF hits are weighed
/// against each other) of the paired relative difference of the image means. Tolerance: 4
/// standard errors of that mean (from the seed-to-seed spread; with 23 degrees of freedom
/// P(|t| > 4) ≈ 6e-4), and the standard error itself must be below 0.5% so the check has
/// teeth: a pmf used in NEE but not in the BSDF-hit MIS weight (or vice versa) shifts the mean
/// by several percent here.
#[test]
fn path_tracing_mean_does_not_depend_on_light_selection() {
    let a = load(TWO_LIGHTS);
    let quad = a
        .lights
        .lights()
        .iter()
        .position(|l| l.object().is_some())
        .unwrap();
    let b = with_scaled_power(&a, quad, 0.3);
    assert!((a.lights.pmf(quad) - b.lights.pmf(quad)).abs() > 0.25);
    let d = paired_differences(&a, &b, IntegratorKind::Pt, 32, 24, 1);
    for (c, dc) in d.iter().enumerate() {
        let (m, se) = mean_se(dc);
        println!("channel {c}: {:+.4}% ± {:.4}%", 100.0 * m, 100.0 * se);
        assert!(se < 0.005, "channel {c}: standard error {se} too large");
        assert!(
            m.abs() < 4.0 * se,
            "channel {c}: image mean moved by {:+.3}% ± {:.3}% when only the light-selection \
             probabilities changed",
            100.0 * m,
            100.0 * se
        );
    }
}

#[test]
#[ignore]
fn materials_scene_mean_does_not_depend_on_selection() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/materials.ron"),
    )
    .unwrap()
    .replace("resolution: (320, 200)", "resolution: (64, 40)");
    let a = load(&text);
    let quad = a
        .lights
        .lights()
        .iter()
        .position(|l| l.object().is_some())
        .unwrap();
    let factor: f64 = std::env::var("FACTOR")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.5);
    let depth: u32 = std::env::var("DEPTH")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let seeds: u64 = std::env::var("SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    let spp: u32 = std::env::var("SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(16);
    let b = with_scaled_power(&a, quad, factor);
    println!(
        "pmf A {:?}  pmf B {:?}",
        (0..a.lights.lights().len())
            .map(|i| a.lights.pmf(i))
            .collect::<Vec<_>>(),
        (0..b.lights.lights().len())
            .map(|i| b.lights.pmf(i))
            .collect::<Vec<_>>()
    );
    let kinds: Vec<IntegratorKind> = std::env::var("KINDS")
        .unwrap_or_else(|_| "pt".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    for kind in kinds {
        let mut d = [vec![], vec![], vec![]];
        let mut ma = [vec![], vec![], vec![]];
        for s in 0..seeds {
            let ia = image_mean(&render(&a, kind, spp, 100 + s, depth));
            let ib = image_mean(&render(&b, kind, spp, 100 + s, depth));
            for c in 0..3 {
                d[c].push(ib[c] / ia[c] - 1.0);
                ma[c].push(ia[c]);
            }
        }
        // Batches of 16 seeds, each judged like a 16-seed experiment: the spread of the batch
        // means against the SE each batch claims.
        for (c, dc) in d.iter().enumerate() {
            let zs: Vec<f64> = dc
                .chunks(16)
                .filter(|b| b.len() == 16)
                .map(|b| {
                    let (m, se) = mean_se(b);
                    m / se
                })
                .collect();
            let big = zs.iter().filter(|z| z.abs() > 3.0).count();
            let ms: Vec<f64> = dc
                .chunks(16)
                .filter(|b| b.len() == 16)
                .map(|b| mean_se(b).0)
                .collect();
            println!(
                "{kind} channel {c}: {} batches of 16: |z|>3 in {big}; max |z| {:.1}; sd of batch means {:.4}%, median claimed SE {:.4}%",
                zs.len(),
                zs.iter().fold(0.0f64, |a, z| a.max(z.abs())),
                100.0 * mean_se(&ms).1 * (ms.len() as f64).sqrt(),
                100.0 * {
                    let mut v: Vec<f64> = dc.chunks(16).filter(|b| b.len() == 16).map(|b| mean_se(b).1).collect();
                    v.sort_by(f64::total_cmp);
                    v[v.len() / 2]
                }
            );
        }
        for c in 0..3 {
            let (m, se) = mean_se(&d[c]);
            println!(
                "{kind} depth {depth} channel {c}: mean A {:.6}, paired rel diff (B/A-1) {:+.4}% ± {:.4}%  ({:.1}σ)",
                mean_se(&ma[c]).0,
                100.0 * m,
                100.0 * se,
                m / se
            );
        }
    }
}
