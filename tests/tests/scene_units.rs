//! Scene units: the same scene written in metres and in millimetres (every length × 1000,
//! `units: "mm"`) renders the same image, for every kind of light: built-in point, spot,
//! directional and area (emissive) lights, a connectable plugin light (`smooth_spot`) and a
//! beam-only plugin light (`laser`, light tracing only), and a measured luminaire (`luminaire`,
//! an IES LM-63 file). Also: `units: "cm"`, `"in"` and `"ft"`
//! for the point light, whose image depends on distances through 1/d².
//!
//! Why the images are bit-identical: both scenes are built in metres (the millimetre one
//! scaled by 0.001 when built, in f64), and a length x written as x / 0.001 in full precision
//! comes back as x within an f64 rounding, far below the f32 in which the renderer stores
//! positions, so both scenes hold the same f32 geometry, lights and camera; same seed, sampler
//! and sample count then give the same pixels. (Measured: identical in every case here.) A unit
//! mistake would be far from this: a point light read in mm would be 10⁶× too bright against
//! the metre scene, an area in mm² read as m² 10⁶× too much power, a directional footprint
//! 10⁶× off. The lights' reported powers (W) must agree to 1e-5 as well.

use spectrace::integrator::{render_with, IntegratorKind, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{build_scene, parse_scene_str, ObjectFactory};
use spectrace_tests::plugin_library;
use std::path::Path;
use std::sync::Arc;

/// The scene with light `light` (RON items; lengths written as `L(x)` in metres) in unit
/// `unit` whose size is `m` metres: every `L(x)` becomes x / m.
fn scene_text(light: &str, unit: &str, m: f64) -> String {
    let template = format!(
        r#"(
    units: "{unit}",
    materials: [
        (name: "white", type: "lambertian", params: (reflectance: 0.7)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 5)),
    ],
    objects: [
        (name: "floor", type: "mesh", material: "white",
         params: (positions: [(L(-2), L(0), L(-2)), (L(-2), L(0), L(2)), (L(2), L(0), L(2)), (L(2), L(0), L(-2))],
                  indices: [(0, 1, 2), (0, 2, 3)])),
        (name: "wall", type: "mesh", material: "white",
         params: (positions: [(L(-2), L(0), L(-1)), (L(2), L(0), L(-1)), (L(2), L(2), L(-1)), (L(-2), L(2), L(-1))],
                  indices: [(0, 1, 2), (0, 2, 3)])),
        (name: "ball", type: "sphere", material: "white",
         params: (center: (L(0.4), L(0.3), L(0)), radius: L(0.3))),
        {light_objects}
    ],
    lights: [ {lights} ],
    cameras: [ (name: "cam", type: "pinhole",
                params: (position: (L(0), L(1.2), L(3)), look_at: (L(0), L(0.4), L(0)), fov: 50, resolution: (32, 24))) ],
)"#,
        light_objects = if light == "area" {
            r#"(name: "panel", type: "mesh", material: "lamp",
         params: (positions: [(L(-0.3), L(1.5), L(-0.3)), (L(0.3), L(1.5), L(-0.3)), (L(0.3), L(1.5), L(0.3)), (L(-0.3), L(1.5), L(0.3))],
                  indices: [(0, 1, 2), (0, 2, 3)])),"#
        } else {
            ""
        },
        lights = match light {
            "area" => "",
            "point" => {
                r#"(name: "bulb", type: "point", params: (position: (L(-0.5), L(1.5), L(0.5)), power: 100, spd: "a"))"#
            }
            "spot" => {
                r#"(name: "spot", type: "spot", params: (position: (L(-0.5), L(1.8), L(1)), target: (L(0), L(0), L(0)), inner_angle: 15, outer_angle: 35, power: 80))"#
            }
            "directional" => {
                r#"(name: "sun", type: "directional", params: (direction: (0.3, -1, -0.4), irradiance: 3, spd: "d65"))"#
            }
            "smooth_spot" => {
                r#"(name: "plugin", type: "smooth_spot", params: (position: (L(-0.5), L(1.8), L(1)), direction: (0.5, -1.8, -1), cone_angle_deg: 35, falloff_start_deg: 15, power_w: 80, spd: "fl11"))"#
            }
            "luminaire" => {
                // A real IES file (scenes/luminaires/), path made absolute below.
                r#"(name: "downlight", type: "luminaire", params: (file: "IES_FILE", position: (L(0.2), L(1.8), L(0.3)), spd: "a"))"#
            }
            "laser" => {
                r#"(name: "laser", type: "laser", params: (origin: (L(-0.5), L(1.5), L(1)), direction: (0.4, -1.5, -1.2), radius: L(0.15), wavelength_nm: 532, power_w: 2))"#
            }
            other => panic!("no light {other}"),
        }
    );
    // Replace every L(x) by x / m, written in full precision.
    let mut out = String::new();
    let mut rest = template.as_str();
    while let Some(i) = rest.find("L(") {
        out.push_str(&rest[..i]);
        let j = i + rest[i..].find(')').unwrap();
        let x: f64 = rest[i + 2..j].parse().unwrap();
        out.push_str(&format!("{:?}", x / m));
        rest = &rest[j + 1..];
    }
    out.push_str(rest);
    let ies = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/luminaires/erco_downlight_lm63-1986_onevalperline.ies");
    out.replace("IES_FILE", &ies.display().to_string())
}

