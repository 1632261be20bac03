//! Parameters are checked when a scene is built: each bad value is refused with an error that
//! names the item and the parameter (issue 13, item 2), and scenes that build but would
//! render (partly) black carry a warning. Every test builds a tiny scene (no rendering), so the
//! whole file runs in well under a second; all checks are exact (no Monte Carlo).
//! Run: `cargo test --release -p spectrace --test robust_params`

use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A one-quad scene: `materials` replaces the floor material's `type` and `params`, `lights`
/// is the `lights` list, `camera` the camera's params.
fn scene(material: &str, lights: &str, camera: &str) -> Result<Scene, String> {
    let text = format!(
        r#"(
    materials: [
        (name: "floor", {material}),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2))),
    ],
    lights: [{lights}],
    cameras: [(name: "front", type: "perspective", params: ({camera}))],
)"#
    );
    let file = Path::new("test.ron");
    let desc = parse_scene_str(&text, file).map_err(|e| e.to_string())?;
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).map_err(|e| e.to_string())
}

const CAMERA: &str = "position: (0, 1, 3), look_at: (0, 0, 0), fov: 40, resolution: (8, 8)";
const LAMP: &str = r#"(name: "lamp", type: "point", params: (position: (0, 1, 0), power: 10))"#;
const GREY: &str = r#"type: "lambertian", params: (reflectance: 0.5)"#;

fn material(m: &str) -> Result<Scene, String> {
    scene(m, LAMP, CAMERA)
}

fn light(l: &str) -> Result<Scene, String> {
    scene(GREY, l, CAMERA)
}

/// `result` is an error containing every one of `parts`.
#[track_caller]
fn refused(result: Result<Scene, String>, parts: &[&str]) {
    let e = match result {
        Ok(_) => panic!("accepted, expected an error with {parts:?}"),
        Err(e) => e,
    };
    for p in parts {
        assert!(e.contains(p), "error {e:?} lacks {p:?}");
    }
}

#[test]
fn valid_scene_builds_without_warnings() {
    let s = material(GREY).unwrap();
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
}

