//! `spectrace luminaire bake` on plugin lights: a connectable plugin light (`smooth_spot`) and
//! one that only hands out beams (`laser`, `next_beam` alone) are measured from a scene with
//! their plugins loaded, and the blobs load and render with no plugin at all.

use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::plugin::Registry;
use spectrace::scene::{load_scene_file, Scene};
use spectrace_tests::{artifact_dir, plugin_library};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-bake-plugins-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn scene_text(lights: &str) -> String {
    format!(
        r#"(
        materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-20, 0, 20), edge0: (40, 0, 0), edge1: (0, 0, -40)))],
        lights: [{lights}],
        cameras: [(name: "down", type: "pinhole",
                   params: (position: (0, 3, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 80,
                            resolution: (32, 32)))],
    )"#
    )
}

fn load(path: &Path, registry: Registry) -> Scene {
    let f = PluginFactory::new(Arc::new(registry), PluginFaults::new());
    load_scene_file(path, &[&f]).unwrap()
}

fn mean_y(scene: &Scene) -> f64 {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(8),
        seed: 2,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 2,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = render_with(
        scene,
        &settings,
        IntegratorKind::Pt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap();
    out.result.image.mean_xyz()[1]
}

/// Baked plugin lights keep their flux (the spot: within 0.5%, the trapezoid integral of its
/// falloff sampled every 2.5°; the laser, aimed off the vertical so that its cell is not a pole:
/// exactly its power up to f64 sums, 1e-9 — every beam carries the full power and the table is
/// scaled to the beams' flux), the laser's spectrum peaks at its line (the 1 nm histogram's bin
/// 532–533 nm), and the baked spot renders like the plugin's spot (PT floor mean within 0.5%:
/// direct light from a delta light with the same wavelength samples, so nearly noise-free).
#[test]
fn plugin_lights_bake_into_blobs_that_need_no_plugin() {
    let bin = artifact_dir().join(format!("spectrace{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.exists(),
        "{} missing: run the README's test command",
        bin.display()
    );
    let point = plugin_library("spectrace-point-light");
    let laser = plugin_library("spectrace-example-laser");
    let scene = tmp("plugins.ron");
    std::fs::write(
        &scene,
        scene_text(
            r#"(name: "spot", type: "smooth_spot", params: (position: (0, 2, 0.3),
                 direction: (0.2, -1, 0), cone_angle_deg: 35, power_w: 42, spd: "fl11")),
               (name: "laser", type: "laser", params: (origin: (0.5, 2, 0), direction: (0.3, -1, 0),
                 radius: 0.01, wavelength_nm: 532, power_w: 2))"#,
        ),
    )
    .unwrap();
    for (light, samples) in [("spot", "64"), ("laser", "200000")] {
        let out = Command::new(&bin)
            .args(["luminaire", "bake"])
            .arg(&scene)
            .args(["--light", light, "--samples", samples, "-o"])
            .arg(tmp(&format!("{light}.blob")))
            .arg("--plugin")
            .arg(&point)
            .arg("--plugin")
            .arg(&laser)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let baked = tmp("baked.ron");
    std::fs::write(
        &baked,
        scene_text(
            r#"(name: "spot", type: "blob", params: (file: "spot.blob")),
               (name: "laser", type: "blob", params: (file: "laser.blob"))"#,
        ),
    )
    .unwrap();
    // No plugin in this registry.
    let baked_scene = load(&baked, spectrace::plugin::builtin_registry());
    let lights = baked_scene.lights.lights();
    let (spot_w, laser_w) = (lights[0].power(), lights[1].power());
    println!("baked spot {spot_w} W (of 42 W), baked laser {laser_w} W (of 2 W)");
    assert!((spot_w / 42.0 - 1.0).abs() < 0.005, "{spot_w}");
    assert!((laser_w / 2.0 - 1.0).abs() < 1e-9, "{laser_w}");
    let spd = lights[1].spd();
    let peak = (400..700)
        .map(|l| (l as f64 + 0.5, spd.value(l as f64 + 0.5)))
        .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    assert_eq!(peak.0, 532.5, "laser spectrum peaks at {} nm", peak.0);

    // The baked spot alone against the plugin's spot alone.
    let only = |file: &str, light: &str| {
        let p = tmp(file);
        std::fs::write(&p, scene_text(light)).unwrap();
        p
    };
    let original = only(
        "spot_only.ron",
        r#"(name: "spot", type: "smooth_spot", params: (position: (0, 2, 0.3),
             direction: (0.2, -1, 0), cone_angle_deg: 35, power_w: 42, spd: "fl11"))"#,
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry.load_plugin(&point).unwrap();
    let a = mean_y(&load(&original, registry));
    let b = mean_y(&load(
        &only(
            "spot_baked.ron",
            r#"(name: "spot", type: "blob", params: (file: "spot.blob"))"#,
        ),
        spectrace::plugin::builtin_registry(),
    ));
    println!("floor mean Y: baked / plugin spot = {:.5}", b / a);
    assert!((b / a - 1.0).abs() < 0.005, "{b} vs {a}");
}
