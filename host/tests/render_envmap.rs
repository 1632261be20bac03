//! Environment maps (`envmap`) in whole renders: a white furnace, agreement with the constant
//! `environment` type, the photometric `illuminance`, in PT, BDPT and LT. The maps are written
//! as OpenEXR into a temporary directory by the tests.

mod common_render;
use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::{parse_spd_spec, Spd};
use std::path::{Path, PathBuf};

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-envmap-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Write a `w × h` RGB EXR whose pixel (x, y) (y from the top) is `f(x, y)`.
fn write_exr(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3] + Sync) {
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        let c = f(x, y);
        (c[0], c[1], c[2])
    })
    .unwrap();
}

fn scene(dir: &Path, text: &str) -> Scene {
    let file = dir.join("scene.ron");
    let desc = parse_scene_str(text, &file).unwrap();
    build_scene(&desc, dir, &file, &[&BuiltinFactory]).unwrap()
}

fn render(scene: &Scene, kind: IntegratorKind, spp: u32) -> Vec<f64> {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 11,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 50,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = common_render::render(scene, &settings, kind).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image.xyz.iter().map(|p| p[1]).collect()
}

/// Mean and its standard error over pixels that should all have the same value.
fn mean_and_error(y: &[f64]) -> (f64, f64) {
    let n = y.len() as f64;
    let m = y.iter().sum::<f64>() / n;
    let var = y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// `∫ ȳ` on the CIE 1931 2° 1 nm grid (the film's normaliser).
fn int_ybar() -> f64 {
    let obs = CieObserverKind::Cie1931_2.get();
    (360..=830).map(|l| obs.xyz_bar(l as f64)[1]).sum()
}

const FURNACE: &str = r#"(
    materials: [(name: "white", type: "lambertian", params: (reflectance: 1.0))],
    objects: [(name: "ball", type: "sphere", material: "white", params: (center: (0, 0, 0), radius: 1))],
    lights: [LIGHT],
    cameras: [(name: "c", type: "pinhole",
               params: (position: (0, 0.3, 2.5), look_at: (0, 0, 0), fov: 30, resolution: (16, 16)))],
)"#;

/// White furnace: a white (ρ = 1) diffuse sphere under a constant map of value 0.5 (scale 3)
/// looks exactly like the sky around it, so every pixel has Y = 1.5 (the sRGB white has
/// luminance 1; the table's grey is exact to 2e-3). In PT, BDPT and LT the image mean is within
/// 4 standard errors (from the pixels' spread) + 0.3% (the grey's table error and the map's
/// bilinear reconstruction) of 1.5.
#[test]
fn white_sphere_in_a_constant_envmap_is_invisible() {
    let dir = temp_dir("furnace");
    write_exr(&dir.join("grey.exr"), 32, 16, |_, _| [0.5; 3]);
    let s = scene(
        &dir,
        &FURNACE.replace(
            "LIGHT",
            r#"(name: "sky", type: "envmap", params: (file: "grey.exr", scale: 3))"#,
        ),
    );
    for (kind, spp) in [
        (IntegratorKind::Pt, 64),
        (IntegratorKind::Bdpt, 32),
        (IntegratorKind::Lt, 512),
    ] {
        let (m, e) = mean_and_error(&render(&s, kind, spp));
        eprintln!("furnace {kind}: Y = {m:.5} ± {e:.5} (want 1.5)");
        assert!(
            (m - 1.5).abs() < 4.0 * e + 0.003 * 1.5,
            "{kind}: Y = {m} ± {e}, want 1.5"
        );
    }
}

