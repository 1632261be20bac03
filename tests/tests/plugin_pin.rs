//! Pinned plugin libraries (`host/src/scene_file/pin.rs`): a scene lists the libraries it needs,
//! by path or by path and SHA-256; a pinned library whose file hashes differently is refused
//! with both hashes named, the plain path form keeps working, and the hash `spectrace plugins`
//! prints is the file's SHA-256.

use spectrace::plugin::Registry;
use spectrace::scene_file::pin::sha256_hex;
use spectrace_tests::plugin_library;
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("spectrace-pin-{}-{name}", std::process::id()))
}

/// A scene file whose only interesting part is its `plugins` list (the rest is never built).
fn scene_with(plugins: &str, name: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(
        &p,
        format!("(\n    plugins: {plugins},\n    materials: [],\n    objects: [],\n)"),
    )
    .unwrap();
    p
}

#[test]
fn a_pinned_library_loads_only_with_its_own_hash() {
    let lib = plugin_library("spectrace-point-light");
    let actual = sha256_hex(&std::fs::read(&lib).unwrap());

    // The right pin (upper case as some tools print it): loaded, its hash recorded.
    let scene = scene_with(
        &format!(
            "[(path: \"{}\", sha256: \"{}\")]",
            lib.display(),
            actual.to_uppercase()
        ),
        "good.ron",
    );
    let mut r = Registry::new();
    r.load_scene_plugins(&scene)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.plugins().len(), 1);
    assert_eq!(r.plugins()[0].sha256.as_deref(), Some(actual.as_str()));

    // A wrong pin: refused, naming the scene, both hashes and the library.
    let wrong = sha256_hex(b"not the library");
    let scene_bad = scene_with(
        &format!("[(path: \"{}\", sha256: \"{wrong}\")]", lib.display()),
        "bad.ron",
    );
    let e = Registry::new().load_scene_plugins(&scene_bad).unwrap_err();
    assert!(
        e.contains(&wrong) && e.contains(&actual) && e.contains("mismatch"),
        "{e}"
    );
    assert!(e.contains("bad.ron") && e.contains("point_light"), "{e}");

    // The plain path form, relative to the scene file's directory.
    let dir = lib.parent().unwrap();
    let rel_scene = dir.join(format!("spectrace-pin-{}-plain.ron", std::process::id()));
    std::fs::write(
        &rel_scene,
        format!(
            "(plugins: [\"{}\"])",
            lib.file_name().unwrap().to_string_lossy()
        ),
    )
    .unwrap();
    let mut r = Registry::new();
    r.load_scene_plugins(&rel_scene)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.plugins().len(), 1);

    // A scene without the field loads nothing; a library already loaded is not loaded twice,
    // but its pin is still checked.
    let none = scene_with("[]", "none.ron");
    r.load_scene_plugins(&none).unwrap();
    r.load_scene_plugins(&scene).unwrap();
    assert_eq!(r.plugins().len(), 1);
    let e = r.load_scene_plugins(&scene_bad).unwrap_err();
    assert!(e.contains(&wrong) && e.contains(&actual), "{e}");
    for f in [scene, scene_bad, rel_scene, none] {
        let _ = std::fs::remove_file(f);
    }
}

// The whole scene parser accepts the field in both forms (it is part of the scene format).
#[test]
fn the_scene_format_accepts_both_forms() {
    let text = r#"(plugins: ["a.so", (path: "b.so", sha256: "00")])"#;
    let d: spectrace::scene_file::description::SceneDescription = ron::from_str(text).unwrap();
    assert_eq!(d.plugins.len(), 2);
    assert_eq!(d.plugins[1].path(), "b.so");
}
