//! The plugin host end to end, against real plugin libraries built by `cargo build --workspace`:
//! loading, the registry, constructors, panics, version and layout checks.

use spectrace::plugin::{LoadedPlugin, Registry, RegistryError};
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::{ErrorKind, ObjectKind, RandomSample, TypeInfo};
use spectrace_tests::plugin_library;
use std::path::Path;

const POINT_PARAMS: &str = "(position: (1.0, 2.0, -3.0), power_w: 60.0, spd: \"d65\")";

fn params(text: &str) -> ObjectSource<'_> {
    ObjectSource::Params(RStr::from_str(text))
}

/// A deterministic spread of random samples (a fixed LCG: the test must not depend on a crate's
/// generator changing).
fn samples(n: usize) -> Vec<RandomSample> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n)
        .map(|_| {
            let mut s = RandomSample::default();
            for u in &mut s.u {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                *u = (state >> 11) as f64 / (1u64 << 53) as f64;
            }
            s
        })
        .collect()
}

fn registry_with(path: &Path) -> Registry {
    let mut r = Registry::new();
    r.load_plugin(path)
        .unwrap_or_else(|e| panic!("{}", e.verbose()));
    r
}

#[test]
fn loaded_plugin_gives_the_same_beams_as_the_same_type_built_in() {
    let loaded = registry_with(&plugin_library("spectrace-point-light"));
    let mut builtin = Registry::new();
    builtin
        .add_plugin(
            LoadedPlugin::from_module(spectrace_point_light::root_module(), "in-process").unwrap(),
        )
        .unwrap();
    for (ty, text) in [
        ("isotropic_point", POINT_PARAMS),
        (
            "smooth_spot",
            "(position: (0, 5, 0), direction: (0, -1, 0.2), cone_angle_deg: 40, falloff_start_deg: 20, power_w: 15, spd: \"blackbody:3000\")",
        ),
    ] {
        let a = loaded.create_plugin_light(ty, params(text))
.unwrap()
.light;
        let b = builtin.create_plugin_light(ty, params(text))
.unwrap()
.light;
        let n = 2000;
        for s in samples(n) {
            let ba = a.next_beam(&s).unwrap();
            let bb = b.next_beam(&s).unwrap();
            // Bit-identical: the same code, the same inputs, across the ABI or not.
            assert_eq!(ba, bb, "{ty}: beams differ for {s:?}");
            assert!(ba.power_w.is_finite() && ba.power_w >= 0.0);
            let d = ba.direction;
            let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            assert!((length - 1.0).abs() < 1e-12, "direction not unit");
            assert!((300.0..=830.0).contains(&ba.colour[0]));
        }
        // The seed's numberOfBeams counts what next_beam handed out.
        assert_eq!(a.number_of_beams(), n as f64);
        assert_eq!(b.number_of_beams(), n as f64);
    }
}

#[test]
fn point_light_beams_average_to_its_flux() {
    // Mean beam power estimates the flux (Beam docs). Point light: every beam carries exactly Φ.
    // Spot light: power varies with angle; 20 000 beams give a relative standard error below
    // 0.5%, so 2% is a > 4σ bound.
    let r = registry_with(&plugin_library("spectrace-point-light"));
    let point = r
        .create_plugin_light("isotropic_point", params(POINT_PARAMS))
        .unwrap()
        .light;
    for s in samples(100) {
        assert_eq!(point.next_beam(&s).unwrap().power_w, 60.0);
    }
    let spot = r
        .create_plugin_light(
            "smooth_spot",
            params("(position: (0,0,0), direction: (0,0,-1), cone_angle_deg: 50, falloff_start_deg: 10, power_w: 15)"),
        )
.unwrap()
.light;
    let n = 20_000;
    let mean: f64 = samples(n)
        .iter()
        .map(|s| spot.next_beam(s).unwrap().power_w)
        .sum::<f64>()
        / n as f64;
    assert!(
        (mean / 15.0 - 1.0).abs() < 0.02,
        "mean beam power {mean} W vs 15 W"
    );
}

#[test]
fn plugins_list_their_types_with_parameters() {
    let r = registry_with(&plugin_library("spectrace-point-light"));
    let p = &r.plugins()[0];
    assert_eq!(p.info.name.as_str(), "point-light");
    assert_eq!(
        p.info.api_version.as_str(),
        spectrace_plugin_api::API_VERSION
    );
    let names: Vec<&str> = p.info.types.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["isotropic_point", "smooth_spot"]);
    let point = &p.info.types[0];
    assert!(point
        .params
        .iter()
        .any(|q| q.name.as_str() == "power_w" && q.unit.as_str() == "W"));
}

