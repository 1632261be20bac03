//! The README's plugin example is the real `plugins/example-laser` crate, which the workspace
//! builds and the tests below load: if the two drift apart, this fails.

use spectrace::plugin::Registry;
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::RandomSample;
use spectrace_tests::plugin_library;

fn workspace_file(rel: &str) -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    std::fs::read_to_string(root.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

#[test]
fn readme_shows_the_example_plugin_verbatim() {
    let readme = workspace_file("README.md");
    for file in [
        "plugins/example-laser/src/lib.rs",
        "plugins/example-laser/Cargo.toml",
    ] {
        let code = workspace_file(file);
        assert!(
            readme.contains(code.trim_end()),
            "README.md must contain {file} verbatim (copy it again after editing the example)"
        );
    }
}

#[test]
fn readme_commands_match_ci() {
    let readme = workspace_file("README.md");
    let ci = workspace_file(".ci/run");
    let command = ci.lines().last().unwrap().trim();
    assert!(
        readme.contains(command),
        "README must give the CI test command `{command}`"
    );
}

#[test]
fn the_example_laser_loads_and_emits_its_line() {
    let mut r = Registry::new();
    r.load_plugin(&plugin_library("spectrace-example-laser"))
        .unwrap();
    let laser = r
        .create_plugin_light(
            "laser",
            ObjectSource::Params(RStr::from_str(
                "(origin: (0, 1, 0), direction: (0, 0, -2), radius: 0.01, wavelength_nm: 532, power_w: 0.005)",
            )),
        )
        .unwrap();
    let mut s = RandomSample::default();
    s.u[0] = 0.99;
    s.u[1] = 0.3;
    let b = laser.light.next_beam(&s).unwrap();
    assert_eq!(b.colour[0], 532.0);
    assert_eq!(b.power_w, 0.005);
    assert_eq!(b.direction, [0.0, 0.0, -1.0]);
    // The start point lies in the aperture disk (radius 0.01 in the z = 0 plane around (0,1,0)).
    let off = b.origin - spectrace_plugin_api::Vec3::new(0.0, 1.0, 0.0);
    assert!(
        off.length() <= 0.01 + 1e-15 && off.z.abs() < 1e-15,
        "{off:?}"
    );
    // Beams only: it offers no connection capability, so the host must trace its beams.
    assert_eq!(laser.flags.0, 0);
}
