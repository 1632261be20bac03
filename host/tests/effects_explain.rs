//! Scene analysis on the bundled scenes that need no plugin: each names the effects it calls
//! for (exact sets: the analysis is deterministic), and `spectrace explain` runs on them.
//! Run: `cargo test --release -p spectrace --test effects_explain`.

use spectrace::effects::{analyze, Effect};
use spectrace::scene::{load_scene_file_with, BuiltinFactory, RepresentationOptions};
use std::path::PathBuf;

fn effects_of(scene: &str) -> Vec<Effect> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(scene);
    let s =
        load_scene_file_with(&path, &[&BuiltinFactory], &RepresentationOptions::default()).unwrap();
    analyze(&s).findings().iter().map(|f| f.effect).collect()
}

#[test]
fn bundled_scenes_name_their_effects() {
    use Effect::*;
    assert_eq!(effects_of("cornell_box.ron"), vec![SpectrallyVarying]);
    assert_eq!(
        effects_of("caustic.ron"),
        vec![DeltaBsdfs, SpecularChains, SpectrallyVarying]
    );
    assert_eq!(
        effects_of("materials.ron"),
        vec![
            Dispersion,
            DeltaLights,
            DeltaBsdfs,
            SpecularChains,
            SpectrallyVarying
        ]
    );
    assert_eq!(
        effects_of("spot_mirror.ron"),
        vec![DeltaLights, DeltaBsdfs, SpecularChains, SpectrallyVarying]
    );
    assert_eq!(
        effects_of("fluorescence.ron"),
        vec![Fluorescence, SpectrallyVarying]
    );
}

#[test]
fn explain_command_runs_and_rejects_a_missing_scene() {
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/materials.ron");
    assert_eq!(
        spectrace::cli::main_with_args(["spectrace", "explain", scene.to_str().unwrap()]),
        0
    );
    assert_eq!(
        spectrace::cli::main_with_args(["spectrace", "explain", "/nonexistent/scene.ron"]),
        1
    );
}
