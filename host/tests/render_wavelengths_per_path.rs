//! Wavelengths per path (1, 4, 8, 16) and light-SPD wavelength sampling in the path tracer:
//! every setting estimates the same image (each lane divides by the density it was drawn with,
//! dispersion keeps only the hero with its pdf divided by the 4G lanes the film averages), and
//! more wavelengths per path lower the colour noise of one sample.

use ron::Value;
use spectrace::integrator::{
    render, PathTracer, RenderError, RenderSettings, SampleBudget, WavelengthSampling,
};
use spectrace::scene::{
    build_scene, cornell_box_description, default_scene, parse_scene_str, BuiltinFactory, Scene,
};
use std::path::Path;

/// Mean XYZ of the whole image for each of `seeds` independent renders at `spp`.
fn seed_means(scene: &Scene, tracer: PathTracer, seeds: u64, spp: u32) -> Vec<[f64; 3]> {
    (0..seeds)
        .map(|seed| {
            let settings = RenderSettings {
                budget: SampleBudget::Spp(spp),
                seed: 500 + seed,
                threads: Some(2),
                tracer,
                ..RenderSettings::default()
            };
            let img = render(scene, &settings, &|_, _| {}, None).unwrap().image;
            assert_eq!(img.non_finite_count(), 0);
            img.mean_xyz()
        })
        .collect()
}

