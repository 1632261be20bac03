//! `spectrace plugins check` — the conformance kit run by the host on libraries it loaded
//! through its normal loader — on every shipped plugin library and on every deliberately
//! broken fixture (plugins/fixtures/broken-*). A shipped type passes every check; each broken
//! type fails exactly the one check named for its defect, and the exit status says so.
//!
//! The libraries are the workspace's release builds (`cargo build --release --workspace`).

use serde_json::Value;
use spectrace_tests::{artifact_dir, plugin_library};
use std::process::Command;

/// Run `spectrace plugins check` with `args`; the exit status and the parsed JSON reports.
fn check(library: &str, args: &[&str]) -> (bool, Vec<Value>) {
    let lib = plugin_library(library);
    let out = Command::new(artifact_dir().join("spectrace"))
        .args(["plugins", "check"])
        .arg(&lib)
        .args(args)
        .arg("--json")
        .output()
        .expect("run spectrace");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let reports: Vec<Value> = serde_json::from_str(&stdout).unwrap_or_else(|e| {
        panic!(
            "{library} {args:?}: no JSON ({e}):\n{stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.success(), reports)
}

/// Names of the checks of `report` that failed.
fn failures(report: &Value) -> Vec<String> {
    report["checks"]
        .as_array()
        .expect("checks")
        .iter()
        .filter(|c| c["status"] == "fail")
        .map(|c| c["check"].as_str().unwrap_or("?").to_string())
        .collect()
}

/// Every shipped type, with parameters (types with required parameters cannot be built from
/// `()`), by library: (type, parameters).
const SHIPPED: &[(&str, &[(&str, &str)])] = &[
    (
        "spectrace-point-light",
        &[
            ("isotropic_point", "(position: (0, 0, 0), power_w: 10)"),
            (
                "smooth_spot",
                "(position: (0, 0, 0), direction: (0, -1, 0), power_w: 10)",
            ),
        ],
    ),
    (
        "spectrace-example-laser",
        &[(
            "laser",
            "(origin: (0, 0, 0), direction: (0, 0, -1), wavelength_nm: 532, power_w: 1)",
        )],
    ),
    (
        "spectrace-sensor-spectra",
        &[
            ("lorentzian", "(centre_nm: 589, fwhm_nm: 10)"),
            ("gaussian_sensor", "()"),
        ],
    ),
    (
        "spectrace-rough-diffuse",
        &[("oren_nayar", "(roughness: 0.8)")],
    ),
    (
        "spectrace-standard",
        &[
            ("lambertian", "()"),
            ("mirror", "()"),
            ("dielectric", "()"),
            ("rough_dielectric", "()"),
            ("conductor", "()"),
            ("plastic", "(diffuse_reflectance: 1)"),
            ("rough_plastic", "(diffuse_reflectance: 1, alpha: 0.2)"),
            ("emissive", "(radiance: \"d65\", scale: 10)"),
            ("fluorescent", "(bfc: \"CIBA12\")"),
            ("spec", "(spec: \"d65\")"),
            ("spec", "(spec: \"fl11\")"),
            ("spec", "(spec: \"line:589\")"),
            (
                "table",
                "(values: ((400, 1), (500, 2), (600, 1.5), (700, 0.5)))",
            ),
            ("cie1931-2", "()"),
            ("cie1964-10", "()"),
            ("cie2015-2", "()"),
            ("cie2015-10", "()"),
            ("point", "(position: (0, 0.5, 0), power: 20)"),
            (
                "spot",
                "(position: (0, 0.5, 0), target: (0, -1, 0), power: 20)",
            ),
            ("directional", "(direction: (0, -1, 0), irradiance: 2)"),
            ("environment", "(radiance: \"d65\", scale: 0.5)"),
        ],
    ),
    (
        "spectrace-api-only",
        &[
            ("api_conductor", "(metal: \"aluminium\", roughness: 0.25)"),
            ("api_conductor", "(metal: \"gold\", roughness: 0.5)"),
            (
                "api_spot",
                "(position: (0, 0.5, 0), target: (0, -1, 0), inner_angle: 12, outer_angle: 22, \
                 power: 60, spd: \"blackbody:2856\")",
            ),
        ],
    ),
];

#[test]
fn every_shipped_plugin_type_passes_plugins_check() {
    let mut problems = Vec::new();
    for (lib, types) in SHIPPED {
        for (ty, params) in *types {
            let (ok, reports) = check(lib, &["--type", ty, "--params", params]);
            assert_eq!(reports.len(), 1, "{lib} {ty}");
            let failed = failures(&reports[0]);
            if !failed.is_empty() {
                problems.push(format!(
                    "{lib} `{ty}` {params}: failed {failed:?}\n{:#}",
                    reports[0]
                ));
            }
            assert_eq!(ok, failed.is_empty(), "{lib} {ty}: exit status");
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Each broken fixture library with its types: (type, the one check that must fail).
const BROKEN: &[(&str, &[(&str, &str)])] = &[
    (
        "spectrace-fixture-broken-materials",
        &[
            ("negative_eval", "finite"),
            ("uniform_sampler", "chi2"),
            ("record_pdf_doubled", "sample_pdf"),
            ("pdf_too_large", "pdf_integral"),
            ("creates_energy", "energy"),
            ("not_reciprocal", "reciprocity"),
            ("own_random_numbers", "determinism"),
            ("per_thread_cache", "threads"),
            ("state_forgets", "state"),
        ],
    ),
    (
        "spectrace-fixture-broken-lights",
        &[
            ("double_emission", "power"),
            ("heavy_beams", "beams_power"),
            ("inverse_distance", "toward"),
            ("cosine_emitter", "emission"),
            ("flat_beams", "beams"),
            ("state_forgets", "state"),
        ],
    ),
    (
        "spectrace-fixture-broken-spds",
        &[
            ("not_normalised", "integral"),
            ("uniform_sampler", "chi2"),
            ("hidden_line", "lines"),
            ("state_forgets", "state"),
        ],
    ),
    (
        "spectrace-fixture-broken-observers",
        &[
            ("negative_lobe", "finite"),
            ("range_too_short", "range"),
            ("state_forgets", "state"),
        ],
    ),
];

#[test]
fn each_broken_fixture_is_caught_by_its_check_alone() {
    for (lib, expected) in BROKEN {
        // Every type of the library at once, from its defaults: one report each.
        let (ok, reports) = check(lib, &[]);
        assert!(!ok, "{lib}: the exit status must say that checks failed");
        assert_eq!(reports.len(), expected.len(), "{lib}: one report per type");
        for (ty, check_name) in *expected {
            let r = reports
                .iter()
                .find(|r| r["type_name"] == *ty)
                .unwrap_or_else(|| panic!("{lib}: no report of `{ty}`"));
            assert_eq!(
                failures(r),
                vec![check_name.to_string()],
                "{lib} `{ty}` must fail `{check_name}` alone:\n{r:#}"
            );
        }
    }
}
