//! A spot light whose spectrum is one delta line (`spd: "line:589"`, a sodium-like lamp) or one
//! narrow band (`gaussian:589:2`, 2 nm FWHM) must render with every integrator, all three
//! agreeing within 0.5%, at the colour of the spectral locus at 589 nm.
//! Before the wavelength mixture gave a lane drawn on a delta line the line's discrete
//! probability (instead of 0), and before path tracing drew from the lights' spectra when they
//! are narrowband, every integrator returned a black image for the line.
//!
//! Why they once agreed only within 2%: noise, not bias. Over 4 seeds at 256 spp the light
//! tracer's image mean scattered by σ ≈ 1.2% (pt 0.02%): half of its light paths drew their
//! wavelengths from the observer component of the mixture, which can never land on a line,
//! so they carried nothing. The render plan now draws every wavelength from the lights'
//! spectra when all emission is narrowband (and nothing fluoresces), which took lt's σ to
//! ≈ 0.35% at 256 spp (what is left is where its light paths land: with a point light 80% of
//! them miss the wall, so the lamp here is a spot whose cone lies inside the view).
//! Run: `cargo test --release -p spectrace --test render_line_emitters`.

use spectrace::color::xyz::chromaticity;
use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

fn scene(spd: &str) -> Scene {
    let text = format!(
        r#"(
        output: (spp: 16, max_depth: 4),
        materials: [ (name: "wall", type: "lambertian", params: (reflectance: 0.8)) ],
        objects: [ (name: "back", type: "quad", material: "wall",
             params: (corner: (-2.5, -2.5, -2), edge0: (5, 0, 0), edge1: (0, 5, 0))) ],
        lights: [ (name: "sodium", type: "spot",
                   params: (position: (0, 0, 0), target: (0, 0, -2), inner_angle: 30,
                            outer_angle: 40, power: 100, spd: "{spd}")) ],
        cameras: [ (name: "c", type: "perspective",
             params: (position: (0, 0, 3), look_at: (0, 0, -1), fov: 40, resolution: (16, 16))) ],
    )"#
    );
    let file = Path::new("line.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Image-mean Y and the mean Y of the four 8×8 tiles, one seed.
fn render(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> [f64; 5] {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: 4,
            ..PathTracer::default()
        },
    };
    let out = render_with(scene, &settings, kind, false, &|_, _| {}, None).unwrap();
    let img = &out.result.image;
    assert_eq!(img.non_finite_count(), 0, "{kind}: non-finite");
    let mut v = [0.0; 5];
    v[0] = img.mean_xyz()[1];
    for y in 0..16 {
        for x in 0..16 {
            let t = 1 + (y / 8) * 2 + x / 8;
            v[t] += img.xyz[y * 16 + x][1] / 64.0;
        }
    }
    v
}

/// Mean over seeds and the standard error of that mean, per quantity.
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

/// Quantities: image-mean Y and the mean Y of each 8×8 tile, each averaged over 16 seeds, for
/// pt (128 spp), bdpt (128 spp) and lt (1024 light paths per pixel) on a diffuse wall under a
/// 100 W spot light with a `line:589` and a `gaussian:589:2` spectrum. bdpt and lt must agree
/// with pt within 0.5% (the issue's demand), and the standard error of each difference
/// (from the seed spread) must be below 0.5%/3, so 0.5% is at least 3σ: a real offset of
/// 0.5% would not pass by luck. Measured: see the printed lines and the module docs. The mean's chromaticity must be that
/// of the monochromatic stimulus at 589 nm (CIE 1931) within 1e-4 for the line (the image is
/// one wavelength times a positive factor; only f32 accumulation separates them) and within
/// 2e-3 for the 2 nm band (its own spread along the locus).
#[test]
fn line_and_narrowband_lights_agree_in_all_integrators() {
    let cmf = CieObserverKind::Cie1931_2.get().xyz_bar(589.0);
    let locus = chromaticity(cmf);
    for (spd, xy_tol) in [("line:589", 1e-4), ("gaussian:589:2", 2e-3)] {
        let scene = scene(spd);
        let seeds: Vec<u64> = (1..=16).collect();
        let runs = |kind, spp| -> Vec<[f64; 5]> {
            seeds
                .iter()
                .map(|&s| render(&scene, kind, spp, s))
                .collect()
        };
        let (pt, pt_se) = mean_and_se(&runs(IntegratorKind::Pt, 128));
        assert!(pt[0] > 0.0, "{spd}: pt black image");
        for (kind, spp) in [(IntegratorKind::Bdpt, 128), (IntegratorKind::Lt, 1024)] {
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
                    "{spd} {kind} vs pt, {what}: {:+.3}% ± {:.3}%",
                    100.0 * diff,
                    100.0 * sigma
                );
                assert!(m[i] > 0.0, "{spd} {kind} {what}: black");
                assert!(
                    diff.abs() < 0.005,
                    "{spd} {kind} {what}: mean Y {} vs pt {} ({:+.3}%)",
                    m[i],
                    pt[i],
                    100.0 * diff
                );
                assert!(
                    3.0 * sigma < 0.005,
                    "{spd} {kind} {what}: standard error {:.3}% too large for a 0.5% test",
                    100.0 * sigma
                );
            }
        }
        for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt] {
            let settings = RenderSettings {
                sampler: Default::default(),
                budget: SampleBudget::Spp(64),
                seed: 9,
                threads: None,
                camera: None,
                tile_size: 16,
                tracer: PathTracer::default(),
            };
            let out = render_with(&scene, &settings, kind, false, &|_, _| {}, None).unwrap();
            let xy = chromaticity(out.result.image.mean_xyz());
            assert!(
                (xy.0 - locus.0).abs() < xy_tol && (xy.1 - locus.1).abs() < xy_tol,
                "{spd} {kind}: xy {xy:?} vs locus at 589 nm {locus:?}"
            );
        }
    }
}
