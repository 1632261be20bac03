//! Image textures in whole renders: a textured floor seen from above under a white sky has,
//! pixel by pixel, the texture's linear colour (the uplifted reflectance under the sRGB white);
//! a spectral EXR texture; bad texture files.

use spectrace::color::SRGB;
use spectrace::film::spectral::SpectralImage;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::{Path, PathBuf};

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-texture-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene(dir: &Path, text: &str) -> Result<Scene, String> {
    let file = dir.join("scene.ron");
    let desc = parse_scene_str(text, &file).map_err(|e| e.to_string())?;
    build_scene(&desc, dir, &file, &[&BuiltinFactory]).map_err(|e| e.to_string())
}

/// A floor quad (uv (0,0) at x = −1, z = +1; u along +x, v along −z) filling the view of a
/// camera looking straight down (image right = +x, image up = −z), under a constant white map
/// of luminance 1: a diffuse floor of reflectance ρ(λ) then has radiance ρ(λ)·W(λ) and its
/// pixels the linear sRGB colour of ρ, i.e. the texel's colour.
fn floor_scene(reflectance: &str) -> String {
    format!(
        r#"(
        materials: [(name: "tex", type: "lambertian", params: (reflectance: {reflectance}))],
        objects: [(name: "floor", type: "quad", material: "tex",
                   params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2)))],
        lights: [(name: "sky", type: "envmap", params: (file: "white.exr"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 3, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 30,
                            resolution: (16, 16)))],
    )"#
    )
}

fn render_rgb(s: &Scene, spp: u32) -> Vec<[f64; 3]> {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 3,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 8,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = render_with(s, &settings, IntegratorKind::Pt, false, &|_, _| {}, None).unwrap();
    out.result.image.to_rgb(&SRGB)
}

fn white_sky(dir: &Path) {
    exr::prelude::write_rgb_file(dir.join("white.exr"), 16, 8, |_, _| {
        (1.0f32, 1.0f32, 1.0f32)
    })
    .unwrap();
}

/// A 2 × 2 sRGB PNG (nearest filter): each image quadrant's mean linear RGB (pixels next to
/// the texel boundary left out) equals its texel's decoded linear colour within 4 standard
/// errors (from the quadrant's pixel spread) + 0.01 absolute (the table uplift reproduces a
/// colour within 2e-3; the 1 nm D65 white differs from sRGB's rounded white point by < 1e-3 in
/// chromaticity, and a lane's light is reflected by the bilinearly filtered white map).
/// Also: v = 0 is the image's bottom row (texture rows top-first), u = 0 its left column.
#[test]
fn textured_floor_shows_the_texture_colours() {
    let dir = temp_dir("floor");
    white_sky(&dir);
    // Top row: red-ish, green-ish; bottom row: blue-ish, grey.
    let texels: [[u8; 3]; 4] = [[200, 60, 40], [50, 180, 70], [40, 80, 210], [128, 128, 128]];
    let img = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb(texels[(y * 2 + x) as usize]));
    img.save(dir.join("tex.png")).unwrap();
    let s = scene(
        &dir,
        &floor_scene(r#"(texture: (file: "tex.png", filter: "nearest"))"#),
    )
    .unwrap();
    let rgb = render_rgb(&s, 64);
    for (q, texel) in texels.iter().enumerate() {
        let want = texel.map(|v| spectrace::color::srgb_decode(v as f64 / 255.0));
        let (qx, qy) = (q % 2, q / 2);
        let mut px = Vec::new();
        for y in 0..16 {
            for x in 0..16 {
                if (x / 8, y / 8) == (qx, qy) && !(7..=8).contains(&x) && !(7..=8).contains(&y) {
                    px.push(rgb[y * 16 + x]);
                }
            }
        }
        for c in 0..3 {
            let n = px.len() as f64;
            let m = px.iter().map(|p| p[c]).sum::<f64>() / n;
            let var = px.iter().map(|p| (p[c] - m).powi(2)).sum::<f64>() / (n - 1.0);
            let e = (var / n).sqrt();
            eprintln!(
                "texel {q} channel {c}: {m:.4} ± {e:.4}, want {:.4}",
                want[c]
            );
            assert!(
                (m - want[c]).abs() < 4.0 * e + 0.01,
                "texel {q} channel {c}: {m} ± {e}, want {}",
                want[c]
            );
        }
    }
}

