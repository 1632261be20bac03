//! Integrator behaviours that the image tests do not show directly: dispersion keeps only the
//! hero wavelength, time budgets stop and keep their work, and cancellation returns the partial
//! film.

use glam::Vec2;
use spectrace::camera::CameraSample;
use spectrace::integrator::{
    render, PathStats, PathTracer, PixelSampler, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::SampledWavelengths;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

fn glass_scene(ior: &str) -> Scene {
    let text = format!(
        r#"(
        materials: [
            (name: "glass", type: "dielectric", params: (ior: {ior})),
            (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 10)),
        ],
        objects: [
            (name: "ball", type: "sphere", material: "glass", params: (center: (0, 0, 0), radius: 1)),
            (name: "sky", type: "sphere", material: "lamp", params: (center: (0, 0, 0), radius: 20)),
        ],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 0, 5), look_at: (0, 0, 0), fov: 10, resolution: (8, 8)))],
    )"#
    );
    let desc = parse_scene_str(&text, Path::new("glass.ron")).unwrap();
    build_scene(
        &desc,
        Path::new("."),
        Path::new("glass.ron"),
        &[&BuiltinFactory],
    )
    .unwrap()
}

/// A path through dispersive glass (N-BK7) ends with the secondary lanes terminated (pdf 0,
/// hero pdf divided by the lane count); through constant-IOR glass all lanes survive. Checked
/// on a ray through the sphere's centre, which always hits the glass.
#[test]
fn dispersive_glass_terminates_secondary_wavelengths() {
    for (ior, dispersive) in [("\"N-BK7\"", true), ("1.5", false)] {
        let scene = glass_scene(ior);
        let cam = scene.cameras.get(None).unwrap();
        let ray = cam
            .camera
            .generate_ray(&CameraSample {
                p_film: Vec2::new(4.0, 4.0),
                p_lens: Vec2::splat(0.5),
            })
            .unwrap()
            .ray;
        let mut sampler = PixelSampler::new(1, 0, 0);
        let mut lambda = SampledWavelengths::sample_visible(0.37);
        let before = lambda;
        let mut stats = PathStats::default();
        let l = PathTracer::default().li(&scene, ray, &mut lambda, &mut sampler, &mut stats);
        assert!(!l.has_non_finite());
        assert_eq!(lambda.secondary_terminated(), dispersive, "ior {ior}");
        if dispersive {
            assert_eq!(lambda.pdf[0], before.pdf[0] / 4.0);
        } else {
            assert_eq!(lambda, before);
        }
    }
}

/// A time budget stops after at least one full pass, close to the budget (the pass in flight
/// finishes: allow 2 s of overshoot on a loaded CI machine), with a finite image; a pre-set
/// cancel flag returns at once with whatever exists (here nothing: 0 spp, black, finite).
#[test]
fn time_budget_and_cancellation() {
    let scene = glass_scene("1.5");
    let s = RenderSettings {
        budget: SampleBudget::Time(Duration::from_millis(200)),
        threads: Some(2),
        ..RenderSettings::default()
    };
    let r = render(&scene, &s, &|_, _| {}, None).unwrap();
    assert!(r.spp >= 1);
    assert!(r.elapsed < Duration::from_millis(2200), "{:?}", r.elapsed);
    assert_eq!(r.image.non_finite_count(), 0);
    let cancel = AtomicBool::new(true);
    let s = RenderSettings {
        budget: SampleBudget::Spp(1000),
        ..s
    };
    let r = render(&scene, &s, &|_, _| {}, Some(&cancel)).unwrap();
    assert_eq!(r.spp, 0);
    assert_eq!(r.image.non_finite_count(), 0);
}
