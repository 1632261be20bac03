//! Textured emitters: an `emissive` material whose `radiance` is an image. A 1 × 2 m quad
//! shows a two-colour texture (left texel one colour, right texel another, nearest filter),
//! written as an RGB OpenEXR into a temporary directory.
//!
//! - The rendered image of the emitter gives the texture's RGB back (illuminant uplift → film
//!   XYZ → linear sRGB), in PT, BDPT and LT (LT sees the emitter only through light paths that
//!   start on it, so this also checks the light's own radiance lookup and its power-weighted
//!   start positions).
//! - Illuminance under it, from both sensor estimators, equals the integral of the texture's
//!   luminance over the quad (`E = ∫ L_v cos θ cos θ' / r² dA`, by quadrature here).

use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::sensor::{measure, Estimator, MeasureSettings, KM_LM_PER_W};
use std::path::{Path, PathBuf};

const LEFT: [f64; 3] = [4.0, 1.0, 0.5];
const RIGHT: [f64; 3] = [0.3, 0.8, 2.5];

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-emtex-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The quad `(-1, -0.5, 0) + s·(2, 0, 0) + t·(0, 1, 0)` emitting along +z, the texture's left
/// texel on s < ½; a camera 3 m in front; two sensor points 1 m in front facing it.
fn scene(dir: &Path) -> Scene {
    exr::prelude::write_rgb_file(dir.join("two.exr"), 2, 1, |x, _| {
        let c = if x == 0 { LEFT } else { RIGHT };
        (c[0] as f32, c[1] as f32, c[2] as f32)
    })
    .unwrap();
    let text = r#"(
        materials: [(name: "glow", type: "emissive",
                     params: (radiance: (texture: (file: "two.exr", filter: "nearest", wrap: "clamp"))))],
        objects: [(name: "panel", type: "quad", material: "glow",
                   params: (corner: (-1, -0.5, 0), edge0: (2, 0, 0), edge1: (0, 1, 0)))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 0, 3), look_at: (0, 0, 0), fov: 12, resolution: (32, 16)))],
        sensors: [(name: "front", type: "illuminance_grid",
                   params: (corner: (-0.01, 0.01, 1), edge0: (0.02, 0, 0), edge1: (0, -0.02, 0),
                            resolution: (1, 1))),
                  (name: "side", type: "illuminance_grid",
                   params: (corner: (0.79, 0.31, 0.6), edge0: (0.02, 0, 0), edge1: (0, -0.02, 0),
                            resolution: (1, 1)))],
    )"#;
    let file = dir.join("scene.ron");
    let desc = parse_scene_str(text, &file).unwrap();
    build_scene(&desc, dir, &file, &[&BuiltinFactory]).unwrap()
}

/// XYZ (film units) → linear sRGB (IEC 61966-2-1's matrix).
fn to_srgb(c: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = c;
    [
        3.2406 * x - 1.5372 * y - 0.4986 * z,
        -0.9689 * x + 1.8758 * y + 0.0415 * z,
        0.0557 * x - 0.2040 * y + 1.0570 * z,
    ]
}

