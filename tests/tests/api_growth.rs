//! API growth without breaking plugins (the compatibility rule in `plugin-api/src/module.rs`).
//!
//! `plugins/fixtures/api-0.1.0/` is a frozen, verbatim copy of the plugin API's source as it was
//! before the interface grew (extension module v1: beams in other representations).
//! `plugins/fixtures/api-0.1.0-light/` is a plugin built against that copy. This test builds it
//! with cargo as its own project, loads it into the current host, and renders it: it must load
//! (the layout check passes because the root module and its vtables did not change), the
//! missing extension must read as absent (its lights are native), its call back into the host
//! (an SPD lent by the host) must work, and its light must render like the built-in point light
//! of the same emission.
//!
//! `plugins/fixtures/api-ext-v1/` to `api-ext-v7/` freeze the API after extensions v1 to v7;
//! the plugins built on them (`api-ext-v1-plugin` to `api-ext-v7-plugin`) must load and render
//! the same way, each seeing the later extensions as absent.
//!
//! This test is what showed that growing the root module or a trait vtable after its
//! `last_prefix_field` marker, as abi_stable allows, still locks every older plugin out: the
//! layout check accepts a library with MORE prefix fields than the host, never fewer.

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

#[test]
fn a_plugin_built_against_the_frozen_0_1_0_api_loads_and_renders() {
    let lib = build_external(
        "plugins/fixtures/api-0.1.0-light",
        "spectrace_fixture_api_0_1_0_light",
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&lib)
        .unwrap_or_else(|e| panic!("the 0.1.0 plugin must load: {}", e.verbose()));
    let plugin = registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "api-0.1.0-light")
        .expect("loaded")
        .clone();
    assert_eq!(plugin.info.api_version.as_str(), "0.1.0");
    assert!(
        spectrace::plugin::representation::extension::extensions_v1(&plugin.path)
            .unwrap()
            .is_none(),
        "a library built before extension module v1 existed does not export it"
    );
    assert!(
        spectrace::plugin::representation::declared(&registry, "frozen_point")
            .unwrap()
            .is_none(),
        "and its lights are then native"
    );
    let registry = Arc::new(registry);

    let plugin_scene = tmp("plugin.ron");
    std::fs::write(
        &plugin_scene,
        scene_text(r#"(name: "bulb", type: "frozen_point", params: (position: (0, 1, 0), power_w: 20, spd: "d65"))"#),
    )
    .unwrap();
    let native_scene = tmp("native.ron");
    std::fs::write(
        &native_scene,
        scene_text(r#"(name: "bulb", type: "point", params: (position: (0, 1, 0), power: 20, spd: "d65"))"#),
    )
    .unwrap();

    // Same emission, two implementations: the mean Y over the image agrees within 4 standard
    // errors of the difference (estimated from 4 seeds each), and the test is sharp enough that
    // 4σ stays below 2% (a broken old-API path, e.g. lost power or a wrong SPD, is far larger).
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
        "old-API plugin {mp:.6} ± {sp:.2e}, built-in point {mn:.6} ± {sn:.2e} ({:+.3}%, {:+.1} σ)",
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

/// A plugin built against the API of extension v1, before v2 (`plugins/fixtures/api-ext-v1/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v1-plugin/` built
/// on it) keeps loading: it exports extension v1 but not v2, so the host finds v1, reads v2 as
/// absent and builds its objects through the root module alone. Quantity: its grey material's
/// `eval` through the host adapter (exactly ρ/π, f32 rounding: 1e-6), and its point light's
/// image mean Y against the built-in point light of the same emission (light tracing, 4 seeds of
/// 256 spp each): within 4 standard errors of the difference, with 4σ below 2% so that a broken
/// fall-back (lost power, wrong spectrum) would be seen.
#[test]
fn a_plugin_built_against_extension_v1_loads_and_renders() {
    use spectrace::material::{Material as _, ShadingContext, TransportMode};
    use spectrace_plugin_api::abi::std_types::RStr;
    use spectrace_plugin_api::module::ObjectSource;
    let lib = build_external(
        "plugins/fixtures/api-ext-v1-plugin",
        "spectrace_fixture_api_ext_v1_plugin",
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&lib)
        .unwrap_or_else(|e| panic!("the v1 plugin must load: {}", e.verbose()));
    let plugin = registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "api-ext-v1-plugin")
        .expect("loaded")
        .clone();
    assert!(
        spectrace::plugin::representation::extension::extensions_v1(&plugin.path)
            .unwrap()
            .is_some(),
        "it exports extension v1"
    );
    assert!(
        spectrace::plugin::extension_v2::extensions_v2(&plugin.path)
            .unwrap()
            .is_none(),
        "a library built before extension v2 existed does not export it"
    );
    let source = ObjectSource::Params(RStr::from_str("(reflectance: 0.5)"));
    assert!(registry
        .create_plugin_material_v2("v1_grey", source)
        .unwrap()
        .is_none());
    let grey = spectrace::plugin::adapter::PluginMaterial::new(
        registry.create_plugin_material("v1_grey", source).unwrap(),
        spectrace::plugin::adapter::Origin {
            label: "v1_grey".into(),
            faults: PluginFaults::new(),
        },
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

    let plugin_scene = tmp("v1-plugin.ron");
    std::fs::write(
        &plugin_scene,
        scene_text(r#"(name: "bulb", type: "v1_point", params: (position: (0, 1, 0), power_w: 20, spd: "d65"))"#),
    )
    .unwrap();
    let native_scene = tmp("v1-native.ron");
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
        "v1 plugin {mp:.6} ± {sp:.2e}, built-in point {mn:.6} ± {sn:.2e} ({:+.3}%, {:+.1} σ)",
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

/// A plugin built against the API of extension v2, before v3 (`plugins/fixtures/api-ext-v2/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v2-plugin/` built
/// on it) keeps loading: it exports extensions v1 and v2 but not v3, so the host finds v2, reads
/// v3 as absent and builds its material through v2. That material declares FLUORESCENT, which
/// the v2 API could not back with data: the scene warns (naming the object) that it renders its
/// reflectance only. Quantity: the image mean Y of a floor of that material (ρ = 0.5) under the
/// built-in point light against the built-in `lambertian` of the same reflectance (light
/// tracing, 4 seeds of 256 spp each): within 4 standard errors of the difference, with 4σ below
/// 2% so that a broken fall-back (a lost or doubled reflectance) would be seen.
#[test]
fn a_plugin_built_against_extension_v2_loads_and_renders() {
    let lib = build_external(
        "plugins/fixtures/api-ext-v2-plugin",
        "spectrace_fixture_api_ext_v2_plugin",
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&lib)
        .unwrap_or_else(|e| panic!("the v2 plugin must load: {}", e.verbose()));
    let plugin = registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "api-ext-v2-plugin")
        .expect("loaded")
        .clone();
    assert!(
        spectrace::plugin::representation::extension::extensions_v1(&plugin.path)
            .unwrap()
            .is_some()
    );
    assert!(spectrace::plugin::extension_v2::extensions_v2(&plugin.path)
        .unwrap()
        .is_some());
    assert!(
        spectrace::plugin::extension_v3::extensions_v3(&plugin.path)
            .unwrap()
            .is_none(),
        "a library built before extension v3 existed does not export it"
    );
    let source = spectrace_plugin_api::module::ObjectSource::Params(
        spectrace_plugin_api::abi::std_types::RStr::from_str("(reflectance: 0.5)"),
    );
    assert!(registry
        .create_plugin_material_v3("v2_fluorescent_grey", source)
        .unwrap()
        .is_none());
    let registry = Arc::new(registry);

    let light =
        r#"(name: "bulb", type: "point", params: (position: (0, 1, 0), power: 20, spd: "d65"))"#;
    let plugin_scene = tmp("v2-plugin.ron");
    std::fs::write(
        &plugin_scene,
        scene_text_with(
            r#"(name: "floor", type: "v2_fluorescent_grey", params: (reflectance: 0.5))"#,
            light,
        ),
    )
    .unwrap();
    let native_scene = tmp("v2-native.ron");
    std::fs::write(
        &native_scene,
        scene_text_with(
            r#"(name: "floor", type: "lambertian", params: (reflectance: 0.5))"#,
            light,
        ),
    )
    .unwrap();
    {
        let plugins = PluginFactory::new(registry.clone(), PluginFaults::new());
        let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
        let scene = load_scene_file(&plugin_scene, &factories).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            scene
                .warnings()
                .iter()
                .any(|w| w.contains("object \"floor\"") && w.contains("declares FLUORESCENT")),
            "{:?}",
            scene.warnings()
        );
        assert!(!scene.objects.fluorescence());
    }
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
        "v2 plugin {mp:.6} ± {sp:.2e}, built-in lambertian {mn:.6} ± {sn:.2e} ({:+.3}%, {:+.1} σ)",
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

/// Two scene files with one floor (ρ = 0.5) under the built-in point light: the plugin's
/// `{tag}_grey` and the built-in `lambertian` (the fall-back tests of the frozen APIs).
fn grey_floor_scenes(tag: &str) -> (PathBuf, PathBuf) {
    let light =
        r#"(name: "bulb", type: "point", params: (position: (0, 1, 0), power: 20, spd: "d65"))"#;
    let write = |name: String, ty: String| {
        let path = tmp(&name);
        let object = format!(r#"(name: "floor", type: "{ty}", params: (reflectance: 0.5))"#);
        std::fs::write(&path, scene_text_with(&object, light)).unwrap();
        path
    };
    (
        write(format!("{tag}-plugin.ron"), format!("{tag}_grey")),
        write(format!("{tag}-native.ron"), "lambertian".to_string()),
    )
}

/// The image mean Y of the plugin's floor against the built-in's (light tracing, 4 seeds of
/// 256 spp each): within 4 standard errors of the difference, with 4σ below 2% so that a broken
/// fall-back (a lost or doubled reflectance) would be seen. No plugin faults. Removes the files.
fn assert_renders_like_the_builtin(
    registry: &Arc<spectrace::plugin::Registry>,
    plugin_scene: PathBuf,
    native_scene: PathBuf,
    tag: &str,
) {
    let mut p = Vec::new();
    let mut n = Vec::new();
    for seed in 0..4 {
        let (m, faults) = render_mean(&plugin_scene, registry, seed);
        assert_eq!(faults.count(), 0, "{:?}", faults.report());
        assert_eq!(faults.invalid_count(), 0, "{:?}", faults.report());
        p.push(m);
        n.push(render_mean(&native_scene, registry, 100 + seed).0);
    }
    let ((mp, sp), (mn, sn)) = (mean_and_se(&p), mean_and_se(&n));
    let se = (sp * sp + sn * sn).sqrt();
    eprintln!(
        "{tag} plugin {mp:.6} ± {sp:.2e}, built-in lambertian {mn:.6} ± {sn:.2e} ({:+.3}%, {:+.1} σ)",
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

/// The prelude of the fall-back tests of the frozen APIs: builds the fixture
/// `plugins/fixtures/{dir}` (a plugin of that name on a frozen copy of the API), loads it next to
/// the built-ins, and checks what a library built before the next extension must show: its
/// newest extension module is found (`newest`), the next one is not (`next`: "a library built
/// before that extension existed does not export it"), and the next version's material
/// constructor answers "absent" for its `{tag}_grey` (`create_next`, given the registry and the
/// material's parameters), so the host falls back.
fn load_frozen_fixture(
    dir: &str,
    tag: &str,
    newest: impl Fn(&Path) -> bool,
    next: impl Fn(&Path) -> bool,
    create_next: impl Fn(
        &spectrace::plugin::Registry,
        spectrace_plugin_api::module::ObjectSource<'_>,
    ) -> bool,
) -> Arc<spectrace::plugin::Registry> {
    let lib = build_external(
        &format!("plugins/fixtures/{dir}"),
        &format!("spectrace_fixture_{}", dir.replace('-', "_")),
    );
    let mut registry = spectrace::plugin::builtin_registry();
    registry
        .load_plugin(&lib)
        .unwrap_or_else(|e| panic!("the {tag} plugin must load: {}", e.verbose()));
    let plugin = registry
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == dir)
        .expect("loaded")
        .clone();
    assert!(newest(&plugin.path), "{dir} exports its newest extension");
    assert!(
        !next(&plugin.path),
        "a library built before the extension after {tag} existed does not export it"
    );
    let source = spectrace_plugin_api::module::ObjectSource::Params(
        spectrace_plugin_api::abi::std_types::RStr::from_str("(reflectance: 0.5)"),
    );
    assert!(
        !create_next(&registry, source),
        "{tag}_grey is not built through the extension after {tag}"
    );
    Arc::new(registry)
}

/// The floor material of each of the two grey-floor scenes (plugin, built-in), as built.
fn floors(
    registry: &Arc<spectrace::plugin::Registry>,
    scenes: [&PathBuf; 2],
) -> [Arc<dyn spectrace::material::Material>; 2] {
    scenes.map(|scene| {
        let plugins = PluginFactory::new(registry.clone(), PluginFaults::new());
        let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
        let scene = load_scene_file(scene, &factories).unwrap_or_else(|e| panic!("{e}"));
        let floor = &scene.objects.objects()[0];
        assert_eq!(floor.name, "floor");
        floor.material.clone()
    })
}

/// A plugin built against the API of extension v3, before v4 (`plugins/fixtures/api-ext-v3/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v3-plugin/` built
/// on it) keeps loading: it exports extensions v1–v3 but not v4, so the host reads v4 as absent
/// and builds its material through v3. Its grey material cannot declare itself spectrally flat
/// (that arrived with v4), so the host takes it as not flat, which is always safe: its paths keep
/// the colour of their four wavelengths, while the built-in grey `lambertian` is flat. Quantity:
/// the image mean Y of a floor of that material (ρ = 0.5) under the built-in point light against
/// the built-in `lambertian` of the same reflectance (light tracing, 4 seeds of 256 spp each):
/// within 4 standard errors of the difference, with 4σ below 2% so that a broken fall-back (a
/// lost or doubled reflectance) would be seen.
#[test]
fn a_plugin_built_against_extension_v3_loads_and_renders() {
    use spectrace::plugin::{extension_v3::extensions_v3, extension_v4::extensions_v4};
    let registry = load_frozen_fixture(
        "api-ext-v3-plugin",
        "v3",
        |p| extensions_v3(p).unwrap().is_some(),
        |p| extensions_v4(p).unwrap().is_some(),
        |r, s| r.create_plugin_material_v4("v3_grey", s).unwrap().is_some(),
    );
    let (plugin_scene, native_scene) = grey_floor_scenes("v3");
    let [plugin, native] = floors(&registry, [&plugin_scene, &native_scene]);
    assert!(!plugin.spectrally_flat());
    assert!(native.spectrally_flat());
    assert_renders_like_the_builtin(&registry, plugin_scene, native_scene, "v3");
}

/// A plugin built against the API of extension v4, before v5 (`plugins/fixtures/api-ext-v4/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v4-plugin/` built
/// on it) keeps loading: it exports extensions v1–v4 but not v5, so the host reads v5 as absent
/// and builds its material through v4. Its grey material declares itself spectrally flat (v4;
/// checked and kept) but cannot declare one BSDF value for every direction (that arrived with
/// v5), so the host evaluates it again for next-event estimation, which is always safe, while
/// the built-in `lambertian` lends its sampled value. Quantity and tolerance as for v3.
#[test]
fn a_plugin_built_against_extension_v4_loads_and_renders() {
    use spectrace::plugin::{extension_v4::extensions_v4, extension_v5::extensions_v5};
    let registry = load_frozen_fixture(
        "api-ext-v4-plugin",
        "v4",
        |p| extensions_v4(p).unwrap().is_some(),
        |p| extensions_v5(p).unwrap().is_some(),
        |r, s| r.create_plugin_material_v5("v4_grey", s).unwrap().is_some(),
    );
    let (plugin_scene, native_scene) = grey_floor_scenes("v4");
    let [plugin, native] = floors(&registry, [&plugin_scene, &native_scene]);
    assert!(plugin.spectrally_flat() && native.spectrally_flat());
    assert!(!plugin.f_same_for_all_directions());
    assert!(native.f_same_for_all_directions());
    assert_renders_like_the_builtin(&registry, plugin_scene, native_scene, "v4");
}

/// A plugin built against the API of extension v5, before v6 (`plugins/fixtures/api-ext-v5/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v5-plugin/` built
/// on it) keeps loading: it exports extensions v1–v5 but not v6, so the host reads v6 as absent
/// and builds its material through v5. Its grey material declares itself spectrally flat (v4)
/// and one BSDF value for every direction (v5), both checked and kept, but cannot declare that
/// it samples with the cosine-weighted density (that arrived with v6), so the host asks it for
/// its density, which is always safe, while the built-in `lambertian` has it computed. Quantity
/// and tolerance as for v3.
#[test]
fn a_plugin_built_against_extension_v5_loads_and_renders() {
    use spectrace::plugin::{extension_v5::extensions_v5, extension_v6::extensions_v6};
    let registry = load_frozen_fixture(
        "api-ext-v5-plugin",
        "v5",
        |p| extensions_v5(p).unwrap().is_some(),
        |p| extensions_v6(p).unwrap().is_some(),
        |r, s| r.create_plugin_material_v6("v5_grey", s).unwrap().is_some(),
    );
    let (plugin_scene, native_scene) = grey_floor_scenes("v5");
    let [plugin, native] = floors(&registry, [&plugin_scene, &native_scene]);
    assert!(plugin.spectrally_flat() && native.spectrally_flat());
    assert!(plugin.f_same_for_all_directions() && native.f_same_for_all_directions());
    assert!(!plugin.cosine_weighted_pdf());
    assert!(native.cosine_weighted_pdf());
    assert_renders_like_the_builtin(&registry, plugin_scene, native_scene, "v5");
}

/// A plugin built against the API of extension v6, before v7 (`plugins/fixtures/api-ext-v6/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v6-plugin/` built
/// on it) keeps loading: it exports extensions v1–v6 but not v7, so the host reads v7 as absent
/// (its observers would be called per wavelength; it has none) and builds its material through
/// v6 (and its observer `v6_eye` is not built through v7). Its grey material declares itself flat, lends its sampled value and samples with the
/// cosine-weighted density (each checked by the host when built), as the built-in grey
/// `lambertian` does. Quantity: the image mean Y of a floor of that material (ρ = 0.5) under the
/// built-in point light against the built-in material's, as for the earlier versions
/// (`assert_renders_like_the_builtin`).
#[test]
fn a_plugin_built_against_extension_v6_loads_and_renders() {
    use spectrace::plugin::{extension_v6::extensions_v6, extension_v7::extensions_v7};
    let registry = load_frozen_fixture(
        "api-ext-v6-plugin",
        "v6",
        |p| extensions_v6(p).unwrap().is_some(),
        |p| extensions_v7(p).unwrap().is_some(),
        |r, s| !matches!(r.create_plugin_observer_v7("v6_eye", s), Ok(None)),
    );
    let (plugin_scene, native_scene) = grey_floor_scenes("v6");
    let [plugin, native] = floors(&registry, [&plugin_scene, &native_scene]);
    assert!(plugin.spectrally_flat() && native.spectrally_flat());
    assert!(plugin.f_same_for_all_directions() && native.f_same_for_all_directions());
    assert!(plugin.cosine_weighted_pdf() && native.cosine_weighted_pdf());
    assert_renders_like_the_builtin(&registry, plugin_scene, native_scene, "v6");
}

/// A plugin built against the API of extension v7, before v8 (`plugins/fixtures/api-ext-v7/`, a
/// frozen copy of the API source at that point, and `plugins/fixtures/api-ext-v7-plugin/` built
/// on it) keeps loading: it exports extensions v1–v7 but not v8, so the host reads v8 as absent
/// and builds its material through v7 (its calls through v7's face: the wavelengths by
/// reference, a status word, the error through a slot). Its grey material declares itself flat,
/// lends its sampled value and samples with the cosine-weighted density (each checked by the
/// host through the v7 face when built), as the built-in grey `lambertian` does. Quantity: the
/// image mean Y of a floor of that material (ρ = 0.5) under the built-in point light against the
/// built-in material's, as for the earlier versions (`assert_renders_like_the_builtin`).
#[test]
fn a_plugin_built_against_extension_v7_loads_and_renders() {
    use spectrace::plugin::{extension_v7::extensions_v7, extension_v8::extensions_v8};
    let registry = load_frozen_fixture(
        "api-ext-v7-plugin",
        "v7",
        |p| extensions_v7(p).unwrap().is_some(),
        |p| extensions_v8(p).unwrap().is_some(),
        |r, s| r.create_plugin_material_v8("v7_grey", s).unwrap().is_some(),
    );
    assert!(
        registry
            .create_plugin_material_v7(
                "v7_grey",
                spectrace_plugin_api::module::ObjectSource::Params(
                    spectrace_plugin_api::abi::std_types::RStr::from_str("(reflectance: 0.5)"),
                ),
            )
            .unwrap()
            .is_some(),
        "v7_grey is built through v7"
    );
    let (plugin_scene, native_scene) = grey_floor_scenes("v7");
    let [plugin, native] = floors(&registry, [&plugin_scene, &native_scene]);
    assert!(plugin.spectrally_flat() && native.spectrally_flat());
    assert!(plugin.f_same_for_all_directions() && native.f_same_for_all_directions());
    assert!(plugin.cosine_weighted_pdf() && native.cosine_weighted_pdf());
    assert_renders_like_the_builtin(&registry, plugin_scene, native_scene, "v7");
}
