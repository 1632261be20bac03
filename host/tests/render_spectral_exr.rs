//! The spectral film (`render --spectral-exr`) for path tracing, BDPT and light tracing: the XYZ
//! integrated from its nodes by the documented trapezoid rule equals the film's XYZ within
//! 1e-4 relative on a real render, it does not change the XYZ image, it is the same bits for any
//! thread count, and its EXR round-trips in the Fichet–Pacanowski–Wilkie layout.
//! Run: `cargo test --release -p spectrace --test render_spectral_exr`

use spectrace::film::spectral::{SpectralBins, SpectralImage};
use spectrace::film::XyzImage;
use spectrace::integrator::{
    render_with, render_with_options, IntegratorKind, IntegratorOptions, PathTracer,
    RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A blackbody spot on a red-ish floor and a white wall, 16×10 pixels.
const SCENE: &str = r#"(
    observer: "cie1931-2",
    output: (spp: 8, max_depth: 5, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: "colorchecker:15")),
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

const KINDS: [IntegratorKind; 3] = [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt];

fn scene() -> Scene {
    let file = Path::new("spectral.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn settings(threads: usize) -> RenderSettings {
    RenderSettings {
        sampler: Default::default(),
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

fn render(
    scene: &Scene,
    kind: IntegratorKind,
    bins: &str,
    threads: usize,
) -> (XyzImage, SpectralImage) {
    let options = IntegratorOptions {
        strategy_images: false,
        spectral: Some(SpectralBins::parse(bins).unwrap()),
    };
    let out =
        render_with_options(scene, &settings(threads), kind, options, &|_, _| {}, None).unwrap();
    let img = out.film.spectral_image().unwrap();
    (out.result.image, img)
}

/// Per channel, the largest relative difference of the XYZ integrated from the spectral image
/// against the film's, over the pixels whose film value is at least 1e-3 of the image's largest
/// (fainter pixels are held to 1e-4 of that largest value instead: relative error is
/// meaningless at 0), and the relative difference of the image totals.
fn worst_rel(film: &XyzImage, img: &SpectralImage, scene: &Scene) -> ([f64; 3], [f64; 3]) {
    let xyz = img.to_xyz(scene.observer.as_ref());
    let mut worst = [0.0f64; 3];
    let mut total = [0.0f64; 3];
    for c in 0..3 {
        let max = film.xyz.iter().map(|p| p[c]).fold(0.0, f64::max);
        assert!(max > 0.0, "channel {c} black");
        for (a, b) in xyz.iter().zip(&film.xyz) {
            let d = (a[c] - b[c]).abs() / b[c].max(1e-3 * max);
            worst[c] = worst[c].max(d);
        }
        let a: f64 = xyz.iter().map(|p| p[c]).sum();
        let b: f64 = film.xyz.iter().map(|p| p[c]).sum();
        total[c] = (a - b).abs() / b;
    }
    (worst, total)
}

fn sci(v: &[f64; 3]) -> String {
    format!("X {:.1e} Y {:.1e} Z {:.1e}", v[0], v[1], v[2])
}

/// Quantity: per pixel and image total, X, Y, Z integrated from a real 8 spp render's spectral
/// image (nodes 360:830:1, through the f32 EXR file) by the trapezoid rule, against the film's
/// XYZ, for PT, BDPT (camera film and t = 1 splats) and LT (splats). The tent weights and the
/// rule reproduce the observer's linear interpolation between its 1 nm table entries, so the
/// two agree to rounding (f32 storage: ~1e-7 relative); tolerance 1e-4 relative, the issue's
/// demand. With the default 5 nm nodes over 380–780 nm the rule interpolates x̄ȳz̄ linearly
/// between nodes and misses the light outside: the image totals then differ (measured
/// 0.7–2.4e-4 here; an estimate from x̄ȳz̄'s curvature over 5 nm gives up to ~1e-3 for spiky
/// spectra), tolerance 2e-3, printed for the record.
#[test]
fn xyz_from_nodes_matches_film_xyz() {
    let scene = scene();
    let dir = std::env::temp_dir().join(format!("spectrace-spectral-xyz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for kind in KINDS {
        let (film, img) = render(&scene, kind, "360:830:1", 2);
        let p = dir.join(format!("{kind}.exr"));
        img.write_exr(&p).unwrap();
        let back = SpectralImage::read_exr(&p).unwrap();
        assert_eq!(back.wavelengths.len(), 471);
        let (worst, total) = worst_rel(&film, &back, &scene);
        println!(
            "{kind}, 1 nm nodes: worst pixel {}, image total {}",
            sci(&worst),
            sci(&total)
        );
        assert!(
            worst.iter().chain(&total).all(|r| *r < 1e-4),
            "{kind}: 1 nm nodes: worst per pixel {worst:?}, totals {total:?}"
        );
        let (film, img) = render(&scene, kind, "380:780:5", 2);
        let (_, total) = worst_rel(&film, &img, &scene);
        println!(
            "{kind}, 5 nm nodes over 380-780 nm: image total {}",
            sci(&total)
        );
        assert!(
            total.iter().all(|r| *r < 2e-3),
            "{kind}: 5 nm nodes: totals {total:?}"
        );
        assert!(img.values.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The spectral film is a passenger: the XYZ image with it equals the one without, bit for bit;
/// and the spectral image is the same bits for 1 and 2 threads (exact sums), for PT, BDPT and
/// LT. Also the EXR round trip (values are f32 in the file: tolerance 1e-6 relative) and the
/// layout's header.
#[test]
fn spectral_film_is_deterministic_and_changes_nothing() {
    let scene = scene();
    let dir = std::env::temp_dir().join(format!("spectrace-spectral-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for kind in KINDS {
        let plain = render_with(&scene, &settings(2), kind, false, &|_, _| {}, None).unwrap();
        let (with, img2) = render(&scene, kind, "380:780:5", 2);
        assert_eq!(
            plain.result.image, with,
            "{kind}: XYZ image changed by the spectral film"
        );
        let (_, img1) = render(&scene, kind, "380:780:5", 1);
        assert_eq!(
            img1, img2,
            "{kind}: spectral image depends on the thread count"
        );
        let p = dir.join("s.exr");
        img2.write_exr(&p).unwrap();
        let back = SpectralImage::read_exr(&p).unwrap();
        assert_eq!(back.wavelengths, img2.wavelengths);
        for (a, b) in back.values.iter().zip(&img2.values) {
            assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
        }
        let bytes = std::fs::read(&p).unwrap();
        let has = |t: &str| bytes.windows(t.len()).any(|w| w == t.as_bytes());
        assert!(has("spectralLayoutVersion") && has("trapezoid rule") && has("S0.380,000000nm"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
