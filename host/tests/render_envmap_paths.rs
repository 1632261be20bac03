//! Light paths that start on an environment map (`envmap`): light tracing, BDPT's light
//! subpaths and the light-tracing illuminance sensor draw the emitted direction from the map's
//! luminance distribution (`light::EnvironmentLight::sample_le`). Checked here on a
//! high-dynamic-range map with a small sun: LT and BDPT agree with PT region by region, the
//! sensors read the map's illuminance, and light tracing's variance is far below what uniform
//! emission gives on the same map. The maps are written as OpenEXR into a temporary directory.

mod common_render;
use glam::{Vec2, Vec3A};
use spectrace::integrator::{IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use spectrace::light::{
    EnvironmentLight, EnvironmentMap, EnvironmentRadiance, Light, LightSourceManager,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::sensor::{measure, Estimator, MeasureSettings};
use spectrace::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use spectrace::texture::image_file;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod common_quadrants;
mod common_sun_sky;
use common_sun_sky::write_sun_sky;

fn temp_dir(tag: &str) -> PathBuf {
    common_sun_sky::temp_dir("envpaths", tag)
}

/// A white floor with a grey sphere on it, seen from above, under the sun sky.
const SCENE: &str = r#"(
    materials: [(name: "white", type: "lambertian", params: (reflectance: 0.8)),
                (name: "grey", type: "lambertian", params: (reflectance: (rgb: (0.5, 0.4, 0.3))))],
    objects: [(name: "floor", type: "quad", material: "white",
               params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2))),
              (name: "ball", type: "sphere", material: "grey",
               params: (center: (0.1, 0.25, 0), radius: 0.25))],
    lights: [(name: "sky", type: "envmap", params: (file: "sky.exr", LIGHT_PARAMS))],
    cameras: [(name: "c", type: "pinhole",
               params: (position: (0, 3, 0.01), look_at: (0, 0, 0), fov: 20, resolution: (16, 16)))],
    sensors: [(name: "open", type: "illuminance_grid",
               params: (corner: (-0.98, 0.001, 0.98), edge0: (0.1, 0, 0), edge1: (0, 0, -0.1),
                        resolution: (2, 2)))],
)"#;

fn scene(dir: &Path, light_params: &str) -> Scene {
    let file = dir.join("scene.ron");
    let desc = parse_scene_str(&SCENE.replace("LIGHT_PARAMS", light_params), &file).unwrap();
    build_scene(&desc, dir, &file, &[&BuiltinFactory]).unwrap()
}

