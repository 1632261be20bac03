//! The default scene (measured spectral Cornell box): no NaN/Inf, a mean that matches an
//! independent renderer, and bitwise determinism across thread counts.

use ron::Value;
use spectrace::color::SRGB;
use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, cornell_box_description, BuiltinFactory, Scene};
use std::path::Path;

/// The Cornell box at a reduced resolution (the image mean does not depend on it: a box filter
/// tiles the film, so the mean is the film-plane average of radiance either way).
fn cornell(res: u32) -> Scene {
    let mut desc = cornell_box_description().unwrap();
    if let Value::Map(m) = &mut desc.cameras[0].params {
        m.insert(
            Value::String("resolution".into()),
            Value::Seq(vec![
                Value::Number(ron::Number::from(res as i64)),
                Value::Number(ron::Number::from(res as i64)),
            ]),
        );
    }
    build_scene(&desc, Path::new("."), Path::new("test"), &[&BuiltinFactory]).unwrap()
}

/// Independent estimate: Mitsuba 3.9.1 `llvm_ad_spectral` path tracer on the same data at
/// 10 240 spp, 256×256 (`/work/shared/anchors/cbox_reference_mitsuba.exr`, produced by
/// `mitsuba_cbox.py`; same film convention, CIE 1931 → linear sRGB). Its image mean, read from
/// that EXR: R 0.227357, G 0.114324, B 0.025726; luminance Y = 0.212671 R + 0.715160 G +
/// 0.072169 B = 0.131969 (Rec. 709 Y row, as Mitsuba's sRGB matrix implies).
const MITSUBA_MEAN_Y: f64 = 0.131969;

/// Mean luminance of a 128×128, 64 spp render (1 048 576 paths) within 1% of Mitsuba's; no NaN
/// or Inf pixel. Why 1%: over 8 seeds at 64×64×64 spp the mean Y scattered with σ ≈ 0.1% around
/// 0.998 × Mitsuba's (the −0.2% offset is below what the data pins down: CMF tabulation and
/// spectral interpolation differ slightly between the renderers), so 1% leaves ample room for
/// noise while a real radiometric or colour bug is larger (the furnace bug this suite caught was
/// 12% per bounce).
#[test]
fn cornell_box_mean_matches_mitsuba_reference() {
    let scene = cornell(128);
    let settings = RenderSettings {
        budget: SampleBudget::Spp(64),
        seed: 1,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let res = render(&scene, &settings, &|_, _| {}, None).unwrap();
    assert_eq!(res.image.non_finite_count(), 0);
    assert!(res
        .image
        .xyz
        .iter()
        .all(|p| p.iter().all(|v| v.is_finite() && *v >= -1e-9)));
    let xyz = res.image.mean_xyz();
    let rgb = SRGB.xyz_to_rgb(xyz);
    assert!(
        (xyz[1] / MITSUBA_MEAN_Y - 1.0).abs() < 0.01,
        "mean Y {} vs Mitsuba {MITSUBA_MEAN_Y} (mean linear sRGB {rgb:?})",
        xyz[1]
    );
}

/// Same seed, 1 thread vs 2 threads: bitwise identical XYZ images (every sample's random
/// numbers depend only on seed, pixel and sample index; tiles merge in a fixed order). A
/// different seed must give a different image (the check can fail).
#[test]
fn render_is_deterministic_across_thread_counts() {
    let scene = cornell(24);
    let run = |threads: usize, seed: u64| {
        let s = RenderSettings {
            budget: SampleBudget::Spp(4),
            seed,
            threads: Some(threads),
            tile_size: 7,
            ..RenderSettings::default()
        };
        render(&scene, &s, &|_, _| {}, None).unwrap().image
    };
    let a = run(1, 42);
    let b = run(2, 42);
    let c = run(3, 42);
    assert!(a == b && b == c, "images differ between thread counts");
    assert!(run(2, 43) != a);
}
