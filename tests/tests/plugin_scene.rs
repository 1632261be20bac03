//! A scene that mixes a plugin light with built-in materials and geometry renders, and renders
//! the same image as the same scene lit by the built-in spot light: two independent
//! implementations (plugins/point-light and host/src/light/spot.rs) of one radiometric
//! definition, one through the ABI and adapters, one native. The integrator cannot tell.

use spectrace::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use spectrace_tests::plugin_library;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/plugin_spot.ron")
}

fn render_mean(path: &Path, with_plugin: bool) -> ([f64; 3], u64, Arc<PluginFaults>) {
    let mut registry = spectrace::plugin::builtin_registry();
    if with_plugin {
        registry
            .load_plugin(&plugin_library("spectrace-point-light"))
            .unwrap();
    }
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let scene = load_scene_file(path, &factories).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings {
        budget: SampleBudget::Spp(8),
        seed: 7,
        threads: Some(2),
        tracer: PathTracer::default(),
        ..RenderSettings::default()
    };
    let r = render(&scene, &settings, &|_, _| {}, None).unwrap();
    assert_eq!(r.image.non_finite_count(), 0);
    (r.image.mean_xyz(), r.samples, faults)
}

#[test]
fn plugin_spot_and_builtin_spot_render_the_same_image() {
    let (plugin_mean, samples, faults) = render_mean(&scene_path(), true);
    assert!(samples > 0);
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
    assert!(plugin_mean[1] > 0.0, "the plugin light lit the scene");

    // The same scene with the built-in spot: target = position + direction, inner/outer = the
    // plugin's falloff start / cone angle, power in W, same SPD.
    let text = std::fs::read_to_string(scene_path()).unwrap();
    let builtin = text.replace(
        r#"(name: "key", type: "smooth_spot",
         params: (position: (0, 2.5, 1), direction: (0, -2.5, -1.5), cone_angle_deg: 35,
                  falloff_start_deg: 20, power_w: 3000, spd: "fl11")),"#,
        r#"(name: "key", type: "spot",
         params: (position: (0, 2.5, 1), target: (0, 0, -0.5), inner_angle: 20,
                  outer_angle: 35, power: 3000, spd: "fl11")),"#,
    );
    assert_ne!(builtin, text, "the replacement must have matched");
    let path =
        std::env::temp_dir().join(format!("spectrace-builtin-spot-{}.ron", std::process::id()));
    std::fs::write(&path, builtin).unwrap();
    let (builtin_mean, _, _) = render_mean(&path, false);

    // Same seed and sampler, and a delta light is sampled deterministically, so the two renders
    // differ only by f32-vs-f64 rounding inside the light (relative ~1e-6 per sample) and the
    // rare path whose Russian-roulette or BSDF decision flips because of it. 0.5% is far above
    // the first and still well below any real radiometric disagreement (a wrong 1/4π, cone
    // normalisation or cos factor would be tens of percent).
    for c in 0..3 {
        let rel = (plugin_mean[c] - builtin_mean[c]).abs() / builtin_mean[c];
        assert!(
            rel < 5e-3,
            "channel {c}: plugin {} vs built-in {}",
            plugin_mean[c],
            builtin_mean[c]
        );
    }
}

#[test]
fn a_scene_naming_a_plugin_type_without_the_plugin_says_so() {
    let mut registry = spectrace::plugin::builtin_registry();
    let _ = &mut registry;
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry), faults);
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let e = load_scene_file(&scene_path(), &factories)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("plugin_spot.ron") && e.contains("smooth_spot"),
        "{e}"
    );
}
