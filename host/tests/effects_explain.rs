//! Scene analysis on the bundled scenes that need no plugin: each names the effects it calls
//! for (exact sets: the analysis is deterministic), and `spectrace explain` runs on them.
//! Run: `cargo test --release -p spectrace --test effects_explain`.

use spectrace::effects::{analyze, Effect};
use spectrace::integrator::RenderPlan;
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
    assert_eq!(
        effects_of("thin_film.ron"),
        vec![ThinFilm, DeltaBsdfs, SpecularChains, SpectrallyVarying]
    );
    assert_eq!(
        effects_of("laser.ron"),
        vec![
            LineEmission,
            DeltaLights,
            DeltaBsdfs,
            SpecularChains,
            SpectrallyVarying
        ]
    );
    assert_eq!(
        effects_of("line_lamps.ron"),
        vec![LineEmission, DeltaLights, SpectrallyVarying]
    );
    assert_eq!(
        effects_of("prism.ron"),
        vec![Dispersion, DeltaBsdfs, SpecularChains, SpectrallyVarying]
    );
}

/// The render plan of each new bundled scene turns on what its effects call for (and nothing
/// else): thin film for `thin_film.ron`, dispersion for `prism.ron`, wavelengths from the
/// lights' spectra for the line lamps, from the lines alone for the lasers (all emission is
/// lines there).
#[test]
fn bundled_scenes_get_their_render_plan() {
    let plan = |scene: &str| {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes")
            .join(scene);
        let s = load_scene_file_with(&path, &[&BuiltinFactory], &RepresentationOptions::default())
            .unwrap();
        RenderPlan::auto(&s)
    };
    let p = plan("thin_film.ron");
    assert!(p.thin_film() && !p.dispersion() && !p.emission_wavelengths());
    let p = plan("prism.ron");
    assert!(p.dispersion() && !p.thin_film() && !p.emission_wavelengths());
    let p = plan("line_lamps.ron");
    assert!(p.emission_wavelengths() && p.mixture().emission_weight() == 0.5);
    let p = plan("laser.ron");
    assert!(p.emission_wavelengths() && p.mixture().emission_weight() == 1.0);
    assert_eq!(
        p.light_paths_needed().len(),
        2,
        "{:?}",
        p.light_paths_needed()
    );
    let p = plan("cornell_box.ron");
    assert!(!p.dispersion() && !p.thin_film() && !p.fluorescence() && !p.emission_wavelengths());
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
    // The plan options: accepted, and a bad one refused (exit 1, not a panic).
    assert_eq!(
        spectrace::cli::main_with_args([
            "spectrace",
            "explain",
            scene.to_str().unwrap(),
            "--effects",
            "all",
            "--effect",
            "dispersion=off",
        ]),
        0
    );
    assert_eq!(
        spectrace::cli::main_with_args([
            "spectrace",
            "explain",
            scene.to_str().unwrap(),
            "--effect",
            "delta-lights=off",
        ]),
        1
    );
}