/// Asserts that two sets of per-seed image means estimate the same value in every channel.
/// Tolerance: 5 standard errors of the difference of the two means, estimated from the seeds'
/// spread (Student t with 2(n−1) ≥ 10 dof: a false alarm has p ≈ 0.002), plus 1e-4 relative for
/// f32 accumulation. The test also requires that standard error to be below 1% of the mean, so
/// a noisy run cannot pass by a wide tolerance alone.
fn assert_same_estimate(label: &str, a: &[[f64; 3]], b: &[[f64; 3]]) {
    for c in 0..3 {
        let mean = |v: &[[f64; 3]]| v.iter().map(|x| x[c]).sum::<f64>() / v.len() as f64;
        let var = |v: &[[f64; 3]], m: f64| {
            v.iter().map(|x| (x[c] - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64
        };
        let (ma, mb) = (mean(a), mean(b));
        let se = (var(a, ma) / a.len() as f64 + var(b, mb) / b.len() as f64).sqrt();
        let tol = 5.0 * se + 1e-4 * ma.abs();
        eprintln!(
            "{label} channel {c}: {ma:.6} vs {mb:.6} diff {:.2e} se {se:.2e} tol {tol:.2e}",
            (ma - mb).abs()
        );
        assert!(
            se < 0.01 * ma.abs(),
            "{label} channel {c}: too noisy (se {se}, mean {ma})"
        );
        assert!(
            (ma - mb).abs() <= tol,
            "{label} channel {c}: {ma} vs {mb} (σ_diff {se})"
        );
    }
}

fn tracer(sampling: WavelengthSampling, per_path: u32) -> PathTracer {
    PathTracer {
        wavelengths: sampling,
        wavelengths_per_path: per_path,
        ..PathTracer::default()
    }
}

/// The measured Cornell box at 64×64 pixels (the image mean is the film-plane average of
/// radiance at any resolution; fewer pixels keep the test fast).
fn small_cornell() -> Scene {
    let mut desc = cornell_box_description().unwrap();
    if let Value::Map(m) = &mut desc.cameras[0].params {
        m.insert(
            Value::String("resolution".into()),
            Value::Seq(vec![Value::Number(64.into()), Value::Number(64.into())]),
        );
    }
    build_scene(&desc, Path::new("."), Path::new("test"), &[&BuiltinFactory]).unwrap()
}

/// The measured Cornell box: N = 1, 8, 16 and light-SPD sampling (N = 4 and 16) give the same
/// image mean as the default (visible importance, N = 4).
#[test]
fn cornell_box_same_estimate_for_every_setting() {
    let scene = small_cornell();
    let base = seed_means(&scene, PathTracer::default(), 10, 16);
    for (sampling, n) in [
        (WavelengthSampling::Visible, 1),
        (WavelengthSampling::Visible, 8),
        (WavelengthSampling::Visible, 16),
        (WavelengthSampling::LightSpd, 4),
        (WavelengthSampling::LightSpd, 16),
    ] {
        let other = seed_means(&scene, tracer(sampling, n), 10, 16);
        assert_same_estimate(&format!("cornell {sampling} N={n}"), &base, &other);
    }
}

/// A dispersive N-BK7 sphere filling most of the frame in front of a D65 emitting backdrop (seen
/// through the glass by purely specular paths, so every such path goes hero-only), on a coloured
/// floor lit by a 2856 K blackbody spot light (two different SPDs for light-SPD sampling).
fn dispersive_scene() -> Scene {
    let text = r#"(
        observer: "cie1931-2",
        output: (spp: 4, max_depth: 12, rgb_space: "srgb"),
        materials: [
            (name: "floor", type: "lambertian", params: (reflectance: "colorchecker:13")),
            (name: "glass", type: "dielectric", params: (ior: "N-BK7")),
            (name: "backdrop", type: "emissive", params: (radiance: "d65", scale: 100.0)),
        ],
        objects: [
            (name: "floor", type: "quad", material: "floor",
             params: (corner: (-3, -1, 3), edge0: (6, 0, 0), edge1: (0, 0, -6))),
            (name: "backdrop", type: "quad", material: "backdrop",
             params: (corner: (-3, -1, -2), edge0: (6, 0, 0), edge1: (0, 5, 0))),
            (name: "ball", type: "sphere", material: "glass",
             params: (center: (0, 0, 0), radius: 1)),
        ],
        lights: [
            (name: "spot", type: "spot",
             params: (position: (2, 2, 2), target: (0, -1, 0), inner_angle: 20, outer_angle: 30,
                      power: 400, spd: "blackbody:2856")),
        ],
        cameras: [(name: "c", type: "perspective",
                   params: (position: (0, 0.3, 4), look_at: (0, 0, 0), fov: 35,
                            resolution: (48, 36)))],
    )"#;
    let desc = parse_scene_str(text, Path::new("dispersive.ron")).unwrap();
    build_scene(
        &desc,
        Path::new("."),
        Path::new("dispersive.ron"),
        &[&BuiltinFactory],
    )
    .unwrap()
}

/// Dispersion stays unbiased with several groups: N = 1, 8, 16 and light-SPD sampling agree
/// with N = 4 on a scene seen mostly through dispersive glass (where all lanes but the hero end
/// and the hero's pdf is divided by 4G).
#[test]
fn dispersive_glass_same_estimate_for_every_setting() {
    let scene = dispersive_scene();
    let base = seed_means(&scene, PathTracer::default(), 6, 16);
    for (sampling, n) in [
        (WavelengthSampling::Visible, 1),
        (WavelengthSampling::Visible, 8),
        (WavelengthSampling::Visible, 16),
        (WavelengthSampling::Uniform, 8),
        (WavelengthSampling::LightSpd, 8),
    ] {
        let other = seed_means(&scene, tracer(sampling, n), 6, 16);
        assert_same_estimate(&format!("dispersive {sampling} N={n}"), &base, &other);
    }
}

/// Variance over the pixels of a block of the Cornell box's back wall of the chromaticity
/// (x, y) of a 1-spp image: within the block the pixels are independent samples of nearly the
/// same colour, so this is the colour noise of one sample.
fn chromaticity_variance(scene: &Scene, n: u32) -> f64 {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(1),
        seed: 21,
        threads: Some(2),
        tracer: tracer(WavelengthSampling::Visible, n),
        ..RenderSettings::default()
    };
    let img = render(scene, &settings, &|_, _| {}, None).unwrap().image;
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    let (w, h) = (img.width as usize, img.height as usize);
    // The middle of the back wall: the central third horizontally, upper-middle vertically.
    for py in h * 3 / 10..h / 2 {
        for px in w / 3..2 * w / 3 {
            let [x, y, z] = img.xyz[py * w + px];
            let s = x + y + z;
            if s > 0.0 {
                xs.push(x / s);
                ys.push(y / s);
            }
        }
    }
    let var = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        v.iter().map(|a| (a - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64
    };
    assert!(xs.len() > 1000, "{} lit pixels", xs.len());
    var(&xs) + var(&ys)
}

/// More wavelengths per path lower the colour noise of one sample: the chromaticity variance
/// of the block falls from N = 1 to 4 to 16. Measured ratios are far larger than the bounds
/// asserted here (see the eprintln output); the bounds only demand a clear drop at each step,
/// well outside the ~10% sampling error of a variance from >1000 pixels.
#[test]
fn more_wavelengths_lower_colour_noise() {
    let scene = default_scene().unwrap();
    let v1 = chromaticity_variance(&scene, 1);
    let v4 = chromaticity_variance(&scene, 4);
    let v16 = chromaticity_variance(&scene, 16);
    eprintln!("chromaticity variance: N=1 {v1:.3e}, N=4 {v4:.3e}, N=16 {v16:.3e}");
    assert!(v1 > 2.0 * v4, "N=1 {v1} vs N=4 {v4}");
    assert!(v4 > 1.5 * v16, "N=4 {v4} vs N=16 {v16}");
}

/// An unsupported wavelength count is a setup error that names the value, not a panic.
#[test]
fn bad_wavelength_count_is_an_error() {
    let scene = default_scene().unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(1),
        tracer: tracer(WavelengthSampling::Visible, 6),
        ..RenderSettings::default()
    };
    match render(&scene, &settings, &|_, _| {}, None) {
        Err(RenderError::Setup(m)) => assert!(m.contains('6'), "{m}"),
        other => panic!("expected a setup error, got {:?}", other.map(|r| r.spp)),
    }
}