/// The image of the emitter is the texture: per half of the image (columns 0–13 and 18–31,
/// the seam's columns left out), the mean linear-sRGB value of each channel is within
/// 4 standard errors (from the pixels' spread: spectral sampling noise) + 1% of the brightest
/// channel (the sigmoid table's RGB round trip is within 2e-3; the film's observer table and
/// the D65 white of the uplift against the sRGB matrix's rounded white add a few 1e-3) of the
/// texel's RGB. With the emission uplifted as a reflectance, or without the white, the colours
/// are off by 10% and more.
#[test]
fn the_emitter_shows_its_texture() {
    let dir = temp_dir("image");
    let s = scene(&dir);
    for (kind, spp) in [
        (IntegratorKind::Pt, 32),
        (IntegratorKind::Bdpt, 16),
        (IntegratorKind::Lt, 64),
    ] {
        let settings = RenderSettings {
            budget: SampleBudget::Spp(spp),
            seed: 4,
            threads: Some(2),
            tracer: PathTracer::default(),
            ..RenderSettings::default()
        };
        let out = render_with(&s, &settings, kind, false, &|_, _| {}, None).unwrap();
        let img = &out.result.image;
        assert_eq!(img.non_finite_count(), 0);
        for (half, cols, want) in [("left", 0..14, LEFT), ("right", 18..32, RIGHT)] {
            let px: Vec<[f64; 3]> = (0..16)
                .flat_map(|y| cols.clone().map(move |x| y * 32 + x))
                .map(|i| {
                    let p = img.xyz[i];
                    to_srgb([p[0], p[1], p[2]])
                })
                .collect();
            let n = px.len() as f64;
            let top = want.iter().cloned().fold(0.0, f64::max);
            for ch in 0..3 {
                let m = px.iter().map(|p| p[ch]).sum::<f64>() / n;
                let var = px.iter().map(|p| (p[ch] - m).powi(2)).sum::<f64>() / (n - 1.0);
                let se = (var / n).sqrt();
                eprintln!(
                    "{kind} {half} channel {ch}: {m:.4} ± {se:.4} (texel {})",
                    want[ch]
                );
                assert!(
                    (m - want[ch]).abs() < 4.0 * se + 0.01 * top,
                    "{kind} {half} channel {ch}: {m} ± {se}, texel {}",
                    want[ch]
                );
            }
        }
    }
}

/// Illuminance at the two sensor points against `E = Σ_halves L_v ∫ cos θ cos θ' / r² dA`
/// (midpoint rule on 1000 × 500 cells: converged to < 1e-5 here), `L_v = 683.002 lm/W × Y ×
/// ∫ȳ dλ`, `Y` the texel's luminance from its RGB (0.2126 R + 0.7152 G + 0.0722 B, what the
/// uplift keeps within 2e-3). Both sensor estimators (sensor path tracing for PT/BDPT, light
/// tracing for LT) within 4 standard errors + 0.5% (the uplift's luminance and the observer
/// table's 1 nm sum), standard errors under 2% of the value.
#[test]
fn illuminance_under_it_is_the_textures_integral() {
    let dir = temp_dir("lux");
    let s = scene(&dir);
    let obs = CieObserverKind::Cie1931_2.get();
    let int_y: f64 = (360..=830).map(|l| obs.xyz_bar(l as f64)[1]).sum();
    let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let lv = [lum(LEFT), lum(RIGHT)].map(|y| KM_LM_PER_W * y * int_y);
    let expected = |p: [f64; 3]| {
        let (nx, ny) = (1000usize, 500usize);
        let da = (2.0 / nx as f64) * (1.0 / ny as f64);
        let mut e = 0.0;
        for i in 0..nx {
            let x = -1.0 + (i as f64 + 0.5) * 2.0 / nx as f64;
            let l = if x < 0.0 { lv[0] } else { lv[1] };
            for j in 0..ny {
                let y = -0.5 + (j as f64 + 0.5) / ny as f64;
                let (dx, dy, dz) = (p[0] - x, p[1] - y, p[2]);
                let r2 = dx * dx + dy * dy + dz * dz;
                e += l * dz * dz / (r2 * r2) * da;
            }
        }
        e
    };
    for (grid, p) in [("front", [0.0, 0.0, 1.0]), ("side", [0.8, 0.3, 0.6])] {
        let want = expected(p);
        let g = s.sensors.iter().find(|g| g.name == grid).unwrap();
        for est in [Estimator::SensorPathTracing, Estimator::LightTracing] {
            let settings = MeasureSettings {
                estimator: est,
                samples: 40_000,
                seed: 3,
                threads: Some(2),
                tracer: PathTracer::default(),
            };
            let r = measure(&s, g, &settings).unwrap();
            let (lx, se) = (r.lux[0], r.stderr[0]);
            eprintln!("{grid} {est:?}: {lx:.2} ± {se:.2} lx, integral {want:.2} lx");
            assert!(se < 0.02 * want, "{grid} {est:?}: σ {se} for {want}");
            assert!(
                (lx - want).abs() < 4.0 * se + 0.005 * want,
                "{grid} {est:?}: {lx} ± {se} lx vs {want} lx"
            );
        }
    }
}
