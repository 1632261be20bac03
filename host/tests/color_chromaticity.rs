//! Chromaticities of the CIE illuminants against the values the CIE publishes, and the CLI's
//! JSON output.

use spectrace::color::{chromaticity, emitter_xyz, CieObserverKind};
use spectrace::spectrum::parse_spd_spec;

fn xy(spec: &str) -> (f64, f64) {
    let spd = parse_spd_spec(spec).unwrap();
    chromaticity(emitter_xyz(&spd, CieObserverKind::Cie1931_2.get()))
}

// Illuminant A: x = 0.44757, y = 0.40745 (CIE 15:2018, CIE 1931 2°). Tolerance 1e-4: the
// published values have 5 decimals and the 5 nm table integrated on the 1 nm grid reproduces
// them to that rounding.
#[test]
fn illuminant_a_chromaticity() {
    let (x, y) = xy("a");
    assert!(
        (x - 0.44757).abs() < 1e-4 && (y - 0.40745).abs() < 1e-4,
        "A: {x} {y}"
    );
}

// D65: x = 0.31271, y = 0.32902 (CIE 15:2018, CIE 1931 2°); 1e-4 for the same reason.
#[test]
fn d65_chromaticity() {
    let (x, y) = xy("d65");
    assert!(
        (x - 0.31271).abs() < 1e-4 && (y - 0.32902).abs() < 1e-4,
        "D65: {x} {y}"
    );
}

// D65 for the CIE 1964 10° observer: x = 0.31382, y = 0.33100 (CIE 15:2018 Table 3.3); 1e-4
// as above. Checks that the observer choice really switches the tables.
#[test]
fn d65_chromaticity_10_degree() {
    let spd = parse_spd_spec("d65").unwrap();
    let (x, y) = chromaticity(emitter_xyz(&spd, CieObserverKind::Cie1964_10.get()));
    assert!(
        (x - 0.31382).abs() < 1e-4 && (y - 0.33100).abs() < 1e-4,
        "{x} {y}"
    );
}

// CIE 15 defines A by Planck's law at 2848 K with the old c₂ = 1.435e-2 m·K, the same curve
// as 2856 K with today's c₂ = 1.438777e-2 m·K (2848 · 1.438777/1.435 = 2855.5 K). So our
// blackbody:2856 must reproduce A's chromaticity; 1e-4 covers the 0.5 K difference (≈ 5e-6 in
// xy) and the linear interpolation of A's 5 nm table.
#[test]
fn blackbody_2856_matches_a() {
    let (xa, ya) = xy("a");
    let (xb, yb) = xy("blackbody:2856");
    assert!(
        (xa - xb).abs() < 1e-4 && (ya - yb).abs() < 1e-4,
        "{xb} {yb} vs {xa} {ya}"
    );
}

// A monochromatic line has the spectral-locus chromaticity of the CMFs at that wavelength:
// computed directly from the table row for 520 nm (exact arithmetic, 1e-12).
#[test]
fn line_lies_on_spectral_locus() {
    let (x, y) = xy("line:520");
    let c = spectrace::color::Observer::xyz_bar(CieObserverKind::Cie1931_2.get(), 520.0);
    let s = c[0] + c[1] + c[2];
    assert!((x - c[0] / s).abs() < 1e-12 && (y - c[1] / s).abs() < 1e-12);
}

// The CLI prints one JSON object with exactly the documented keys (for an emitter the light
// figures too, checked in color_light_figures.rs); D65's xy as above (1e-4),
// Y = 100 by normalization (1e-9) and linear sRGB ≈ (1,1,1) because D65 is sRGB's white: the
// CIE table's xy differs from sRGB's rounded (0.3127, 0.3290) by < 2e-5, worth < 1e-3 in RGB.
#[test]
fn cli_json_output() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .args(["color", "d65", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let obj = v.as_object().unwrap();
    let mut keys: Vec<&str> = obj.keys().map(|k| k.as_str()).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "X",
            "Y",
            "Z",
            "cct_k",
            "cri_r",
            "cri_ra",
            "duv",
            "srgb_linear",
            "tm30_rf",
            "tm30_rg",
            "x",
            "y"
        ]
    );
    assert!((v["Y"].as_f64().unwrap() - 100.0).abs() < 1e-9);
    assert!((v["x"].as_f64().unwrap() - 0.31271).abs() < 1e-4);
    for c in v["srgb_linear"].as_array().unwrap() {
        assert!((c.as_f64().unwrap() - 1.0).abs() < 1e-3, "{v}");
    }
}

// Bad input gives exit code 1 and a message naming the problem, not a panic.
#[test]
fn cli_bad_spec_is_an_error() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .args(["color", "no_such_lamp"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no_such_lamp"), "{err}");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .args(["color", "d65", "--observer", "cie1900-7"])
        .output()
        .unwrap();
    assert!(!out.status.success());
}