/// The same radiance from `envmap` (a constant 0.5 map) and from the constant `environment`
/// (D65 with the same integrated radiance: 0.5 × ∫W, W the sRGB white of luminance 1) give the
/// same image of a coloured diffuse sphere: mean Y within 4 combined standard errors + 0.3%
/// (the grey's table error).
#[test]
fn constant_envmap_matches_the_environment_type() {
    let dir = temp_dir("same");
    write_exr(&dir.join("grey.exr"), 32, 16, |_, _| [0.5; 3]);
    // ∫W dλ with W = D65 / (Σ D65 ȳ / Σ ȳ): computed here from the tables, not the renderer.
    let d65 = parse_spd_spec("d65").unwrap();
    let obs = CieObserverKind::Cie1931_2.get();
    let num: f64 = (360..=830)
        .map(|l| d65.value(l as f64) * obs.xyz_bar(l as f64)[1])
        .sum();
    let k = int_ybar() / num;
    let integrated = 0.5 * k; // d65 is normalised: ∫ d65 dλ = 1
    let body = FURNACE.replace("reflectance: 1.0", "reflectance: (rgb: (0.8, 0.3, 0.2))");
    let a = scene(
        &dir,
        &body.replace(
            "LIGHT",
            r#"(name: "sky", type: "envmap", params: (file: "grey.exr"))"#,
        ),
    );
    let b = scene(
        &dir,
        &body.replace(
            "LIGHT",
            &format!(r#"(name: "sky", type: "environment", params: (radiance: "d65", scale: {integrated}))"#),
        ),
    );
    for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt] {
        let (ma, ea) = mean_and_error(&render(&a, kind, 64));
        let (mb, eb) = mean_and_error(&render(&b, kind, 64));
        eprintln!("{kind}: envmap Y = {ma:.5} ± {ea:.5}, environment Y = {mb:.5} ± {eb:.5}");
        let tol = 4.0 * (ea * ea + eb * eb).sqrt() + 0.003 * mb;
        assert!(
            (ma - mb).abs() < tol,
            "{kind}: {ma} vs {mb} (tolerance {tol})"
        );
    }
}

/// `illuminance`: a white diffuse floor under a sky map (bright band low on one side, a
/// gradient, black below the horizon) scaled to E = 5000 lx has luminance E/π cd/m², i.e. film
/// Y = E / (π · 683.002 · ∫ȳ). The map is far from uniform, so this also checks the importance
/// sampling's weights. Within 4 standard errors + 1% (the illuminance is a quadrature over the
/// map's nodes; 64 × 32 nodes, whose error on this map is well under 1%).
#[test]
fn illuminance_sets_the_floor_luminance() {
    let dir = temp_dir("lux");
    let (w, h) = (64, 32);
    write_exr(&dir.join("sky.exr"), w, h, |x, y| {
        if y >= h / 2 {
            return [0.0; 3];
        }
        let u = x as f32 / w as f32;
        let band = if (8..14).contains(&y) && u < 0.2 {
            40.0
        } else {
            0.0
        };
        [0.3 + band, 0.5 + 0.5 * u + band, 1.0 + band * 0.8]
    });
    let text = r#"(
        materials: [(name: "white", type: "lambertian", params: (reflectance: 1.0))],
        objects: [(name: "floor", type: "quad", material: "white",
                   params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2)))],
        lights: [(name: "sky", type: "envmap", params: (file: "sky.exr", illuminance: 5000,
                  transform: ((0.6, 0, 0.8, 0), (0, 1, 0, 0), (-0.8, 0, 0.6, 0), (0, 0, 0, 1))))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 3, 0.01), look_at: (0, 0, 0), fov: 20, resolution: (16, 16)))],
    )"#;
    let s = scene(&dir, text);
    let want = 5000.0 / (std::f64::consts::PI * 683.002 * int_ybar());
    for (kind, spp) in [(IntegratorKind::Pt, 128), (IntegratorKind::Bdpt, 64)] {
        let (m, e) = mean_and_error(&render(&s, kind, spp));
        eprintln!("illuminance {kind}: Y = {m:.5} ± {e:.5} (want {want:.5})");
        assert!(
            (m - want).abs() < 4.0 * e + 0.01 * want,
            "{kind}: {m} ± {e} vs {want}"
        );
    }
}

/// Bad input gets a clear error naming the file: a missing image, a broken one, a shear in
/// `transform`, both `scale` and `illuminance`.
#[test]
fn bad_envmaps_are_errors() {
    let dir = temp_dir("bad");
    std::fs::write(dir.join("broken.exr"), b"v/1\x01garbage").unwrap();
    write_exr(&dir.join("ok.exr"), 8, 4, |_, _| [1.0; 3]);
    for (params, want) in [
        (r#"(file: "missing.exr")"#, "missing.exr"),
        (r#"(file: "broken.exr")"#, "broken.exr"),
        (
            r#"(file: "ok.exr", transform: ((1, 0.5, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)))"#,
            "rotation",
        ),
        (
            r#"(file: "ok.exr", scale: 2, illuminance: 100)"#,
            "at most one",
        ),
    ] {
        let text = FURNACE.replace(
            "LIGHT",
            &format!(r#"(name: "sky", type: "envmap", params: {params})"#),
        );
        let file = dir.join("scene.ron");
        let desc = parse_scene_str(&text, &file).unwrap();
        let Err(err) = build_scene(&desc, &dir, &file, &[&BuiltinFactory]) else {
            panic!("{params}: expected an error")
        };
        let msg = err.to_string();
        assert!(msg.contains(want), "{params}: {msg}");
    }
}
