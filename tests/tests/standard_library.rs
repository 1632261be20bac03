//! The standard set as a library (`plugins/standard`): the host's SPD types and CIE observers
//! loaded from a plugin library build the same objects as the built-ins, and render the same
//! image; loaded next to the built-ins, the library is refused naming both providers.

use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::RegistryFactory;
use spectrace::plugin::{Kind, Registry};
use spectrace::scene::{FactoryContext, ObjectFactory};
use spectrace_tests::plugin_library;
use std::sync::Arc;

fn library() -> std::path::PathBuf {
    plugin_library("spectrace-standard")
}

/// The built-ins with the library's types in place of those it exports (`--replace-builtins`).
fn library_registry() -> Registry {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin_replacing_builtins(&library()).unwrap();
    assert!(r.plugin_for(Kind::Spd, "spec").unwrap().is_some());
    assert!(r.plugin_for(Kind::Observer, "cie1931-2").unwrap().is_some());
    assert!(r
        .plugin_for(Kind::Material, "lambertian")
        .unwrap()
        .is_none());
    r
}

fn factory(r: Registry) -> RegistryFactory {
    RegistryFactory::new(Arc::new(r), PluginFaults::new())
}

fn ctx(f: &RegistryFactory) -> FactoryContext {
    f.context(std::path::Path::new("."), "test".into())
}

#[test]
fn next_to_the_builtins_the_library_is_refused_naming_both() {
    let mut r = spectrace::plugin::builtin_registry();
    let e = r.load_plugin(&library()).unwrap_err().to_string();
    assert!(
        e.contains("duplicate") && e.contains("built-in") && e.contains("plugin `standard`"),
        "{e}"
    );
    assert!(r.plugins().is_empty());
}

/// Quantity: value, pdf and sampled wavelength of the `spec` and `table` SPD types, and x̄ȳz̄
/// of the four CIE observers, at 471 wavelengths (360–830 nm), library against built-in.
/// Tolerance: none: both run the same host code on the same f64 parameters and the plugin
/// interface passes f64 unchanged.
#[test]
fn library_types_sample_exactly_like_the_builtins() {
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(library_registry());
    let spds: [(&str, &str); 3] = [
        ("spec", "(spec: \"blackbody:3000\")"),
        ("spec", "(spec: \"fl11\")"),
        (
            "table",
            "(values: [(400, 1), (500, 3), (600, 0.5), (700, 2)])",
        ),
    ];
    for (ty, params) in spds {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin.spd(ty, &params, &ctx(&builtin)).unwrap();
        let b = lib.spd(ty, &params, &ctx(&lib)).unwrap();
        assert!(
            lib.registry().plugin_for(Kind::Spd, ty).unwrap().is_some(),
            "{ty} comes from the library"
        );
        for i in 0..=470 {
            let nm = 360.0 + i as f64;
            let u = i as f64 / 471.0;
            assert_eq!(a.value(nm), b.value(nm), "{ty} value at {nm}");
            assert_eq!(a.pdf(nm), b.pdf(nm), "{ty} pdf at {nm}");
            assert_eq!(a.sample(u).lambda, b.sample(u).lambda, "{ty} sample at {u}");
        }
    }
    for name in ["cie1931-2", "cie1964-10", "cie2015-2", "cie2015-10"] {
        let a = builtin
            .observer(name, &ron::Value::Unit, &ctx(&builtin))
            .unwrap();
        let b = lib.observer(name, &ron::Value::Unit, &ctx(&lib)).unwrap();
        assert_eq!(a.range(), b.range(), "{name}");
        for i in 0..=470 {
            let nm = 360.0 + i as f64;
            assert_eq!(a.xyz_bar(nm), b.xyz_bar(nm), "{name} at {nm}");
        }
    }
}

/// Quantity: every pixel of the Cornell box (low resolution, 2 spp, fixed seed) with the
/// observer (and the light SPD of an added spot light) from the library, against the same
/// render with the built-ins. Tolerance: none (bit-identical), as above.
#[test]
fn a_scene_renders_identically_with_the_library_types() {
    let mut desc = spectrace::scene::cornell_box_description().unwrap();
    desc.cameras[0].params = {
        let mut p = desc.cameras[0].params.clone();
        if let ron::Value::Map(m) = &mut p {
            m.insert(
                ron::Value::String("resolution".into()),
                ron::from_str("(32, 32)").unwrap(),
            );
        }
        p
    };
    desc.lights.push(
        ron::from_str(
            r#"(name: "spot", type: "spot", params: (position: (278, 500, 0), target: (278, 0, 300), power: 2000000, spd: (type: "spec", params: (spec: "blackbody:3500"))))"#,
        )
        .unwrap(),
    );
    let image = |r: Registry| {
        let f = factory(r);
        let factories: [&dyn ObjectFactory; 1] = [&f];
        let scene = spectrace::scene::build_scene(
            &desc,
            std::path::Path::new("."),
            std::path::Path::new("cornell"),
            &factories,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let settings = RenderSettings {
            budget: SampleBudget::Spp(2),
            seed: 5,
            threads: Some(2),
            ..RenderSettings::default()
        };
        render(&scene, &settings, &|_, _| {}, None).unwrap().image
    };
    let a = image(spectrace::plugin::builtin_registry());
    let b = image(library_registry());
    assert!(a.mean_xyz()[1] > 0.0);
    assert_eq!(a.xyz, b.xyz);
}
