//! Photometric light parameters (`flux_lm`, `intensity_cd`, `illuminance_lx`,
//! `luminance_cd_m2`) against analytic values: the power a light reports, and the lux and
//! cd/m² a render measures.
//!
//! A render measures photometric quantities through the film's Y: the film stores
//! Y = Σ L(λ)·ȳ(λ) / Σ ȳ over the observer's 1 nm grid (CIE 1931 2° here), so the luminance of
//! a pixel is Lv = Km · Y · Σ ȳ (cd/m², Km = 683.002 lm/W), and a Lambertian patch of
//! reflectance ρ under illuminance Ev has Lv = ρ·Ev/π.

use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use spectrace::light::luminous::{luminous_efficacy_lm_per_w, KM_LM_PER_W};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::f64::consts::PI;
use std::path::Path;

fn build(text: &str) -> Result<Scene, String> {
    let path = Path::new("photometric.ron");
    let desc = parse_scene_str(text, path).map_err(|e| e.to_string())?;
    build_scene(&desc, Path::new("."), path, &[&BuiltinFactory]).map_err(|e| e.to_string())
}

/// A 0.4 m square Lambertian patch (ρ = 0.5 at every wavelength) on y = 0, seen from 1 m
/// straight above through a 5° field (the view covers ±4.4 cm), lit by `light`; or, with
/// `emitter`, the patch itself emits.
fn patch_scene(light: &str, emitter: Option<&str>) -> String {
    let material = match emitter {
        Some(m) => format!("(name: \"patch\", type: \"emissive\", params: {m})"),
        None => "(name: \"patch\", type: \"lambertian\", params: (reflectance: 0.5))".into(),
    };
    format!(
        r#"(
    materials: [ {material} ],
    objects: [ (name: "patch", type: "mesh", material: "patch",
                params: (positions: [(-0.2, 0, -0.2), (-0.2, 0, 0.2), (0.2, 0, 0.2), (0.2, 0, -0.2)],
                         indices: [(0, 1, 2), (0, 2, 3)])) ],
    lights: [ {light} ],
    cameras: [ (name: "top", type: "pinhole",
                params: (position: (0, 1, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 5,
                         resolution: (16, 16))) ],
)"#
    )
}

/// The mean luminance over the image (cd/m²) and its standard error (from the spread of the
/// pixels, which are independent estimates).
fn mean_luminance(scene: &Scene) -> (f64, f64) {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(16),
        seed: 5,
        threads: Some(2),
        tracer: PathTracer::default(),
        ..RenderSettings::default()
    };
    let r = render(scene, &settings, &|_, _| {}, None).unwrap();
    let to_cd = KM_LM_PER_W * CieObserverKind::Cie1931_2.get().integral_y();
    let lv: Vec<f64> = r.image.xyz.iter().map(|p| p[1] * to_cd).collect();
    let n = lv.len() as f64;
    let mean = lv.iter().sum::<f64>() / n;
    let var = lv.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// `measured ± se` equals `expected` within 1%, and 1% is at least 4 standard errors (so the
/// check is not noise-limited). The geometry adds at most 0.15%: over the view (±4.4 cm at 2 m
/// from a point source) E falls off as cos³θ by ≤ 0.15% at the corners, 0.05% on average.
fn check(what: &str, measured: (f64, f64), expected: f64) {
    let (m, se) = measured;
    let rel = m / expected - 1.0;
    println!(
        "{what}: measured {m:.4} ± {se:.4}, expected {expected:.4} ({:+.3}%)",
        100.0 * rel
    );
    assert!(
        4.0 * se < 0.01 * expected,
        "{what}: standard error {se} too large"
    );
    assert!(rel.abs() < 0.01, "{what}: {m} vs {expected}");
}

