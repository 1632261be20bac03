//! Every emission capability a plugin declares is honoured: an ENVIRONMENT light, an EMISSIVE
//! material (an area light) and a CONNECTABLE light without a delta bit or a surface each
//! render like their built-in twin under path tracing, BDPT and light tracing, and the
//! environment also matches the analytic furnace value. The shading context's position reaches
//! plugin materials. Plugins come from the fixture crate `plugins/fixtures/emitters`.
//!
//! Monte Carlo tolerances: every estimate is the mean of `SEEDS` independent renders, and its
//! standard error is taken from the spread of those renders; each check allows 0.5% and
//! asserts that this is at least 2.5 standard errors, so a failure means a real difference
//! and not noise (the sample counts were chosen so that it is; see `within_half_a_percent`).

use spectrace::film::XyzImage;
use spectrace::integrator::{IntegratorKind, RenderSettings, SampleBudget};
use spectrace::material::{Material as _, ShadingContext, TransportMode};
use spectrace::plugin::adapter::{Origin, PluginFaults, PluginMaterial};
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, ObjectFactory, Scene};
use spectrace::spectrum::{SampledWavelengths, Spd};
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_tests::plugin_library;
use std::path::Path;
use std::sync::Arc;

const SEEDS: u64 = 8;

fn registry() -> spectrace::plugin::Registry {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-fixture-emitters"))
        .unwrap();
    r
}

fn scene(text: &str) -> (Scene, Arc<PluginFaults>) {
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry()), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let file = Path::new("fixture.ron");
    let desc = parse_scene_str(text, file).unwrap_or_else(|e| panic!("{e}"));
    let scene =
        build_scene(&desc, Path::new("."), file, &factories).unwrap_or_else(|e| panic!("{e}"));
    (scene, faults)
}

/// Mean luminance Y of `pick`ed pixels per seed (seeds 1..=SEEDS).
fn renders(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    pick: &dyn Fn(&XyzImage, usize) -> bool,
) -> Vec<f64> {
    (1..=SEEDS)
        .map(|seed| {
            let settings = RenderSettings {
                budget: SampleBudget::Spp(spp),
                seed,
                threads: Some(2),
                ..RenderSettings::default()
            };
            let out = spectrace_tests::render_every_light_subpath(scene, &settings, kind).unwrap();
            let img = &out.result.image;
            let (mut sum, mut n) = (0.0, 0usize);
            for (i, p) in img.xyz.iter().enumerate() {
                if pick(img, i) {
                    sum += p[1];
                    n += 1;
                }
            }
            sum / n as f64
        })
        .collect()
}

