//! The spectral film (`render --spectral-exr`): the XYZ integrated from its bins matches the
//! film's XYZ of the same samples, it does not change the XYZ image, it is the same bits for any
//! thread count, and its EXR opens in the Fichet–Pacanowski–Wilkie layout.
//! Run: `cargo test --release -p spectrace --test render_spectral_exr`

use spectrace::film::spectral::{SpectralBins, SpectralFilm, SpectralImage};
use spectrace::integrator::path::{render_film, render_film_spectral};
use spectrace::integrator::{PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A blackbody spot on a red-ish floor and a white wall, 16×10 pixels.
const SCENE: &str = r#"(
    observer: "cie1931-2",
    output: (spp: 8, max_depth: 5, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.6)),
        (name: "wall", type: "lambertian", params: (reflectance: 0.8)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2.5, 0, 2), edge0: (5, 0, 0), edge1: (0, 0, -4))),
        (name: "back", type: "quad", material: "wall",
         params: (corner: (-2.5, 0, -2), edge0: (5, 0, 0), edge1: (0, 3, 0))),
    ],
    lights: [
        (name: "spot", type: "spot",
         params: (position: (0, 2.5, 1.5), target: (0.5, 0.5, -1.0), inner_angle: 25,
                  outer_angle: 45, power: 300, spd: "blackbody:3200")),
    ],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 5), look_at: (0, 0.8, -1), fov: 40, resolution: (16, 10))),
    ],
)"#;

fn scene() -> Scene {
    let file = Path::new("spectral.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn settings(threads: usize) -> RenderSettings {
    RenderSettings {
        budget: SampleBudget::Spp(8),
        seed: 5,
        threads: Some(threads),
        camera: None,
        tile_size: 8,
        tracer: PathTracer {
            max_depth: 5,
            ..PathTracer::default()
        },
    }
}

fn render(bins: &str, threads: usize) -> (Vec<[f64; 3]>, SpectralImage, Scene) {
    let scene = scene();
    let b = SpectralBins::parse(bins).unwrap();
    let film = SpectralFilm::new(b, 16, 10);
    let (r, _) = render_film_spectral(
        &scene,
        &spectrace::effects::RenderPlan::auto(&scene),
        &settings(threads),
        &|_, _| {},
        None,
        Some(&film),
    )
    .unwrap();
    (r.image.xyz.clone(), film.image(), scene)
}

/// Relative difference of the image-total XYZ from the bins against the film's.
fn total_rel(film: &[[f64; 3]], img: &SpectralImage, scene: &Scene) -> [f64; 3] {
    let xyz = img.to_xyz(scene.observer.as_ref());
    [0, 1, 2].map(|c| {
        let a: f64 = xyz.iter().map(|p| p[c]).sum();
        let b: f64 = film.iter().map(|p| p[c]).sum();
        (a - b).abs() / b
    })
}

/// Quantity: image-total X, Y, Z integrated from the bins vs the film's, for the SAME samples.
/// They differ only by evaluating x̄ȳz̄ at the bin centre instead of at each sample's wavelength
/// (midpoint rule) and by samples outside the bins. Within a bin the sample sits anywhere, so
/// each sample's error is about |x̄′|·Δ/√12 relative to its value, of random sign: a few % for
/// Δ = 1 nm, divided by √(5120 lanes) gives σ ≈ 1e-4 (measured 0.5–2.2e-4 for 1 nm bins);
/// tolerance 1e-3 for 1 nm bins over 360–830 nm, 5e-3 for the default 5 nm bins over
/// 380–780 nm (σ ≈ 5×, plus the few samples outside 380–780). The exact identity (lanes at bin
/// centres, 1e-6) is the unit test in `film::spectral`.
#[test]
fn xyz_from_bins_matches_film_xyz() {
    let (film, img, scene) = render("360:830:1", 2);
    let rel = total_rel(&film, &img, &scene);
    assert!(
        rel.iter().all(|r| *r < 1e-3),
        "1 nm bins: relative XYZ differences {rel:?}"
    );
    let (film, img, scene) = render("380:780:5", 2);
    let rel = total_rel(&film, &img, &scene);
    assert!(
        rel.iter().all(|r| *r < 5e-3),
        "5 nm bins: relative XYZ differences {rel:?}"
    );
    assert!(img.values.iter().all(|v| v.is_finite() && *v >= 0.0));
    assert!(
        img.values.iter().any(|v| *v > 0.0),
        "spectral image is black"
    );
}

/// The spectral film is a passenger: the XYZ image with it equals the one without, bit for bit;
/// and the spectral image is the same bits for 1 and 2 threads (one thread owns a pixel's
/// tile and adds its samples in order). Also the EXR round trip (values are f32 in the file:
/// tolerance 1e-6 relative).
#[test]
fn spectral_film_is_deterministic_and_changes_nothing() {
    let scene = scene();
    let (plain, _) = render_film(&scene, &settings(2), &|_, _| {}, None).unwrap();
    let (with, img2, _) = render("380:780:5", 2);
    assert_eq!(
        plain.image.xyz, with,
        "XYZ image changed by the spectral film"
    );
    let (_, img1, _) = render("380:780:5", 1);
    assert_eq!(img1, img2, "spectral image depends on the thread count");
    let dir = std::env::temp_dir().join(format!("spectrace-spectral-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("s.exr");
    img2.write_exr(&p).unwrap();
    let back = SpectralImage::read_exr(&p).unwrap();
    assert_eq!(back.wavelengths, img2.wavelengths);
    for (a, b) in back.values.iter().zip(&img2.values) {
        assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
