//! The caustic scene against an independent renderer: spectrace's BDPT and Mitsuba 3's spectral
//! path tracer (`host/data/reference/caustic_reference_mitsuba.exr`, 161,792 spp, made by
//! `docs/figures/caustic/mitsuba_reference.py`) must agree where the caustic is, the part of the
//! image only bidirectional strategies estimate well and the easiest to get wrong (refraction's
//! 1/η² radiance scaling, Fresnel weights, MIS through delta vertices).

use spectrace::analysis::RgbImage;
use spectrace::color::SRGB;
use spectrace::integrator::{render_with, IntegratorKind, RenderSettings, SampleBudget};
use spectrace::scene::{load_scene_file, BuiltinFactory};
use std::path::Path;

/// Per-channel mean of `img` over rows `ys` and columns `xs`.
fn block_mean(img: &RgbImage, ys: std::ops::Range<u32>, xs: std::ops::Range<u32>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in ys {
        for x in xs.clone() {
            let p = img.rgb[(y * img.width + x) as usize];
            for c in 0..3 {
                sum[c] += p[c];
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

// Two blocks of the floor (160×120 image): the ball's shadow with the caustic inside it (rows
// 70–110, columns 40–120) and the caustic's core (rows 74–90, columns 68–92, where the focused
// light is ~4× the lit floor). BDPT at 32 spp, seed 1, per channel within 1.5% (wide block) and
// 3% (core) of Mitsuba's means. Why: over seeds 1–4 the wide block's means scattered within 0.6%
// of Mitsuba's and the core's within 1.5%, with the core's blue 0.9% below Mitsuba's on average
// (the 2048-spp BDPT reference shows the same −1.1%: partly Mitsuba's own caustic noise, which
// this test cannot separate). A broken caustic is far outside: the refraction-scaling fault fixed
// on 2026-11-24 put single pixels at 2.25× and a missing 1/η² would scale the core by 2.25.
#[test]
fn bdpt_caustic_matches_mitsuba() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let reference =
        RgbImage::read_exr(&root.join("data/reference/caustic_reference_mitsuba.exr")).unwrap();
    let scene = load_scene_file(&root.join("../scenes/caustic.ron"), &[&BuiltinFactory]).unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(32),
        seed: 1,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let out = render_with(
        &scene,
        &settings,
        IntegratorKind::Bdpt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    let image = RgbImage::from_xyz(&out.result.image, &SRGB);
    assert_eq!(
        (image.width, image.height),
        (reference.width, reference.height)
    );
    for (name, ys, xs, tol) in [
        ("shadow and caustic", 70..110, 40..120, 0.015),
        ("caustic core", 74..90, 68..92, 0.03),
    ] {
        let ours = block_mean(&image, ys.clone(), xs.clone());
        let theirs = block_mean(&reference, ys, xs);
        for c in 0..3 {
            let ratio = ours[c] / theirs[c];
            assert!(
                (ratio - 1.0).abs() < tol,
                "{name}, channel {c}: spectrace {} vs Mitsuba {} (ratio {ratio:.4})",
                ours[c],
                theirs[c]
            );
        }
    }
}
