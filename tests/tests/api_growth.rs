//! The growth rule (`plugin-api/src/module.rs`): a plugin built against the 0.2.0 API keeps
//! loading and rendering in every 0.2.z host.
//!
//! `plugins/fixtures/api-0.2.0/` is a frozen, verbatim copy of the plugin API's source at 0.2.0;
//! `plugins/fixtures/api-0.2.0-plugin/` is a plugin (a point light and a grey material) built
//! against that copy. This test builds it with cargo as its own project, loads it into the
//! current host and renders it: it must load (the layout check passes because nothing the root
//! module reaches has changed), its call back into the host (an SPD lent by the host) must work,
//! its material must answer exactly, and its light must render like the built-in point light of
//! the same emission. A later 0.2.z that breaks the rule fails here.
//!
//! (Under 0.1, this test showed that growing the root module or a trait vtable after its
//! `last_prefix_field` marker, as abi_stable allows, locks every older plugin out: the layout
//! check accepts a library with MORE prefix fields than the host, never fewer.)

mod support;

use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use support::{build_external, mean_and_se};

fn scene_text(light: &str) -> String {
    scene_text_with(
        r#"(name: "floor", type: "lambertian", params: (reflectance: "colorchecker:19"))"#,
        light,
    )
}

fn scene_text_with(floor: &str, light: &str) -> String {
    format!(
        r#"(
    observer: "cie1931-2",
    output: (spp: 8, max_depth: 3, rgb_space: "srgb"),
    materials: [
        {floor},
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
    ],
    lights: [{light}],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 2.5), look_at: (0, 0, 0), fov: 50, resolution: (32, 32))),
    ],
)"#
    )
}

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "spectrace-api-growth-{}-{name}",
        std::process::id()
    ))
}

fn render_mean(
    scene: &Path,
    registry: &Arc<spectrace::plugin::Registry>,
    seed: u64,
) -> (f64, Arc<PluginFaults>) {
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(registry.clone(), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let scene = load_scene_file(scene, &factories).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings {
        budget: SampleBudget::Spp(256),
        seed,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 3,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = render_with(
        &scene,
        &settings,
        IntegratorKind::Lt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.result.image.non_finite_count(), 0);
    (out.result.image.mean_xyz()[1], faults)
}

/// Quantities: the frozen plugin's grey material's `eval` through the host adapter (exactly
/// ρ/π up to f32 rounding, 1e-6), and its point light's image mean Y against the built-in point
/// light of the same emission (light tracing, 4 seeds of 256 spp each): within 4 standard errors
/// of the difference, with 4σ below 2% so that a broken path (lost power, wrong spectrum) would
/// be seen.
#[test]
fn a_plugin_built_against_the_frozen_0_2_0_api_loads_and_renders() {
    use spectrace::material::{Material as _, ShadingContext, TransportMode};
    use spectrace_plugin_api::abi::std_types::RStr;
    use spectrace_plugin_api::module::ObjectSource;
    let lib = build_external(
        "plugins/fixtures/api-0.2.0-plugin",
        "spectrace_fixture_api_0_2_0_plugin",
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&lib)
        .unwrap_or_else(|e| panic!("the 0.2.0 plugin must load: {}", e.verbose()));
    let plugin = registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "api-0.2.0-plugin")
        .expect("loaded")
        .clone();
    assert_eq!(plugin.info.api_version.as_str(), "0.2.0");
    let source = ObjectSource::Params(RStr::from_str("(reflectance: 0.5)"));
    let grey = spectrace::plugin::adapter::PluginMaterial::new(
        registry
            .create_plugin_material("frozen_grey", source)
            .unwrap(),
        plugin.module.take_error(),
        spectrace::plugin::adapter::Origin {
            label: "frozen_grey".into(),
            faults: PluginFaults::new(),
        },
        "floor",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        grey.spectrally_flat(),
        "its declaration was checked and kept"
    );
    let wo = glam::Vec3A::new(0.0, 0.6, 0.8);
    let ctx = ShadingContext::at(
        glam::Vec3A::ZERO,
        glam::Vec3A::Y,
        glam::Vec3A::Y,
        glam::Vec2::ZERO,
    );
    let lambda = spectrace::spectrum::SampledWavelengths::sample_visible(0.3);
    let f = grey.eval(wo, wo, &ctx, &lambda, TransportMode::Radiance);
    assert!((f.0[0] - 0.5 / std::f32::consts::PI).abs() < 1e-6, "{f:?}");
    let registry = Arc::new(registry);

    let plugin_scene = tmp("frozen-plugin.ron");
    std::fs::write(
        &plugin_scene,
        scene_text(r#"(name: "bulb", type: "frozen_point", params: (position: (0, 1, 0), power_w: 20, spd: "d65"))"#),
    )
    .unwrap();
    let native_scene = tmp("frozen-native.ron");
    std::fs::write(
        &native_scene,
        scene_text(r#"(name: "bulb", type: "point", params: (position: (0, 1, 0), power: 20, spd: "d65"))"#),
    )
    .unwrap();
    let mut p = Vec::new();
    let mut n = Vec::new();
    for seed in 0..4 {
        let (m, faults) = render_mean(&plugin_scene, &registry, seed);
        assert_eq!(faults.count(), 0, "{:?}", faults.report());
        assert_eq!(faults.invalid_count(), 0, "{:?}", faults.report());
        p.push(m);
        n.push(render_mean(&native_scene, &registry, 100 + seed).0);
    }
    let ((mp, sp), (mn, sn)) = (mean_and_se(&p), mean_and_se(&n));
    let se = (sp * sp + sn * sn).sqrt();
    eprintln!(
        "0.2.0 plugin {mp:.6} ± {sp:.2e}, built-in point {mn:.6} ± {sn:.2e} ({:+.3}%, {:+.1} σ)",
        100.0 * (mp - mn) / mn,
        (mp - mn) / se
    );
    assert!(mp > 0.0);
    assert!(
        4.0 * se < 0.02 * mn,
        "σ {se} too large for the test to be sharp"
    );
    assert!((mp - mn).abs() < 4.0 * se, "plugin {mp} vs built-in {mn}");
    for f in [plugin_scene, native_scene] {
        let _ = std::fs::remove_file(f);
    }
}
