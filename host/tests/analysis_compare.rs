//! `spectrace compare` on images with known differences, and its error messages.

use spectrace::analysis::{compare_files, AnalysisError, CompareOptions};
use spectrace::color::SRGB;
use spectrace::film::{write_exr, XyzImage};
use std::path::{Path, PathBuf};

fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-cmp-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An EXR whose linear sRGB is `rgb(x, y)`.
fn write_rgb(path: &Path, w: u32, h: u32, rgb: impl Fn(u32, u32) -> [f64; 3]) {
    let xyz = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| SRGB.rgb_to_xyz(rgb(x, y)))
        .collect();
    write_exr(
        path,
        &XyzImage {
            width: w,
            height: h,
            xyz,
        },
        &SRGB,
    )
    .unwrap();
}

/// Grey 0.2 vs grey 0.3 everywhere: RMSE = 0.1 and relative MSE = 0.01/(0.09 + ε) exactly up to
/// the f32 storage of the EXR and the RGB→XYZ→RGB round trip (1e-5 relative covers both); ΔE00
/// of two neutral greys is their L* difference scaled by S_L (checked against L* computed here).
/// A bright 2×2 "light" in the reference is left out with its one-pixel rim (12 pixels).
#[test]
fn known_differences() {
    let d = dir("known");
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    write_rgb(&a, 16, 8, |_, _| [0.2; 3]);
    write_rgb(&b, 16, 8, |x, y| {
        if (4..6).contains(&x) && (2..4).contains(&y) {
            [5.0; 3]
        } else {
            [0.3; 3]
        }
    });
    let (all, _, _) = compare_files(&a, &b, CompareOptions::default()).unwrap();
    assert_eq!(all.pixels, 128);
    let (c, per_pixel, size) = compare_files(
        &a,
        &b,
        CompareOptions {
            exclude_light: true,
        },
    )
    .unwrap();
    assert_eq!(size, (16, 8));
    assert_eq!(c.excluded_light, 12);
    assert_eq!(c.pixels, 116);
    assert_eq!(per_pixel.iter().filter(|p| p.is_none()).count(), 12);
    assert!((c.rmse - 0.1).abs() < 1e-5 * 0.1, "{}", c.rmse);
    let want_rel = 0.01 / (0.09 + c.rel_mse_epsilon);
    assert!(
        (c.rel_mse - want_rel).abs() < 1e-5 * want_rel,
        "{}",
        c.rel_mse
    );
    let lstar = |y: f64| 116.0 * y.cbrt() - 16.0;
    let (l1, l2) = (lstar(0.2), lstar(0.3));
    let lm = 0.5 * (l1 + l2) - 50.0;
    let want_de = (l2 - l1) / (1.0 + 0.015 * lm * lm / (20.0 + lm * lm).sqrt());
    assert!(
        (c.delta_e_mean - want_de).abs() < 1e-3,
        "{} vs {want_de}",
        c.delta_e_mean
    );
    assert!((c.delta_e_p99 - want_de).abs() < 1e-3);
    for r in c.mean_ratio {
        assert!((r - 2.0 / 3.0).abs() < 1e-5);
    }
    std::fs::remove_dir_all(&d).ok();
}

/// The bundled Mitsuba reference compared with itself: every metric exactly 0, and its light
/// mask is non-empty (the ceiling light is visible) but small (< 5% of the image).
#[test]
fn reference_against_itself() {
    let r = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/reference/cbox_reference_mitsuba.exr");
    let (c, _, size) = compare_files(
        &r,
        &r,
        CompareOptions {
            exclude_light: true,
        },
    )
    .unwrap();
    assert_eq!(size, (256, 256));
    assert_eq!(
        (c.rmse, c.rel_mse, c.delta_e_mean, c.delta_e_p99),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert!(
        c.excluded_light > 0 && c.excluded_light < 256 * 256 / 20,
        "{}",
        c.excluded_light
    );
}

/// Missing file, a file that is not EXR, an EXR without R/G/B and a size mismatch each give an
/// error naming the file at fault (and the channels found), never a panic.
#[test]
fn bad_inputs_are_named() {
    let d = dir("bad");
    std::fs::create_dir_all(&d).unwrap();
    let good = d.join("good.exr");
    write_rgb(&good, 4, 4, |_, _| [0.5; 3]);
    let small = d.join("small.exr");
    write_rgb(&small, 2, 4, |_, _| [0.5; 3]);
    let text = d.join("text.exr");
    std::fs::write(&text, "not an image").unwrap();
    let luma = d.join("luma.exr");
    {
        use exr::prelude::*;
        let ch = AnyChannel::new("Y", FlatSamples::F32(vec![0.5; 16]));
        let layer = Layer::new(
            (4, 4),
            LayerAttributes::named(""),
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(SmallVec::from_vec(vec![ch])),
        );
        Image::from_layer(layer).write().to_file(&luma).unwrap();
    }
    let o = CompareOptions::default();
    let missing = d.join("missing.exr");
    let e = compare_files(&missing, &good, o).unwrap_err();
    assert!(matches!(e, AnalysisError::Read { .. }) && e.to_string().contains("missing.exr"));
    let e = compare_files(&good, &text, o).unwrap_err().to_string();
    assert!(e.contains("text.exr"), "{e}");
    let e = compare_files(&luma, &good, o).unwrap_err().to_string();
    assert!(
        e.contains("luma.exr") && e.contains("channels found: Y"),
        "{e}"
    );
    let e = compare_files(&good, &small, o).unwrap_err().to_string();
    assert!(
        e.contains("4×4") && e.contains("2×4") && e.contains("small.exr"),
        "{e}"
    );
    std::fs::remove_dir_all(&d).ok();
}
