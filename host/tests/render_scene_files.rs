//! Scene files: every shipped scene loads and renders a few samples without NaN/Inf; bad
//! scenes give errors that name the file and the line/column (syntax) or the item and parameter
//! (semantics), never a panic.

use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::scene::{load_scene_file, parse_scene_str, BuiltinFactory, SceneError};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

/// Every `scenes/*.ron` that needs no plugin (`plugin_*.ron` and `mixed-plugins.ron` are tested
/// with their plugins, in `tests/tests/`)
/// builds, and 1 spp of every camera renders with no non-finite pixel.
#[test]
fn shipped_scenes_load_and_render() {
    let mut count = 0;
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".ron") || name.starts_with("plugin_") || name == "mixed-plugins.ron" {
            continue;
        }
        let scene = load_scene_file(&path, &[&BuiltinFactory])
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for cam in scene.cameras.cameras() {
            let s = RenderSettings {
                budget: SampleBudget::Spp(1),
                camera: Some(cam.name.clone()),
                threads: Some(2),
                ..RenderSettings::default()
            };
            let img = render(&scene, &s, &|_, _| {}, None).unwrap().image;
            assert_eq!(
                img.non_finite_count(),
                0,
                "{} / {}",
                path.display(),
                cam.name
            );
        }
        count += 1;
    }
    assert!(count >= 2, "expected the shipped scenes, found {count}");
}

fn write_tmp(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const GOOD_TAIL: &str = r#"
    cameras: [(name: "c", type: "pinhole", params: (position: (0, 0, 5), look_at: (0, 0, 0), resolution: (8, 8)))],
)"#;

/// A RON syntax error reports file:line:column (the missing comma is on line 3).
#[test]
fn syntax_errors_name_line_and_column() {
    let text = "(\n    materials: [\n        (name: \"a\" type: \"lambertian\"),\n    ],\n)";
    let e = parse_scene_str(text, Path::new("bad.ron")).unwrap_err();
    match &e {
        SceneError::Syntax { line, column, .. } => {
            assert_eq!(*line, 3, "{e}");
            assert!(*column > 1);
        }
        other => panic!("expected a syntax error, got {other}"),
    }
    assert!(e.to_string().starts_with("bad.ron:3:"), "{e}");
}

/// Semantic errors name the item and the parameter: unknown material type (listing the known
/// ones), a missing parameter, a wrong parameter type, an unknown material reference, a missing
/// mesh file (relative to the scene file), and an unknown parameter (typo).
#[test]
fn semantic_errors_name_item_and_parameter() {
    let cases = [
        (
            r#"(materials: [(name: "m", type: "velvet")],
                objects: [(name: "o", type: "sphere", material: "m", params: (radius: 1))],"#,
            &["material \"m\"", "velvet", "lambertian"][..],
        ),
        (
            r#"(materials: [(name: "m", type: "lambertian")],
                objects: [(name: "o", type: "sphere", material: "m", params: ())],"#,
            &["object \"o\"", "radius", "missing"][..],
        ),
        (
            r#"(materials: [(name: "m", type: "lambertian", params: (reflectance: true))],
                objects: [(name: "o", type: "sphere", material: "m", params: (radius: 1))],"#,
            &["material \"m\"", "reflectance", "bool"][..],
        ),
        (
            r#"(materials: [(name: "m", type: "lambertian")],
                objects: [(name: "o", type: "sphere", material: "nope", params: (radius: 1))],"#,
            &["object \"o\"", "nope"][..],
        ),
        (
            r#"(materials: [(name: "m", type: "lambertian")],
                objects: [(name: "o", type: "obj", material: "m", params: (file: "missing.obj"))],"#,
            &["object \"o\"", "missing.obj"][..],
        ),
        (
            r#"(materials: [(name: "m", type: "conductor", params: (metal: "gold", roughnes: 0.1))],
                objects: [(name: "o", type: "sphere", material: "m", params: (radius: 1))],"#,
            &["material \"m\"", "roughnes", "unknown parameter"][..],
        ),
    ];
    for (i, (head, needles)) in cases.iter().enumerate() {
        let path = write_tmp(&format!("case{i}.ron"), &format!("{head}{GOOD_TAIL}"));
        let e = load_scene_file(&path, &[&BuiltinFactory])
            .unwrap_err()
            .to_string();
        assert!(e.contains(&format!("case{i}.ron")), "case {i}: {e}");
        for n in *needles {
            assert!(e.contains(n), "case {i}: `{n}` not in: {e}");
        }
    }
    // A well-formed scene with a relative OBJ path next to the scene file loads.
    write_tmp("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let ok = write_tmp(
        "ok.ron",
        &format!(
            "{}{GOOD_TAIL}",
            r#"(materials: [(name: "m", type: "lambertian", params: (reflectance: (rgb: (0.2, 0.5, 0.9))))],
                objects: [(name: "o", type: "obj", material: "m", params: (file: "tri.obj"))],"#
        ),
    );
    load_scene_file(&ok, &[&BuiltinFactory]).unwrap();
    let missing = load_scene_file(Path::new("/nonexistent/scene.ron"), &[&BuiltinFactory]);
    assert!(missing
        .unwrap_err()
        .to_string()
        .contains("/nonexistent/scene.ron"));
}