/// A spectral EXR texture (spectrace's own layout, 380–780 nm every 10 nm) of a flat 0.5
/// reflectance gives Y = 0.5 under the white sky of luminance 1 (held flat outside the nodes),
/// within 4 standard errors + 0.3%.
#[test]
fn spectral_exr_texture() {
    let dir = temp_dir("spectral");
    white_sky(&dir);
    let wavelengths: Vec<f64> = (0..=40).map(|k| 380.0 + 10.0 * k as f64).collect();
    let n = wavelengths.len();
    SpectralImage {
        width: 4,
        height: 4,
        step: 10.0,
        values: vec![0.5; 16 * n],
        wavelengths,
    }
    .write_exr(&dir.join("refl.exr"))
    .unwrap();
    let s = scene(&dir, &floor_scene(r#"(texture: "refl.exr")"#)).unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(32),
        seed: 3,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let out = render_with(&s, &settings, IntegratorKind::Pt, false, &|_, _| {}, None).unwrap();
    let y: Vec<f64> = out.result.image.xyz.iter().map(|p| p[1]).collect();
    let m = y.iter().sum::<f64>() / y.len() as f64;
    let e =
        (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (y.len() as f64 - 1.0) / y.len() as f64)
            .sqrt();
    eprintln!("spectral texture: Y = {m:.5} ± {e:.5} (want 0.5)");
    assert!((m - 0.5).abs() < 4.0 * e + 0.0015, "{m} ± {e}");
}

/// Bad textures are errors naming the file and the problem: missing, not an image, truncated,
/// a PNG header claiming 100000 × 100000 pixels, an unknown filter, a textured emitter given
/// one luminance (which of its texels would it fix?), a reflectance scale above 1.
#[test]
fn bad_textures_are_errors() {
    let dir = temp_dir("bad");
    white_sky(&dir);
    std::fs::write(dir.join("text.png"), b"not an image").unwrap();
    let img = image::RgbImage::from_pixel(8, 8, image::Rgb([1, 2, 3]));
    img.save(dir.join("ok.png")).unwrap();
    let bytes = std::fs::read(dir.join("ok.png")).unwrap();
    std::fs::write(dir.join("cut.png"), &bytes[..bytes.len() - 20]).unwrap();
    let mut huge = bytes.clone();
    huge[16..20].copy_from_slice(&100_000u32.to_be_bytes());
    huge[20..24].copy_from_slice(&100_000u32.to_be_bytes());
    std::fs::write(dir.join("huge.png"), huge).unwrap();
    for (refl, want) in [
        (r#"(texture: "missing.png")"#, "missing.png"),
        (r#"(texture: "text.png")"#, "text.png"),
        (r#"(texture: "cut.png")"#, "cut.png"),
        (r#"(texture: "huge.png")"#, "huge.png"),
        (r#"(texture: (file: "ok.png", filter: "cubic"))"#, "cubic"),
        (r#"(texture: (file: "ok.png", scale: 2))"#, "scale"),
    ] {
        let Err(err) = scene(&dir, &floor_scene(refl)) else {
            panic!("{refl}: expected an error")
        };
        assert!(err.contains(want), "{refl}: {err}");
    }
    let emitter = r#"(
        materials: [(name: "glow", type: "emissive", params: (radiance: (texture: "ok.png"), luminance_cd_m2: 100))],
        objects: [(name: "q", type: "quad", material: "glow",
                   params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0)))],
        cameras: [(name: "c", type: "pinhole", params: (position: (0, 0, 3), look_at: (0, 0, 0), resolution: (4, 4)))],
    )"#;
    let Err(err) = scene(&dir, emitter) else {
        panic!("a textured emitter given a luminance: expected an error")
    };
    assert!(err.contains("texture"), "{err}");
}