/// Film Y per pixel.
fn render(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> Vec<f64> {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 20,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = common_render::render(scene, &settings, kind).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image.xyz.iter().map(|p| p[1]).collect()
}

/// The map's radiance with the default (uniform) direction sampling of
/// [`EnvironmentRadiance`]: what light subpaths did before they followed the map.
#[derive(Debug)]
struct UniformlySampled(EnvironmentMap);

impl EnvironmentRadiance for UniformlySampled {
    fn radiance(&self, dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.0.radiance(dir, lambda)
    }
    fn spd(&self) -> Arc<dyn Spd> {
        self.0.spd()
    }
    fn mean_radiance(&self) -> f64 {
        self.0.mean_radiance()
    }
}

/// Light tracing, BDPT and PT see the same image: for each quadrant of the 16 × 16 image
/// (floor, ball and its shadow in varying shares), the mean of the per-pixel difference
/// LT − PT (and BDPT − PT) is within 4 standard errors of 0, the standard error taken from the
/// spread of those differences over the quadrant's 64 pixels (pixels are estimated from
/// independent samples, so the differences are independent with mean 0 when both are
/// unbiased; the spread includes no image structure). A wrong emission density (e.g. the
/// map's pdf without the disc's cos θ/πR², or a split `pdf_le` disagreeing with `sample_le`
/// in BDPT's MIS) scales or skews the light paths' share and moves these means by far more
/// than 4 SE: each SE is below 2% of the region's mean (asserted; light tracing needs 4096
/// paths per pixel for that: most light paths from the sky land outside the camera's view;
/// BDPT 1024 samples: at 64 its SE in the shadowed quadrant was 4.7%).
#[test]
fn light_paths_agree_with_path_tracing() {
    let dir = temp_dir("agree");
    write_sun_sky(&dir.join("sky.exr"));
    let s = scene(&dir, "scale: 1");
    let pt = render(&s, IntegratorKind::Pt, 256, 3);
    for (kind, spp) in [(IntegratorKind::Lt, 4096), (IntegratorKind::Bdpt, 1024)] {
        let img = render(&s, kind, spp, 5);
        common_quadrants::assert_quadrants_agree(&kind.to_string(), &img, &pt);
    }
}

/// The illuminance sensor's two estimators (sensor path tracing, used by PT and BDPT, and
/// light tracing, used by LT) read the map's `illuminance` on floor points at the corner away
/// from the ball (1.3 m off: it hides ~0.7% of the sky's cosine-weighted light, which is a
/// quarter of the total, the sun being the rest; and not the sun): each of 4 points within
/// 4 of its standard errors + 1% (the map's illuminance is a quadrature over its nodes; its
/// error on this 64 × 32 map with a 2 × 2-node sun is under 1%) of 5000 lx, each standard
/// error under 3% of it.
#[test]
fn sensors_read_the_maps_illuminance() {
    let dir = temp_dir("lux");
    write_sun_sky(&dir.join("sky.exr"));
    let s = scene(&dir, "illuminance: 5000");
    let grid = &s.sensors[0];
    for est in [Estimator::SensorPathTracing, Estimator::LightTracing] {
        let settings = MeasureSettings {
            estimator: est,
            samples: 20_000,
            seed: 9,
            threads: Some(2),
            tracer: PathTracer::default(),
        };
        let r = measure(&s, grid, &settings).unwrap();
        assert_eq!(r.non_finite, 0);
        for (k, (&lx, &se)) in r.lux.iter().zip(&r.stderr).enumerate() {
            eprintln!("{est:?} point {k}: {lx:.1} ± {se:.1} lx (want 5000)");
            assert!(se < 0.03 * 5000.0, "{est:?} point {k}: σ {se}");
            assert!(
                (lx - 5000.0).abs() < 4.0 * se + 50.0,
                "{est:?} point {k}: {lx} ± {se} lx, want 5000"
            );
        }
    }
}

/// The fix itself: light tracing on the sun sky with emission importance-sampled by the map
/// against the same map emitting uniformly over directions (the old behaviour, rebuilt here
/// around the same `EnvironmentMap`). Per-pixel variance estimated from two independent
/// renders of each (mean over pixels of (A − B)²/2, an unbiased estimate of the mean pixel
/// variance). The sun sends half the light from 0.3% of the directions at 300× the sky, so
/// uniform emission reaches it with 1 path in ~300 and each such path carries ~150× the mean
/// weight: its relative variance is tens of times larger. Required: uniform ÷ importance > 4
/// (a ratio of 1 means the sampling is uniform). The two means also agree (within 4 combined
/// SE), as both are unbiased.
#[test]
fn importance_sampled_emission_lowers_light_tracing_variance() {
    let dir = temp_dir("variance");
    write_sun_sky(&dir.join("sky.exr"));
    let sampled = scene(&dir, "scale: 1");
    let mut uniform = scene(&dir, "scale: 1");
    let (image, _) = image_file::load(&dir.join("sky.exr"), None).unwrap();
    let identity = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let map = EnvironmentMap::new("sky", image, &identity, 1.0).unwrap();
    let light = EnvironmentLight::new(Arc::new(UniformlySampled(map)));
    // The builder's bounds: the geometry's, and those grown by the camera positions.
    let bounds = uniform.geometry.bounds();
    let view = uniform
        .cameras
        .cameras()
        .iter()
        .fold(bounds, |b, c| b.grow(c.camera.position()));
    light.preprocess(&bounds);
    light.preprocess_view(&view);
    let lights: Vec<Arc<dyn Light>> = vec![Arc::new(light)];
    uniform.lights = LightSourceManager::new(lights, uniform.objects.len());
    // Same sphere, same power: only the sampling differs.
    assert_eq!(
        uniform.lights.lights()[0].power(),
        sampled.lights.lights()[0].power()
    );
    let lambda = SampledWavelengths::sample_visible(0.5);
    let probe = uniform.lights.lights()[0].sample_le(Vec2::splat(0.3), Vec2::splat(0.6), &lambda);
    assert!(probe.is_some());
    let stats = |s: &Scene| {
        let a = render(s, IntegratorKind::Lt, 128, 21);
        let b = render(s, IntegratorKind::Lt, 128, 22);
        let n = a.len() as f64;
        let var = a.iter().zip(&b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / (2.0 * n);
        let mean = a.iter().chain(&b).sum::<f64>() / (2.0 * n);
        (mean, var)
    };
    let (m_is, v_is) = stats(&sampled);
    let (m_u, v_u) = stats(&uniform);
    let n = 2.0 * 256.0;
    let tol = 4.0 * ((v_is + v_u) / n).sqrt();
    eprintln!(
        "LT mean Y: importance {m_is:.5}, uniform {m_u:.5}; mean pixel variance: importance {v_is:.3e}, uniform {v_u:.3e}, ratio {:.1}",
        v_u / v_is
    );
    assert!(
        (m_is - m_u).abs() < tol,
        "means {m_is} vs {m_u} (tolerance {tol})"
    );
    assert!(
        v_u > 4.0 * v_is,
        "uniform emission's variance {v_u:.3e} is not > 4 × the importance-sampled {v_is:.3e}"
    );
}
