//! Helpers shared by the workspace integration tests.

use spectrace::integrator::{IntegratorKind, RenderSettings, SampleBudget};
use spectrace::plugin::factory::RegistryFactory;
use spectrace::scene::Scene;
use std::path::PathBuf;

/// The directory cargo put this test's artifacts in (`target/<profile>`), where the plugin
/// libraries built by `cargo build --workspace` live beside it.
pub fn artifact_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    // target/<profile>/deps/<test-binary>
    exe.parent()
        .and_then(|deps| deps.parent())
        .expect("test binary lives in target/<profile>/deps")
        .to_path_buf()
}

/// Path of the built plugin library of crate `name` (dashes or underscores).
///
/// Panics with the command to run when it is missing: `cargo test` does not build `cdylib`s,
/// the README's test command does.
pub fn plugin_library(name: &str) -> PathBuf {
    let file = format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    );
    let path = artifact_dir().join(&file);
    assert!(
        path.exists(),
        "{} is missing: build the plugin libraries first with the README's test command \
         (`cargo build --workspace` in the same profile)",
        path.display()
    );
    path
}

/// Render `scene`, built by `factory`, with `kind` (`spp` samples per pixel, `seed`, two
/// threads), effects as `--effects auto` chooses them; XYZ per pixel. Panics when the render
/// fails or a plugin object faulted (the plugin-versus-built-in comparisons need a clean run).
pub fn render_auto_xyz(
    scene: &Scene,
    factory: &RegistryFactory,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
) -> Vec<[f64; 3]> {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let plan = spectrace::integrator::RenderPlan::new(
        scene,
        &spectrace::integrator::EffectsRequest {
            mode: spectrace::integrator::EffectsMode::Auto,
            forced: vec![],
            ..every_light_subpath()
        },
    );
    let out = spectrace::integrator::select::render_planned(
        scene,
        &plan,
        &settings,
        kind,
        false,
        &|_, _| {},
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let faults = factory.faults();
    assert_eq!(faults.count(), 0, "{:?}", faults.report());
    assert_eq!(faults.invalid_count(), 0, "{:?}", faults.report());
    out.result.image.xyz
}

/// The effects request of `--effect light-subpaths=1`, everything else automatic. BDPT's pilot
/// may hand every camera sample to the path tracer where light subpaths do not pay (q = 0); the
/// tests that compare integrators or plugin objects under BDPT keep BDPT's own estimator (its
/// adjoint evaluations, light subpaths and connections) by tracing light subpaths in every
/// camera sample (the pilot still chooses how many, where delta surfaces make caustics). For pt
/// and lt it changes nothing.
pub fn every_light_subpath() -> spectrace::integrator::EffectsRequest {
    spectrace::integrator::EffectsRequest {
        light_subpaths: spectrace::integrator::LightSubpaths::Fraction(1.0),
        ..Default::default()
    }
}

/// `render_with(scene, settings, kind, false, …)` under [`every_light_subpath`].
pub fn render_every_light_subpath(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
) -> Result<spectrace::integrator::IntegratorOutput, spectrace::integrator::RenderError> {
    let plan = spectrace::integrator::RenderPlan::new(scene, &every_light_subpath());
    spectrace::integrator::select::render_planned(
        scene,
        &plan,
        settings,
        kind,
        false,
        &|_, _| {},
        None,
    )
}