#[test]
fn a_file_that_is_not_a_library_is_refused() {
    let dir = std::env::temp_dir().join(format!("spectrace-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fake = dir.join("libfake.so");
    std::fs::write(&fake, b"this is text, not ELF").unwrap();
    let e = Registry::new().load_plugin(&fake).unwrap_err().to_string();
    assert!(
        e.contains("libfake.so") && e.contains("not a loadable shared library"),
        "{e}"
    );
    let missing = dir.join("libmissing.so");
    let e = Registry::new()
        .load_plugin(&missing)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("libmissing.so") && e.contains("no such file"),
        "{e}"
    );
}

#[test]
fn a_library_without_root_module_is_refused() {
    let path = plugin_library("spectrace-fixture-not-a-plugin");
    let e = Registry::new().load_plugin(&path).unwrap_err().to_string();
    assert!(
        e.contains("not a spectrace plugin") && e.contains("root module"),
        "{e}"
    );
}

#[test]
fn a_plugin_built_against_another_api_version_is_refused() {
    let path = plugin_library("spectrace-fixture-old-api");
    let e = Registry::new().load_plugin(&path).unwrap_err().to_string();
    assert!(
        e.contains("spectrace_fixture_old_api"),
        "names the file: {e}"
    );
    assert!(
        e.contains("built against spectrace-plugin-api 0.1.0")
            && e.contains("this host speaks 0.2.0")
            && e.contains("rebuild the plugin against 0.2.0")
            && e.contains("too old"),
        "{e}"
    );
    assert!(e.lines().count() <= 2, "one or two lines: {e}");
}

#[test]
fn a_plugin_with_a_different_layout_is_refused_briefly() {
    let path = plugin_library("spectrace-fixture-bad-layout");
    let err = Registry::new().load_plugin(&path).unwrap_err();
    let short = err.to_string();
    assert!(short.contains("ABI layout mismatch"), "{short}");
    assert!(short.lines().count() <= 2, "one or two lines: {short}");
    // The full report is kept for --verbose.
    assert!(err.verbose().len() > short.len());
}

#[test]
fn duplicate_types_and_plugins_are_refused_naming_both() {
    let path = plugin_library("spectrace-point-light");
    let mut r = Registry::new();
    r.register_builtin(TypeInfo {
        kind: ObjectKind::Light,
        name: "isotropic_point".into(),
        version: 1,
        description: "built-in point".into(),
        params: Default::default(),
        beams: Default::default(),
    })
    .unwrap();
    let e = r.load_plugin(&path).unwrap_err().to_string();
    assert!(
        e.contains("duplicate light type `isotropic_point`") && e.contains("built-in"),
        "{e}"
    );
    assert!(
        r.plugins().is_empty(),
        "nothing of a refused plugin is registered"
    );

    let mut r = registry_with(&path);
    let e = r.load_plugin(&path).unwrap_err().to_string();
    assert!(e.contains("duplicate plugin name `point-light`"), "{e}");
}

#[test]
fn unknown_types_list_what_exists() {
    let r = registry_with(&plugin_library("spectrace-point-light"));
    let e = r.create_plugin_light("laser", params("()")).err().unwrap();
    assert!(matches!(e, RegistryError::UnknownType { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("unknown light type `laser`") && msg.contains("isotropic_point, smooth_spot"),
        "{msg}"
    );
}

#[test]
fn constructor_errors_name_the_parameter() {
    let r = registry_with(&plugin_library("spectrace-point-light"));
    let cases = [
        ("(position: (0,0,0), power_w: -5.0)", "power_w"),
        ("(power_w: 5.0)", "position"),
        ("(position: (0,0,0), power_w: 5.0, colour: 3)", "colour"),
        (
            "(position: (0,0,0), power_w: 5.0, spd: \"no-such-spectrum\")",
            "no-such-spectrum",
        ),
        ("(position: (0,0,0), power_w: ", "parameters"),
    ];
    for (text, needle) in cases {
        let msg = r
            .create_plugin_light("isotropic_point", params(text))
            .err()
            .unwrap()
            .to_string();
        assert!(msg.contains(needle), "`{text}` → {msg}");
        assert!(msg.contains("point-light"), "names the plugin: {msg}");
    }
}

#[test]
fn a_panicking_plugin_is_reported_and_the_host_goes_on() {
    let r = registry_with(&plugin_library("spectrace-fixture-panicking-light"));
    let light = r
        .create_plugin_light("panicking", params("()"))
        .unwrap()
        .light;
    let mut s = RandomSample::default();
    s.u[0] = 0.9;
    let e = light.next_beam(&s).into_result().unwrap_err();
    assert_eq!(e.kind, ErrorKind::Panic);
    assert!(
        e.message.as_str().contains("deliberate panic in next_beam"),
        "{e}"
    );
    // Still usable after the panic.
    s.u[0] = 0.1;
    assert_eq!(light.next_beam(&s).unwrap().colour[0], 550.0);
    assert_eq!(
        light.number_of_beams(),
        1.0,
        "the panicked call emitted no beam"
    );

    let e = r
        .create_plugin_light("panicking", params("(panic_in_constructor: true)"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("plugin panicked") && e.contains("told to panic"),
        "{e}"
    );
}

#[test]
fn a_plugin_directory_loads_the_good_and_reports_the_bad() {
    let dir = std::env::temp_dir().join(format!("spectrace-plugdir-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["spectrace-point-light", "spectrace-fixture-old-api"] {
        let src = plugin_library(name);
        std::fs::copy(&src, dir.join(src.file_name().unwrap())).unwrap();
    }
    let mut r = Registry::new();
    let errors = r.load_plugin_dir(&dir);
    assert_eq!(r.plugins().len(), 1);
    assert_eq!(errors.len(), 1);
    assert!(errors[0].to_string().contains("old_api"));
}

#[test]
fn plugin_types_join_the_built_ins_in_one_registry() {
    let mut r = spectrace::plugin::builtin_registry();
    // The built-in scene types are registered like plugin types …
    assert!(r.contains(ObjectKind::Light, "point"));
    assert!(r.contains(ObjectKind::Material, "lambertian"));
    assert!(r.plugin_for(ObjectKind::Light, "point").unwrap().is_none());
    // … so a plugin with distinct names loads beside them, and one reusing a name is refused.
    r.load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    assert!(r
        .plugin_for(ObjectKind::Light, "isotropic_point")
        .unwrap()
        .is_some());
}