#[test]
fn lambertian_constant_reflectance_outside_unit_interval_is_refused() {
    // Each of these built before the check (issue 13); a reflectance is in [0, 1].
    for (v, shown) in [
        ("2", "2"),
        ("-0.5", "-0.5"),
        ("NaN", "NaN"),
        ("1e300", "1e300"),
    ] {
        refused(
            material(&format!(
                r#"type: "lambertian", params: (reflectance: {v})"#
            )),
            &[
                "material \"floor\"",
                "parameter `reflectance`",
                &format!("value {shown} at every wavelength is outside [0, 1]"),
            ],
        );
    }
    // The ends of the interval are fine.
    material(r#"type: "lambertian", params: (reflectance: 1)"#).unwrap();
    material(r#"type: "lambertian", params: (reflectance: 0)"#).unwrap();
}

#[test]
fn every_tabulated_reflectance_entry_is_checked() {
    refused(
        material(
            r#"type: "lambertian", params: (reflectance: [(400, 0.5), (550, 2), (700, 0.5)])"#,
        ),
        &[
            "material \"floor\"",
            "parameter `reflectance`",
            "value 2 at 550 nm is outside [0, 1]",
        ],
    );
    // An entry outside the visible range counts too.
    refused(
        material(r#"type: "mirror", params: (reflectance: [(300, -0.1), (400, 0.5), (800, 0.5)])"#),
        &["parameter `reflectance`", "value -0.1 at 300 nm"],
    );
    // A bundled measured reflectance (ColorChecker patch) is within [0, 1] everywhere.
    material(r#"type: "lambertian", params: (reflectance: "colorchecker:1")"#).unwrap();
}

#[test]
fn rgb_uplift_reflectance_is_checked() {
    refused(
        material(r#"type: "lambertian", params: (reflectance: (rgb: (1.5, 0.2, 0.2)))"#),
        &["parameter `reflectance`", "[0, 1]"],
    );
    // The uplift of any in-range colour stays within [0, 1] at every nm (checked 360–830).
    material(r#"type: "lambertian", params: (reflectance: (rgb: (1, 1, 1)))"#).unwrap();
    material(r#"type: "lambertian", params: (reflectance: (rgb: (0.9, 0.05, 0.0)))"#).unwrap();
}

#[test]
fn light_power_not_representable_is_refused_with_the_limit() {
    // 1e300 W used to become +inf in the light's f32 and the light vanished.
    for p in ["1e300", "3.5e38", "inf", "NaN", "-1"] {
        refused(
            light(&format!(
                r#"(name: "lamp", type: "point", params: (position: (0, 1, 0), power: {p}))"#
            )),
            &["light \"lamp\"", "parameter `power`"],
        );
    }
    refused(
        light(r#"(name: "lamp", type: "point", params: (position: (0, 1, 0), power: 1e300))"#),
        &["3.4028234663852886e38 W", "32-bit float limit"],
    );
    refused(
        light(
            r#"(name: "sun", type: "directional", params: (direction: (0, -1, 0), irradiance: 1e39))"#,
        ),
        &["light \"sun\"", "parameter `irradiance`", "W/m²"],
    );
}

#[test]
fn emissive_scale_not_representable_is_refused() {
    for s in ["1e300", "NaN", "-2"] {
        refused(
            material(&format!(
                r#"type: "emissive", params: (radiance: "d65", scale: {s})"#
            )),
            &["material \"floor\"", "parameter `scale`"],
        );
    }
    // A table times its scale beyond f32 is refused as well (the product is what is stored).
    refused(
        material(
            r#"type: "emissive", params: (radiance: [(400, 1e30), (700, 1e30)], scale: 1e20)"#,
        ),
        &["parameter `scale`", "32-bit float limit"],
    );
    refused(
        scene(
            GREY,
            r#"(name: "sky", type: "environment", params: (radiance: "d65", scale: 1e300))"#,
            CAMERA,
        ),
        &["light \"sky\"", "parameter `scale`"],
    );
}

#[test]
fn spot_angles_out_of_range_are_refused() {
    let spot = |inner: &str, outer: &str| {
        light(&format!(
            r#"(name: "spot", type: "spot", params: (position: (0, 2, 0), target: (0, 0, 0),
               inner_angle: {inner}, outer_angle: {outer}, power: 10))"#
        ))
    };
    refused(
        spot("10", "200"),
        &["light \"spot\"", "parameter `outer_angle`", "(0, 180)"],
    );
    refused(spot("10", "0"), &["parameter `outer_angle`"]);
    refused(
        spot("40", "30"),
        &["parameter `inner_angle`", "outer_angle = 30"],
    );
    refused(spot("-1", "30"), &["parameter `inner_angle`"]);
    refused(
        light(
            r#"(name: "spot", type: "spot", params: (position: (0, 2, 0), target: (0, 2, 0), power: 10))"#,
        ),
        &["parameter `target`", "must differ"],
    );
    spot("0", "179").unwrap();
}

#[test]
fn ior_must_be_finite_and_positive_over_the_range() {
    for ior in ["-1", "0", "NaN", "1e300"] {
        refused(
            material(&format!(r#"type: "dielectric", params: (ior: {ior})"#)),
            &["material \"floor\"", "parameter `ior`"],
        );
    }
    // Cauchy a + b/λ² negative at the blue end (a = -1, b = 0.01 µm²: n(360 nm) ≈ -0.92).
    refused(
        material(r#"type: "dielectric", params: (ior: (cauchy: (-1, 0.01)))"#),
        &["parameter `ior`", "at 360 nm"],
    );
    // A Sellmeier pole inside the range (C₁ = 0.55² µm²: λ = 550 nm).
    refused(
        material(
            r#"type: "rough_dielectric", params: (ior: (sellmeier: (b: (1, 0, 0), c: (0.3025, 0, 0))))"#,
        ),
        &["parameter `ior`", "must be finite and > 0"],
    );
    material(r#"type: "dielectric", params: (ior: "N-BK7")"#).unwrap();
}

#[test]
fn roughness_must_be_finite_and_non_negative() {
    for r in [
        "(roughness: NaN)",
        "(alpha: -0.1)",
        "(roughness: 1e20)",
        "(alpha: inf)",
    ] {
        refused(
            material(&format!(r#"type: "conductor", params: {r}"#)),
            &["material \"floor\""],
        );
    }
    refused(
        material(r#"type: "conductor", params: (roughness: 1e20)"#),
        &["parameter `roughness`", "finite GGX α"],
    );
    refused(
        material(
            r#"type: "conductor", params: (n: [(400, -1), (700, 1)], k: [(400, 1), (700, 1)])"#,
        ),
        &["parameter `n`", "at 400 nm"],
    );
}

#[test]
fn positions_and_directions_must_be_finite_and_directions_non_zero() {
    refused(
        light(r#"(name: "lamp", type: "point", params: (position: (1e300, 0, 0), power: 10))"#),
        &["light \"lamp\"", "parameter `position`"],
    );
    refused(
        light(
            r#"(name: "sun", type: "directional", params: (direction: (0, 0, 0), irradiance: 1))"#,
        ),
        &["light \"sun\"", "parameter `direction`", "non-zero"],
    );
    refused(
        light(
            r#"(name: "sun", type: "directional", params: (direction: (0, NaN, 0), irradiance: 1))"#,
        ),
        &["parameter `direction`"],
    );
    refused(
        scene(
            GREY,
            LAMP,
            "position: (0, 1, 1e39), look_at: (0, 0, 0), resolution: (8, 8)",
        ),
        &["camera \"front\"", "parameter `position`"],
    );
}

#[test]
fn no_light_scene_warns_that_it_renders_black() {
    let s = scene(GREY, "", CAMERA).unwrap();
    assert_eq!(
        s.warnings(),
        ["the scene has no light (no emissive object, no `lights` entry): it renders black"]
    );
}

#[test]
fn zero_power_light_warns() {
    let s =
        light(r#"(name: "lamp", type: "point", params: (position: (0, 1, 0), power: 0))"#).unwrap();
    assert!(
        s.warnings().iter().any(|w| {
            w
            == "light \"lamp\" emits nothing (total power 0 W): it contributes nothing to the image"
        }),
        "{:?}",
        s.warnings()
    );
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.contains("no light in the scene emits anything")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn power_near_the_f32_limit_warns() {
    // 3e38 W fits in f32 but leaves no headroom: a warning, not a silent black light.
    let s = light(r#"(name: "lamp", type: "point", params: (position: (0, 1, 0), power: 3e38))"#)
        .unwrap();
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.contains("light \"lamp\" has a total power of 3.000e38 W")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn all_black_materials_warn() {
    let s = material(r#"type: "lambertian", params: (reflectance: 0)"#).unwrap();
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.starts_with("every material is black")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn camera_that_sees_nothing_warns() {
    let s = scene(
        GREY,
        LAMP,
        "position: (0, 1, 3), look_at: (0, 1, 10), fov: 40, resolution: (8, 8)",
    )
    .unwrap();
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.starts_with("camera \"front\" sees no object")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn non_finite_translation_is_refused() {
    let text = format!(
        r#"(
    materials: [(name: "floor", {GREY})],
    objects: [(name: "floor", type: "quad", material: "floor",
               params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2)),
               transform: [Translate((0, NaN, 0))])],
    lights: [{LAMP}],
    cameras: [(name: "front", type: "perspective", params: ({CAMERA}))],
)"#
    );
    let file = Path::new("test.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    let e = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory])
        .expect_err("a NaN translation must be refused")
        .to_string();
    assert!(
        e.contains("object \"floor\"") && e.contains("translation"),
        "{e}"
    );
}
