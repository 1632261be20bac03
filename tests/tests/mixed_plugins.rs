//! `scenes/mixed-plugins.ron`: a built-in light and materials, a material from a workspace
//! plugin library, the third-party plugin built outside the workspace, and a light from a blob,
//! in one scene. The blob is packed here (as the scene's header says) next to a copy of the
//! scene in a temporary folder; the scene is then rendered by the CLI exactly as documented and
//! in-process, where every kind of light must have emitted.

mod support;

use spectrace::integrator::{IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use spectrace_tests::{artifact_dir, plugin_library};
use std::process::Command;
use std::sync::Arc;
use support::{build_external, repo};

#[test]
fn the_mixed_plugins_scene_renders() {
    let bin = artifact_dir().join(format!("spectrace{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.exists(),
        "{} missing: run the README's test command",
        bin.display()
    );
    let third_party = build_external("examples/third-party-light", "third_party_light");
    let point = plugin_library("spectrace-point-light");
    let rough = plugin_library("spectrace-rough-diffuse");

    let dir = std::env::temp_dir().join(format!("spectrace-mixed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("mixed-plugins.ron");
    std::fs::copy(repo().join("scenes/mixed-plugins.ron"), &scene).unwrap();
    let pack = Command::new(&bin)
        .args(["blob", "pack", "isotropic_point", "--params"])
        .arg(r#"(position: (-0.8, 1.6, 0.6), power_w: 40, spd: "a")"#)
        .arg("-o")
        .arg(dir.join("mixed-plugins.blob"))
        .arg("--plugin")
        .arg(&point)
        .output()
        .unwrap();
    assert!(
        pack.status.success(),
        "{}",
        String::from_utf8_lossy(&pack.stderr)
    );

    // The CLI, as the scene's header says (fewer samples).
    let exr = dir.join("mixed.exr");
    let out = Command::new(&bin)
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&exr)
        .args(["--spp", "2", "--quiet", "--threads", "2", "--plugin"])
        .arg(&point)
        .arg("--plugin")
        .arg(&rough)
        .arg("--plugin")
        .arg(&third_party)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(exr.exists());
    assert!(stdout.contains("non-finite pixels: 0"), "{stdout}");
    assert!(!stdout.contains("warning"), "{stdout}");

    // In-process: all three lights built (built-in, third-party, blob), and each emitted.
    let mut registry = spectrace::plugin::builtin_registry();
    for lib in [&point, &rough, &third_party] {
        registry.load_plugin(lib).unwrap_or_else(|e| panic!("{e}"));
    }
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let scene = load_scene_file(&scene, &factories).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.lights.lights().len(), 3);
    let settings = RenderSettings {
        budget: SampleBudget::Spp(2),
        seed: 1,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 4,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = spectrace_tests::render_every_light_subpath(&scene, &settings, IntegratorKind::Bdpt)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.result.image.non_finite_count(), 0);
    assert!(out.result.image.mean_xyz()[1] > 0.0);
    assert_eq!(
        faults.count() + faults.invalid_count(),
        0,
        "{:?}",
        faults.report()
    );
    // The third-party light is beams-only: its beams were traced (and converted).
    assert!(scene.lights.lights()[1].number_of_beams() > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
