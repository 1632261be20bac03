//! Plugins that misbehave while rendering (issue: bad input never crashes, floods or silently
//! gives a wrong image). A plugin's NaN or negative powers, pdfs and values, non-unit directions
//! and out-of-range wavelengths are dropped, counted by plugin object and reason, and reported;
//! the render completes with a finite image. A plugin that panics on every other call is
//! reported once per call site with its count, however many times it panicked, and whatever
//! `RUST_BACKTRACE` says.

use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use spectrace_tests::{artifact_dir, plugin_library};
use std::path::PathBuf;
use std::process::Command;
use std::sync::Arc;

fn scene_text(light: &str, spp: u32) -> String {
    format!(
        r#"(
    observer: "cie1931-2",
    output: (spp: {spp}, max_depth: 3, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: "colorchecker:19")),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
    ],
    lights: [
        (name: "good", type: "point", params: (position: (0.5, 1, 0), power: 10, spd: "d65")),
        {light},
    ],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 2.5), look_at: (0, 0, 0), fov: 50, resolution: (24, 24))),
    ],
)"#
    )
}

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("spectrace-faults-{}-{name}", std::process::id()))
}

/// Render the scene with the misbehaving light set to `fault` by `kind`; returns the faults and
/// the image's mean Y.
fn render_fault(fault: &str, kind: IntegratorKind) -> (Arc<PluginFaults>, f64) {
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&plugin_library("spectrace-fixture-misbehaving-light"))
        .unwrap_or_else(|e| panic!("{e}"));
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let path = tmp(&format!("{fault}-{kind}.ron"));
    let light = format!(
        r#"(name: "bad", type: "misbehaving", params: (position: (-0.5, 1, 0), fault: "{fault}"))"#
    );
    std::fs::write(&path, scene_text(&light, 4)).unwrap();
    let scene = load_scene_file(&path, &factories).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_file(&path);
    let settings = RenderSettings {
        budget: SampleBudget::Spp(4),
        seed: 3,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 3,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = render_with(&scene, &settings, kind, false, &|_, _| {}, None)
        .unwrap_or_else(|e| panic!("{fault}, {kind}: the render must complete: {e}"));
    assert_eq!(
        out.result.image.non_finite_count(),
        0,
        "{fault}, {kind}: no bad value reaches the image"
    );
    (faults, out.result.image.mean_xyz()[1])
}

// Each fault, under the integrators that call what it breaks: every bad result is dropped and
// counted under the light's label with its reason, nothing fails outright, and the built-in
// light still lights the image. The control ("none") drops nothing.
#[test]
fn bad_values_from_a_plugin_are_dropped_counted_and_reported() {
    const LT: IntegratorKind = IntegratorKind::Lt;
    const PT: IntegratorKind = IntegratorKind::Pt;
    let cases: [(&str, &[IntegratorKind], &str); 6] = [
        ("nan_power", &[LT], "power"),
        ("negative_power", &[LT], "power"),
        ("bad_wavelength", &[LT], "wavelength"),
        ("non_unit", &[LT, PT], "direction"),
        ("nan_pdf", &[LT, PT], "pdf"),
        ("negative_value", &[LT, PT], "value"),
    ];
    for (fault, kinds, reason) in cases {
        for &kind in kinds {
            let (faults, mean) = render_fault(fault, kind);
            assert_eq!(faults.count(), 0, "{fault}, {kind}: {:?}", faults.report());
            let invalid = faults.invalid();
            assert!(
                invalid
                    .iter()
                    .any(|(who, why, n)| who.contains("misbehaving")
                        && who.contains("misbehaving-fixture")
                        && why.contains(reason)
                        && *n > 0),
                "{fault}, {kind}: expected drops for `{reason}`, got {invalid:?}"
            );
            assert!(
                invalid
                    .iter()
                    .all(|(who, _, _)| who.contains("misbehaving")),
                "only the bad light is blamed: {invalid:?}"
            );
            let report = faults.report();
            assert!(
                report
                    .iter()
                    .any(|l| l.contains("dropped") && l.contains(reason)),
                "{report:?}"
            );
            assert!(mean > 0.0, "{fault}, {kind}: the good light still renders");
        }
    }
    for kind in [LT, PT] {
        let (faults, _) = render_fault("none", kind);
        assert_eq!(
            faults.count() + faults.invalid_count(),
            0,
            "{:?}",
            faults.report()
        );
    }
}

// The CLI with a light that panics in half of its `next_beam` calls (hundreds of panics in
// this render), with RUST_BACKTRACE=1: the image is still written, and stderr holds one line for
// the call site with the count, not one message per panic (before: ~49 000 messages for a tiny
// render, gigabytes with backtraces). 4 KiB is generous for the few lines expected and far below
// even one message per panic.
#[test]
fn a_panicking_plugin_is_reported_once_per_call_site_with_a_count() {
    let bin = artifact_dir().join(format!("spectrace{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.exists(),
        "{} missing: run the README's test command",
        bin.display()
    );
    let scene = tmp("panicking.ron");
    std::fs::write(
        &scene,
        scene_text(r#"(name: "bad", type: "panicking", params: ())"#, 16),
    )
    .unwrap();
    let exr = tmp("panicking.exr");
    let out = Command::new(&bin)
        .arg("render")
        .arg(&scene)
        .arg("-o")
        .arg(&exr)
        .args([
            "--integrator",
            "lt",
            "--quiet",
            "--threads",
            "2",
            "--plugin",
        ])
        .arg(plugin_library("spectrace-fixture-panicking-light"))
        .env("RUST_BACKTRACE", "1")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "failed plugin calls make the command fail"
    );
    assert!(exr.exists(), "the image is still written");
    assert!(
        stderr.len() < 4096,
        "{} bytes of stderr:\n{}",
        stderr.len(),
        &stderr[..stderr.len().min(2000)]
    );
    let site_lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("at `next_beam panicked at"))
        .collect();
    assert_eq!(site_lines.len(), 1, "one line for the call site:\n{stderr}");
    let count: u64 = site_lines[0]
        .split_whitespace()
        .find_map(|w| w.parse().ok())
        .expect("the line carries the count");
    assert!(count > 100, "{count} panics counted: {stderr}");
    assert!(!stderr.contains("stack backtrace"), "{stderr}");
    for f in [scene, exr.clone(), exr.with_extension("png")] {
        let _ = std::fs::remove_file(f);
    }
}