// A point light of 1000 lm reports 1000 lm (its power × the spectrum's efficacy, to 1e-9), the
// same power as intensity_cd = 1000/4π cd (to 1e-12: one f32 rounding of the power is common
// to both), and lights a patch 2 m below with Ev = I/h² = 1000/(4π·4) = 19.894 lx, measured
// from the render as π·Lv/ρ (tolerance: see `check`).
#[test]
fn point_light_flux_intensity_and_lux() {
    let lamp = |p: &str| {
        format!("(name: \"bulb\", type: \"point\", params: (position: (0, 2, 0), {p}, spd: \"a\"))")
    };
    let by_flux = build(&patch_scene(&lamp("flux_lm: 1000"), None)).unwrap();
    let by_cd = build(&patch_scene(
        &lamp(&format!("intensity_cd: {:?}", 1000.0 / (4.0 * PI))),
        None,
    ))
    .unwrap();
    let l = &by_flux.lights.lights()[0];
    let lm = l.power() * luminous_efficacy_lm_per_w(l.spd().as_ref());
    assert!((lm / 1000.0 - 1.0).abs() < 1e-6, "reported {lm} lm");
    let p_cd = by_cd.lights.lights()[0].power();
    assert!(
        (p_cd / l.power() - 1.0).abs() < 1e-6,
        "{p_cd} vs {} W",
        l.power()
    );
    let (lv, se) = mean_luminance(&by_flux);
    check(
        "point 1000 lm at 2 m",
        (PI * lv / 0.5, PI * se / 0.5),
        1000.0 / (4.0 * PI * 4.0),
    );
}

// A spot of 250 cd on its axis (inside the 20° inner cone) 2 m above the patch: Ev = 250/4 =
// 62.5 lx; flux_lm = 250 · Ω (Ω the falloff's solid angle) gives the same power.
#[test]
fn spot_intensity_on_axis() {
    let spot = |p: &str| {
        format!(
            "(name: \"spot\", type: \"spot\", params: (position: (0, 2, 0), target: (0, 0, 0), inner_angle: 20, outer_angle: 30, {p}, spd: \"d65\"))"
        )
    };
    let scene = build(&patch_scene(&spot("intensity_cd: 250"), None)).unwrap();
    let omega = spectrace::light::spot::falloff_solid_angle_sr(20.0, 30.0);
    let by_flux = build(&patch_scene(
        &spot(&format!("flux_lm: {:?}", 250.0 * omega)),
        None,
    ))
    .unwrap();
    let (a, b) = (
        scene.lights.lights()[0].power(),
        by_flux.lights.lights()[0].power(),
    );
    assert!((a / b - 1.0).abs() < 1e-6, "{a} vs {b} W");
    let (lv, se) = mean_luminance(&scene);
    check("spot 250 cd at 2 m", (PI * lv / 0.5, PI * se / 0.5), 62.5);
}

// A directional light of 500 lx straight down: the patch (facing it) has Ev = 500 lx.
#[test]
fn directional_illuminance() {
    let scene = build(&patch_scene(
        "(name: \"sun\", type: \"directional\", params: (direction: (0, -1, 0), illuminance_lx: 500, spd: \"d65\"))",
        None,
    ))
    .unwrap();
    let (lv, se) = mean_luminance(&scene);
    check("directional 500 lx", (PI * lv / 0.5, PI * se / 0.5), 500.0);
}

// An emissive patch of 300 cd/m² seen straight on has Lv = 300 cd/m² in every pixel.
#[test]
fn emissive_luminance() {
    let scene = build(&patch_scene(
        "",
        Some("(radiance: \"blackbody:2700\", luminance_cd_m2: 300)"),
    ))
    .unwrap();
    check("emissive 300 cd/m²", mean_luminance(&scene), 300.0);
}

// Exactly one of the alternatives: both, or none, is an error naming the parameters.
#[test]
fn exactly_one_alternative() {
    let both = build(&patch_scene(
        "(name: \"b\", type: \"point\", params: (position: (0, 2, 0), power: 10, flux_lm: 100))",
        None,
    ))
    .unwrap_err();
    assert!(
        both.contains("light \"b\"") && both.contains("not both `power` and `flux_lm`"),
        "{both}"
    );
    let none = build(&patch_scene(
        "(name: \"b\", type: \"directional\", params: (direction: (0, -1, 0)))",
        None,
    ))
    .unwrap_err();
    assert!(
        none.contains("missing: give exactly one of `irradiance`, `illuminance_lx`"),
        "{none}"
    );
    let two = build(&patch_scene(
        "",
        Some("(radiance: \"d65\", scale: 2, luminance_cd_m2: 100)"),
    ))
    .unwrap_err();
    assert!(two.contains("not both"), "{two}");
}