/// Mean and standard error of the mean (zero for a single value).
fn stats(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    if v.len() < 2 {
        return (m, 0.0);
    }
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// `a` agrees with `b` within 0.5%: per seed the ratio `a_i / b_i` (`b` has one entry when
/// it is exact); its mean must be within 0.5% of 1, and 0.5% must be at least 2.5 standard
/// errors of that mean, so the check can see a difference of that size (paired ratios: where
/// both renders share their random numbers, as the built-in and plugin twins of one emitter
/// do, the noise cancels). Renders are deterministic, so the outcome is too.
fn within_half_a_percent(what: &str, a: &[f64], b: &[f64]) {
    let ratios: Vec<f64> = a
        .iter()
        .enumerate()
        .map(|(i, x)| x / b[i.min(b.len() - 1)])
        .collect();
    let (m, se) = stats(&ratios);
    let rel = m - 1.0;
    println!(
        "{what}: {:.6e} vs {:.6e}: {:+.3}% (standard error {:.3}%)",
        stats(a).0,
        stats(b).0,
        100.0 * rel,
        100.0 * se
    );
    assert!(
        2.5 * se <= 0.005,
        "{what}: standard error {:.3}% too large for a 0.5% check",
        100.0 * se
    );
    assert!(rel.abs() < 0.005, "{what}: {:+.3}% off", 100.0 * rel);
}

fn all(_: &XyzImage, _: usize) -> bool {
    true
}

const KINDS: [IntegratorKind; 3] = [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt];

/// Sample counts per integrator that bring the standard error of these small images below
/// 0.17%: BDPT pays for its extra strategies' noise and light tracing for the light paths
/// that never reach the view.
fn spp(kind: IntegratorKind, base: u32) -> u32 {
    match kind {
        IntegratorKind::Lt => base * 4,
        IntegratorKind::Bdpt => base * 4,
        _ => base,
    }
}

/// Furnace: a grey (ρ = 0.5) floor patch filling the view from above under a uniform
/// environment of radiance L = 2·S_e(λ) sees only the sky, so every pixel has radiance ρ·L,
/// luminance Y = ρ·2·S_e(555 nm) (S_e is flat, so Y needs no integral). Built-in `environment`
/// and the plugin `fixture_environment` (which samples incident and emitted directions its own
/// way), each integrator. (A patch just filling the view keeps light tracing efficient: about 14% of the
/// environment's light paths land on it.)
#[test]
fn environment_furnace_builtin_and_plugin() {
    let text = |light: &str| {
        format!(
            r#"(
            output: (max_depth: 8),
            materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
            objects: [(name: "floor", type: "quad", material: "grey",
                       params: (corner: (-0.6, 0, 0.6), edge0: (1.2, 0, 0), edge1: (0, 0, -1.2)))],
            lights: [(name: "sky", {light})],
            cameras: [(name: "c", type: "perspective",
                       params: (position: (0, 0.5, 0), look_at: (0, 0, 0), up: (0, 0, -1),
                                fov: 90, resolution: (16, 16)))],
        )"#
        )
    };
    let e = spectrace::spectrum::parse_spd_spec("e").unwrap();
    let expected = 0.5 * 2.0 * e.value(555.0);
    let (builtin, _) = scene(&text(
        r#"type: "environment", params: (radiance: "e", scale: 2)"#,
    ));
    let (plugin, faults) = scene(&text(r#"type: "fixture_environment", params: (scale: 2)"#));
    for kind in KINDS {
        // Light tracing: 4× more again (measured standard error 0.25% at 1024 spp).
        let n = if kind == IntegratorKind::Lt {
            4096
        } else {
            spp(kind, 256)
        };
        let got = renders(&builtin, kind, n, &all);
        within_half_a_percent(&format!("environment furnace, {kind}"), &got, &[expected]);
        // The plugin's light paths start from its own `sample_emission` (SPHERE_EMISSION:
        // half of them around +y), so light tracing is no longer the built-in's image seed by
        // seed: it must meet the furnace value on its own, which a density that disagrees
        // with the directions drawn would miss.
        let got = renders(&plugin, kind, n, &all);
        within_half_a_percent(
            &format!("fixture_environment furnace, {kind}"),
            &got,
            &[expected],
        );
    }
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// A floor patch lit by a small quad light 1 m above it, seen from a camera between them that
/// looks down and so does not see the light (most light paths land in view, which keeps light
/// tracing efficient): `material`/`object` or `light` make the emitter.
fn lit_floor(material: &str, object: &str, light: &str) -> String {
    format!(
        r#"(
        output: (max_depth: 6),
        materials: [
            (name: "floor", type: "lambertian", params: (reflectance: 0.5)),
            {material}
        ],
        objects: [
            (name: "floor", type: "quad", material: "floor",
             params: (corner: (-0.6, 0, 0.6), edge0: (1.2, 0, 0), edge1: (0, 0, -1.2))),
            {object}
        ],
        lights: [{light}],
        cameras: [(name: "c", type: "perspective",
                   params: (position: (0, 0.6, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 90,
                            resolution: (16, 16)))],
    )"#
    )
}

/// The built-in emitter: a 0.5 m quad at y = 1 facing down, radiance 20·S_e.
const BUILTIN_MATERIAL: &str =
    r#"(name: "lamp", type: "emissive", params: (radiance: "e", scale: 20)),"#;
const LAMP_OBJECT: &str = r#"(name: "lamp", type: "quad", material: "lamp",
             params: (corner: (-0.25, 1, -0.25), edge0: (0.5, 0, 0), edge1: (0, 0, 0.5))),"#;

fn builtin_lamp() -> Scene {
    let (s, _) = scene(&lit_floor(BUILTIN_MATERIAL, LAMP_OBJECT, ""));
    s
}

/// A plugin EMISSIVE material on the same quad becomes an area light and renders like the
/// built-in `emissive` under each integrator.
#[test]
fn plugin_emissive_material_is_an_area_light() {
    let builtin = builtin_lamp();
    let (plugin, faults) = scene(&lit_floor(
        r#"(name: "lamp", type: "fixture_emitter", params: (scale: 20)),"#,
        LAMP_OBJECT,
        "",
    ));
    assert_eq!(
        plugin.lights.lights().len(),
        1,
        "the plugin emitter is an area light"
    );
    for kind in KINDS {
        let a = renders(&plugin, kind, spp(kind, 16), &all);
        let b = renders(&builtin, kind, spp(kind, 16), &all);
        within_half_a_percent(&format!("fixture_emitter vs emissive, {kind}"), &a, &b);
    }
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// A CONNECTABLE plugin light without a delta bit and without a surface (nothing can hit it)
/// renders like the same quad built in: next-event estimation gets the whole weight where no
/// BSDF-hit term exists (before, its weight was below 1 and the image too dark).
#[test]
fn surfaceless_plugin_light_matches_the_builtin_area_light() {
    let builtin = builtin_lamp();
    let (plugin, faults) = scene(&lit_floor(
        "",
        "",
        r#"(name: "lamp", type: "fixture_quad_light",
            params: (corner: (-0.25, 1, -0.25), edge0: (0.5, 0, 0), edge1: (0, 0, 0.5),
                     scale: 20))"#,
    ));
    for kind in KINDS {
        // The two lights sample emission independently, so light tracing's noise does not
        // cancel here: 50× more paths (measured standard error 0.8% at 64 spp).
        let n = if kind == IntegratorKind::Lt {
            3200
        } else {
            spp(kind, 16)
        };
        let a = renders(&plugin, kind, n, &all);
        let b = renders(&builtin, kind, n, &all);
        within_half_a_percent(
            &format!("fixture_quad_light vs emissive quad, {kind}"),
            &a,
            &b,
        );
    }
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// The shading context's position reaches a plugin material: `fixture_position_tint` answers
/// `low/π` at x < 0 and `high/π` at x ≥ 0 through the host adapter (exact, f32 rounding), and
/// a floor of it under a uniform environment (a plane sees only sky: radiance ρ·L) shows
/// ρ = low on its left half and high on its right, each within 2% (path tracing, standard
/// error about 0.3%; pixels on the centre column are left out).
#[test]
fn shading_position_reaches_plugin_materials() {
    let registry = registry();
    let material = registry
        .create_plugin_material(
            "fixture_position_tint",
            ObjectSource::Params(RStr::from_str("(low: 0.2, high: 0.8)")),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let material = PluginMaterial::new(
        material,
        take_error(&registry),
        Origin {
            label: "tint".into(),
            faults: PluginFaults::new(),
        },
        "tint",
    )
    .unwrap();
    let lambda = SampledWavelengths::sample_visible(0.4);
    let wo = glam::Vec3A::new(0.0, 0.6, 0.8);
    for (x, r) in [(-1.0f32, 0.2f32), (1.0, 0.8)] {
        let ctx = ShadingContext::at(
            glam::Vec3A::new(x, 0.0, 0.0),
            glam::Vec3A::Z,
            glam::Vec3A::Z,
            glam::Vec2::ZERO,
        );
        let f = material.eval(wo, wo, &ctx, &lambda, TransportMode::Radiance);
        assert!(
            (f.0[0] - r / std::f32::consts::PI).abs() < 1e-6,
            "{f:?} at x = {x}"
        );
    }

    let (scene, faults) = scene(
        r#"(
        output: (max_depth: 4),
        materials: [(name: "tint", type: "fixture_position_tint", params: (low: 0.2, high: 0.8))],
        objects: [(name: "floor", type: "quad", material: "tint",
                   params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
        lights: [(name: "sky", type: "environment", params: (radiance: "e", scale: 2))],
        cameras: [(name: "c", type: "perspective",
                   params: (position: (0, 2, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 40,
                            resolution: (16, 16)))],
    )"#,
    );
    let l = 2.0
        * spectrace::spectrum::parse_spd_spec("e")
            .unwrap()
            .value(555.0);
    let left = |img: &XyzImage, i: usize| (i as u32 % img.width) < img.width / 2 - 1;
    let right = |img: &XyzImage, i: usize| (i as u32 % img.width) > img.width / 2;
    for (name, pick, rho) in [
        (
            "left (x < 0)",
            &left as &dyn Fn(&XyzImage, usize) -> bool,
            0.2,
        ),
        ("right (x > 0)", &right, 0.8),
    ] {
        let (m, se) = stats(&renders(&scene, IntegratorKind::Pt, 16, pick));
        println!(
            "{name}: {m:.5e} vs {:.5e} (standard error {:.3}%)",
            rho * l,
            100.0 * se / m
        );
        assert!(
            (m / (rho * l) - 1.0).abs() < 0.02,
            "{name}: {m} vs {}",
            rho * l
        );
    }
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// The surface's normals reach a plugin material: `fixture_normal_tint` answers `up/π` where the
/// normal it reads (shading or geometric) has y ≥ 0.5 and `other/π` elsewhere. Through the host
/// adapter, with geometric normal +x and shading normal +y and the other way round, each choice
/// of normal gives the reflectance of the normal it was given (exact up to f32 rounding, 1e-6);
/// with no normals (zero, what the host gives where it knows none) it answers `other/π`. A floor of it (normal
/// +y) under a uniform environment (a plane sees only sky: radiance ρ·L) then shows ρ = `up`
/// within 2% (path tracing, standard error about 0.06%), where a lost normal would give `other`,
/// a factor 4 less.
#[test]
fn surface_normals_reach_plugin_materials() {
    let registry = registry();
    let origin = || Origin {
        label: "normal tint".into(),
        faults: PluginFaults::new(),
    };
    let lambda = SampledWavelengths::sample_visible(0.4);
    let wo = glam::Vec3A::new(0.0, 0.6, 0.8);
    let (x, y) = (glam::Vec3A::X, glam::Vec3A::Y);
    let up_geometric = ShadingContext::at(glam::Vec3A::ZERO, y, x, glam::Vec2::ZERO);
    let up_shading = ShadingContext::at(glam::Vec3A::ZERO, x, y, glam::Vec2::ZERO);
    for (which, up_ctx, side_ctx) in [
        ("shading", &up_shading, &up_geometric),
        ("geometric", &up_geometric, &up_shading),
    ] {
        let params = format!("(up: 0.8, other: 0.2, normal: \"{which}\")");
        let source = ObjectSource::Params(RStr::from_str(&params));
        let material = PluginMaterial::new(
            registry
                .create_plugin_material("fixture_normal_tint", source)
                .unwrap_or_else(|e| panic!("{e}")),
            take_error(&registry),
            origin(),
            "tint",
        )
        .unwrap();
        for (ctx, r) in [(up_ctx, 0.8f32), (side_ctx, 0.2)] {
            let f = material.eval(wo, wo, ctx, &lambda, TransportMode::Radiance);
            assert!(
                (f.0[0] - r / std::f32::consts::PI).abs() < 1e-6,
                "{which} normal: {f:?} for {ctx:?}"
            );
        }
        let no_normals = ShadingContext::at(
            glam::Vec3A::ZERO,
            glam::Vec3A::ZERO,
            glam::Vec3A::ZERO,
            glam::Vec2::ZERO,
        );
        let f = material.eval(wo, wo, &no_normals, &lambda, TransportMode::Radiance);
        assert!(
            (f.0[0] - 0.2 / std::f32::consts::PI).abs() < 1e-6,
            "no normals: {f:?}"
        );
    }

    let (scene, faults) = scene(
        r#"(
        output: (max_depth: 4),
        materials: [(name: "tint", type: "fixture_normal_tint", params: (up: 0.8, other: 0.2))],
        objects: [(name: "floor", type: "quad", material: "tint",
                   params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
        lights: [(name: "sky", type: "environment", params: (radiance: "e", scale: 2))],
        cameras: [(name: "c", type: "perspective",
                   params: (position: (0, 2, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 40,
                            resolution: (16, 16)))],
    )"#,
    );
    let l = 2.0
        * spectrace::spectrum::parse_spd_spec("e")
            .unwrap()
            .value(555.0);
    let (m, se) = stats(&renders(&scene, IntegratorKind::Pt, 16, &|_, _| true));
    println!(
        "floor: {m:.5e} vs ρ·L = {:.5e} (standard error {:.3}%)",
        0.8 * l,
        100.0 * se / m
    );
    assert!((m / (0.8 * l) - 1.0).abs() < 0.02, "{m} vs {}", 0.8 * l);
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// A plugin light's claim to emit one spectral shape everywhere (`UNIFORM_SPECTRAL_SHAPE`) is
/// checked when
/// the light is built. `fixture_quad_light` with `uniform: true` emits `20·S_e(λ)` at every point
/// and passes: the scene builds and the light keeps its declaration. With `tinted_half: true` as
/// well, half of the quad emits `20·S_e(λ)·λ/560 nm`, a different colour: the scene is refused
/// with a message naming the plugin, the scene's light and a wavelength where the emission
/// departs from the spectrum's shape. Quantities: the declaration (exact) and the message's
/// content (the probe's tolerance, 1e-4 relative, is far below the tint's 32% at 380 nm).
#[test]
fn a_plugin_lights_uniform_shape_claim_is_checked() {
    let quad = |extra: &str| {
        lit_floor(
            "",
            "",
            &format!(
                r#"(name: "lamp", type: "fixture_quad_light",
                    params: (corner: (-0.25, 1, -0.25), edge0: (0.5, 0, 0), edge1: (0, 0, 0.5),
                             scale: 20, uniform: true{extra}))"#
            ),
        )
    };
    let (honest, _) = scene(&quad(""));
    assert!(honest.lights.lights()[0].uniform_spectral_shape());

    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry()), faults);
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let file = Path::new("fixture.ron");
    let desc = parse_scene_str(&quad(", tinted_half: true"), file).unwrap();
    let e = match build_scene(&desc, Path::new("."), file, &factories) {
        Ok(_) => panic!("a light that changes colour across its surface must be refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("fixture_quad_light")
            && e.contains("fixture-emitters")
            && e.contains("lamp")
            && e.contains("UNIFORM_SPECTRAL_SHAPE")
            && e.contains(" nm "),
        "{e}"
    );
}

/// The root module's `take_error` of the emitters fixture library.
fn take_error(registry: &spectrace::plugin::Registry) -> spectrace::plugin::adapter::TakeError {
    registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "fixture-emitters")
        .expect("loaded")
        .module
        .take_error()
}
