//! A light that only hands out beams (the seed's `next_beam`, flag BEAMS_ONLY, no evaluation)
//! renders through light tracing, in `lt` and inside `bdpt`, with the analytic brightness.
//! Run: `cargo test --release -p spectrace --test integrators_beams`.

use glam::{Vec2, Vec3A};
use spectrace::geometry::Ray;
use spectrace::integrator::{
    render_with, strategy_summary, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::light::LightSourceManager;
use spectrace::light::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::{BuiltinSpd, SampledSpectrum, SampledWavelengths, Spd};
use spectrace_plugin_api::{Beam, RandomSample, Vec3};
use std::path::Path;
use std::sync::Arc;

/// A laser of `power` W at `nm` nm: every beam starts at `origin` and goes along `dir`, so each
/// beam carries the full power (one sample of a delta distribution).
#[derive(Debug)]
struct TestLaser {
    origin: [f64; 3],
    dir: [f64; 3],
    nm: f64,
    power: f64,
    spd: Arc<dyn Spd>,
}

impl Light for TestLaser {
    fn flags(&self) -> LightFlags {
        LightFlags::BEAMS_ONLY
    }
    fn power(&self) -> f64 {
        self.power
    }
    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }
    fn sample_li(
        &self,
        _ctx: &LightSampleContext,
        _u: Vec2,
        _lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        None
    }
    fn pdf_li(&self, _ctx: &LightSampleContext, _p: Vec3A, _n: Vec3A) -> f32 {
        0.0
    }
    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }
    fn sample_le(&self, _u1: Vec2, _u2: Vec2, _l: &SampledWavelengths) -> Option<LightLeSample> {
        None
    }
    fn pdf_le(&self, _ray: &Ray, _n: Vec3A) -> (f32, f32) {
        (0.0, 0.0)
    }
    fn next_beam(&self, _u: &RandomSample) -> Option<Beam> {
        let [x, y, z] = self.origin;
        let [dx, dy, dz] = self.dir;
        Some(Beam {
            origin: Vec3::new(x, y, z),
            direction: Vec3::new(dx, dy, dz),
            wavelength_nm: self.nm,
            power_w: self.power,
            source_id: 0,
        })
    }
}

const RHO: f64 = 0.5;
const FOV_DEG: f64 = 30.0;
const RES: u32 = 33;

/// A large grey wall (reflectance ½) in the plane z = 0 facing +z, a camera at `cam` looking at
/// the origin, and the laser hitting the wall's origin head-on.
fn laser_scene(cam: [f64; 3]) -> Scene {
    let text = format!(
        r#"(
    observer: "cie1931-2",
    output: (spp: 4, max_depth: 8, rgb_space: "srgb"),
    materials: [ (name: "grey", type: "lambertian", params: (reflectance: {RHO})) ],
    objects: [ (name: "wall", type: "quad", material: "grey",
                params: (corner: (-5, -5, 0), edge0: (10, 0, 0), edge1: (0, 10, 0))) ],
    lights: [],
    cameras: [ (name: "c", type: "perspective",
                params: (position: ({}, {}, {}), look_at: (0, 0, 0), fov: {FOV_DEG},
                         resolution: ({RES}, {RES}))) ],
)"#,
        cam[0], cam[1], cam[2]
    );
    let file = Path::new("laser.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    let mut scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
    let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(3000.0).unwrap());
    let laser: Arc<dyn Light> = Arc::new(TestLaser {
        origin: [0.0, 0.0, 1.0],
        dir: [0.0, 0.0, -1.0],
        nm: 550.0,
        power: 2.0,
        spd,
    });
    scene.lights = LightSourceManager::new(vec![laser], scene.objects.len());
    scene
}

fn settings(spp: u32) -> RenderSettings {
    RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed: 5,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: 8,
            ..PathTracer::default()
        },
    }
}