fn factory() -> PluginFactory {
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    registry
        .load_plugin(&plugin_library("spectrace-example-laser"))
        .unwrap();
    PluginFactory::new(Arc::new(registry), PluginFaults::new())
}

/// The image (XYZ per pixel) and the power the scene's lights report, W.
fn render(text: &str, kind: IntegratorKind, spp: u32) -> (Vec<[f64; 3]>, f64) {
    let f = factory();
    let factories: [&dyn ObjectFactory; 1] = [&f];
    let path = Path::new("units.ron");
    let desc = parse_scene_str(text, path).unwrap_or_else(|e| panic!("{e}"));
    let scene =
        build_scene(&desc, Path::new("."), path, &factories).unwrap_or_else(|e| panic!("{e}"));
    let power: f64 = scene.lights.lights().iter().map(|l| l.power()).sum();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 11,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let out = render_with(&scene, &settings, kind, false, &|_, _| {}, None).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    assert_eq!(f.faults().count(), 0, "{:?}", f.faults().first());
    (out.result.image.xyz.clone(), power)
}

fn mean(img: &[[f64; 3]]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in img {
        for c in 0..3 {
            m[c] += p[c] / img.len() as f64;
        }
    }
    m
}

/// Renders `light` in metres and in `unit` (`m` metres) and compares as the module docs say.
fn same_image(light: &str, unit: &str, m: f64, kind: IntegratorKind, spp: u32) {
    let (a, pa) = render(&scene_text(light, "m", 1.0), kind, spp);
    let (b, pb) = render(&scene_text(light, unit, m), kind, spp);
    let (ma, mb) = (mean(&a), mean(&b));
    // Power is per metre whatever the unit (for the area light 5 W/(m²·sr) × π × 0.36 m²;
    // for the directional light its footprint is the scene's bounding disc, in m²).
    assert!(
        (pa / pb - 1.0).abs() < 1e-5,
        "{light} in {unit}: power {pb} W, in m {pa} W"
    );
    assert!(
        ma[1] > 1e-4,
        "{light}: the metre scene is lit (mean Y {})",
        ma[1]
    );
    let mut abs_diff = 0.0;
    for (p, q) in a.iter().zip(&b) {
        abs_diff += (p[1] - q[1]).abs() / a.len() as f64;
    }
    println!(
        "{light} in {unit}: mean XYZ m {ma:?}, {unit} {mb:?}; mean |ΔY| / mean Y = {:.2e}; power {pa} W",
        abs_diff / ma[1]
    );
    assert!(
        a == b,
        "{light} in {unit}: images differ (mean XYZ {mb:?} vs {ma:?} in metres, mean |ΔY| {abs_diff})"
    );
}

#[test]
fn point_spot_directional_area_and_ies_lights_in_mm_and_m() {
    for light in ["point", "spot", "directional", "area", "luminaire"] {
        same_image(light, "mm", 1e-3, IntegratorKind::Pt, 8);
    }
}

#[test]
fn point_light_in_cm_in_and_ft() {
    same_image("point", "cm", 0.01, IntegratorKind::Pt, 8);
    same_image("point", "in", 0.0254, IntegratorKind::Pt, 8);
    same_image("point", "ft", 0.3048, IntegratorKind::Pt, 8);
}

#[test]
fn plugin_lights_in_mm_and_m() {
    same_image("smooth_spot", "mm", 1e-3, IntegratorKind::Pt, 8);
    // Beams only: light tracing is the only integrator that renders it.
    same_image("laser", "mm", 1e-3, IntegratorKind::Lt, 8);
}

/// A unit that does not exist is refused, naming the item and the known units.
#[test]
fn unknown_unit_is_refused() {
    let text = scene_text("point", "furlong", 1.0);
    let f = factory();
    let factories: [&dyn ObjectFactory; 1] = [&f];
    let desc = parse_scene_str(&text, Path::new("u.ron")).unwrap();
    let e = build_scene(&desc, Path::new("."), Path::new("u.ron"), &factories)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("units") && e.contains("`furlong`") && e.contains("m, cm, mm, in, ft"),
        "{e}"
    );
}