/// Total Y over the image equals the analytic value: the lit point is a Lambertian point source
/// of intensity `I = ρ·P·cos θ_wall/π` seen from distance d on the optical axis; a pixel there
/// spans the solid angle `A_image/N` (A_image = 4·tan_x·tan_y at unit distance), so its mean
/// radiance is `I·N/(d²·A_image)`, and Y = that × ȳ(550 nm)/∫ȳ (film convention). Every beam
/// is deterministic here (radius 0, one wavelength), so the only errors are f32 rounding and the
/// fixed-point splat quantum: tolerance 1e-3 relative.
#[test]
fn beams_only_laser_matches_the_analytic_spot_brightness() {
    let cam = [0.0, 1.5, 4.0];
    let scene = laser_scene(cam);
    let d2: f64 = cam.iter().map(|c| c * c).sum();
    let cos_wall = cam[2] / d2.sqrt();
    let tan = (FOV_DEG.to_radians() / 2.0).tan();
    let a_image = 4.0 * tan * tan;
    let n = (RES * RES) as f64;
    let obs = spectrace::color::CieObserverKind::Cie1931_2.get().clone();
    use spectrace::color::Observer;
    let y_bar = obs.xyz_bar(550.0)[1] / obs.integral_y();
    let expected = RHO * 2.0 * cos_wall / std::f64::consts::PI * n / (d2 * a_image) * y_bar;
    for kind in [IntegratorKind::Lt, IntegratorKind::Bdpt] {
        let out = render_with(&scene, &settings(4), kind, false, &|_, _| {}, None).unwrap();
        let img = &out.result.image;
        let total: f64 = img.xyz.iter().map(|p| p[1]).sum();
        assert!(img
            .xyz
            .iter()
            .all(|p| p.iter().all(|v| v.is_finite() && *v >= 0.0)));
        assert!(
            (total / expected - 1.0).abs() < 1e-3,
            "{kind}: total Y {total} vs analytic {expected}"
        );
        // All of it lands on the centre pixel, where the camera looks.
        let centre = img.xyz[(RES / 2 * RES + RES / 2) as usize][1];
        assert!(
            (centre / total - 1.0).abs() < 1e-6,
            "{kind}: spot not centred"
        );
    }
    // Path tracing cannot see a beams-only light, and the summary says so.
    let pt = render_with(
        &scene,
        &settings(1),
        IntegratorKind::Pt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap();
    assert_eq!(pt.result.image.mean_xyz(), [0.0; 3]);
    let lines = strategy_summary(&scene, IntegratorKind::Pt);
    assert!(lines[0].contains("NOT rendered by pt"), "{lines:?}");
    let lines = strategy_summary(&scene, IntegratorKind::Bdpt);
    assert!(lines[0].contains("beams-only") && lines[0].contains("light tracing"));
}

/// A beams-only laser next to an ordinary point light of equal power: BDPT must render the
/// point light in full even on the pairs whose light subpath went to the laser (probability ½;
/// its next-event strategy does not need the light subpath). Off the laser's spot pixel the
/// image is the point light's alone, so BDPT and LT must match PT rendering the point light
/// alone. PT here is direct lighting of a plane, noisy only through the wavelength and filter
/// samples; LT's splats are noisier (half its paths go to the laser). At 512 spp on 33² pixels
/// the standard errors are a few 0.1% (LT's largest); tolerance 1.5% (a next-event estimate dropped with the laser's selection
/// probability would be off by 50%).
#[test]
fn beams_only_light_next_to_a_point_light() {
    let cam = [0.0, 1.5, 4.0];
    let mut scene = laser_scene(cam);
    let laser = scene.lights.lights()[0].clone();
    let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(4000.0).unwrap());
    let point: Arc<dyn Light> = Arc::new(spectrace::light::PointLight::new(
        Vec3A::new(0.5, 0.5, 1.0),
        spd,
        2.0,
    ));
    scene.lights = LightSourceManager::new(vec![laser, point.clone()], scene.objects.len());
    let centre = (RES / 2 * RES + RES / 2) as usize;
    let mean_off_spot = |img: &spectrace::film::XyzImage| -> f64 {
        let sum: f64 = img
            .xyz
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != centre)
            .map(|(_, p)| p[1])
            .sum();
        sum / (img.xyz.len() - 1) as f64
    };
    let expected = {
        let mut s = laser_scene(cam);
        s.lights = LightSourceManager::new(vec![point], s.objects.len());
        let out = render_with(
            &s,
            &settings(512),
            IntegratorKind::Pt,
            false,
            &|_, _| {},
            None,
        );
        mean_off_spot(&out.unwrap().result.image)
    };
    for kind in [IntegratorKind::Bdpt, IntegratorKind::Lt] {
        let out = render_with(&scene, &settings(512), kind, false, &|_, _| {}, None).unwrap();
        let y = mean_off_spot(&out.result.image);
        eprintln!("{kind}: mean Y off the spot {y} vs PT with the point light alone {expected}");
        assert!(
            (y / expected - 1.0).abs() < 0.015,
            "{kind}: {y} vs {expected}"
        );
    }
}
