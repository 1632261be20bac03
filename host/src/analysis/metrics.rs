//! Image error metrics against a reference: RMSE, relative MSE and CIEDE2000 statistics, with
//! the directly visible light optionally left out the way `shared/anchors/rmse.py` does it
//! (reference pixels with any channel above 1.0, dilated by one pixel in the 4-neighbourhood):
//! those pixels are orders of magnitude brighter than the rest and would dominate the RMSE.

use super::ciede2000::delta_e_2000;
use super::cielab::linear_srgb_to_lab;
use super::RgbImage;

/// ε of the relative MSE, `mean((a − b)² / (b² + ε))`: keeps black reference pixels from
/// dividing by zero; 1e-2 is small next to the Cornell box's typical pixel (≈ 0.1–0.5 linear).
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// What to leave out of the comparison.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CompareOptions {
    /// Leave out the directly visible light (see the module docs).
    pub exclude_light: bool,
}

/// The numbers `spectrace compare` prints (serialised as its `--json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Comparison {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels left out as light (0 unless `exclude_light`).
    pub excluded_light: usize,
    /// Pixels left out by the caller's mask (e.g. those showing specular surfaces), beyond the
    /// light.
    #[serde(default)]
    pub excluded_other: usize,
    /// Pixels of the test image with a NaN or infinite channel (left out of every metric).
    pub non_finite: usize,
    /// √(mean over pixels and channels of (a − b)²), linear RGB units.
    pub rmse: f64,
    /// mean over pixels and channels of (a − b)² / (b² + ε), ε = [`REL_MSE_EPSILON`].
    pub rel_mse: f64,
    /// The ε used in `rel_mse`.
    pub rel_mse_epsilon: f64,
    /// Mean CIEDE2000 over the compared pixels (CIELAB via XYZ, D65 white with Y = 1).
    pub delta_e_mean: f64,
    /// 99th percentile (nearest rank) of the per-pixel CIEDE2000.
    pub delta_e_p99: f64,
    /// Largest per-pixel CIEDE2000.
    pub delta_e_max: f64,
    /// Mean of the test image over the mean of the reference over the compared pixels, per
    /// channel (R, G, B).
    pub mean_ratio: [f64; 3],
}

/// The light mask of `reference`: `true` where the directly visible light (or its one-pixel
/// rim) is.
pub fn light_mask(reference: &RgbImage) -> Vec<bool> {
    let (w, h) = (reference.width as usize, reference.height as usize);
    let bright: Vec<bool> = reference
        .rgb
        .iter()
        .map(|p| p.iter().cloned().fold(f64::MIN, f64::max) > 1.0)
        .collect();
    let mut mask = bright.clone();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if bright[i] {
                if x > 0 {
                    mask[i - 1] = true;
                }
                if x + 1 < w {
                    mask[i + 1] = true;
                }
                if y > 0 {
                    mask[i - w] = true;
                }
                if y + 1 < h {
                    mask[i + w] = true;
                }
            }
        }
    }
    mask
}

/// Compare `test` with `reference` (same size; the caller checks). Returns the metrics and the
/// per-pixel ΔE00 (`None` for pixels left out).
pub fn compare_images(
    test: &RgbImage,
    reference: &RgbImage,
    options: CompareOptions,
) -> (Comparison, Vec<Option<f64>>) {
    compare_images_excluding(test, reference, options, None)
}

/// [`compare_images`] that also leaves out the pixels where `exclude` is `true` (same length as
/// the images; counted in [`Comparison::excluded_other`]).
pub fn compare_images_excluding(
    test: &RgbImage,
    reference: &RgbImage,
    options: CompareOptions,
    exclude: Option<&[bool]>,
) -> (Comparison, Vec<Option<f64>>) {
    let light = if options.exclude_light {
        light_mask(reference)
    } else {
        vec![false; reference.rgb.len()]
    };
    let other: Vec<bool> = (0..light.len())
        .map(|i| !light[i] && exclude.is_some_and(|e| e.get(i).copied().unwrap_or(false)))
        .collect();
    let mask: Vec<bool> = light.iter().zip(&other).map(|(a, b)| *a || *b).collect();
    let mut sq = 0.0f64;
    let mut rel = 0.0f64;
    let mut sum_t = [0.0f64; 3];
    let mut sum_r = [0.0f64; 3];
    let mut n = 0usize;
    let mut non_finite = 0usize;
    let mut per_pixel = Vec::with_capacity(test.rgb.len());
    let mut des = Vec::with_capacity(test.rgb.len());
    for (i, (t, r)) in test.rgb.iter().zip(&reference.rgb).enumerate() {
        if mask[i] {
            per_pixel.push(None);
            continue;
        }
        if t.iter().chain(r.iter()).any(|v| !v.is_finite()) {
            non_finite += 1;
            per_pixel.push(None);
            continue;
        }
        n += 1;
        for c in 0..3 {
            let d = t[c] - r[c];
            sq += d * d;
            rel += d * d / (r[c] * r[c] + REL_MSE_EPSILON);
            sum_t[c] += t[c];
            sum_r[c] += r[c];
        }
        let de = delta_e_2000(linear_srgb_to_lab(*t), linear_srgb_to_lab(*r));
        des.push(de);
        per_pixel.push(Some(de));
    }
    let values = (3 * n).max(1) as f64;
    des.sort_by(f64::total_cmp);
    let (mean, p99, max) = if des.is_empty() {
        (0.0, 0.0, 0.0)
    } else {
        let rank = ((0.99 * des.len() as f64).ceil() as usize).clamp(1, des.len()) - 1;
        (
            des.iter().sum::<f64>() / des.len() as f64,
            des[rank],
            des[des.len() - 1],
        )
    };
    let comparison = Comparison {
        pixels: n,
        excluded_light: light.iter().filter(|m| **m).count(),
        excluded_other: other.iter().filter(|m| **m).count(),
        non_finite,
        rmse: (sq / values).sqrt(),
        rel_mse: rel / values,
        rel_mse_epsilon: REL_MSE_EPSILON,
        delta_e_mean: mean,
        delta_e_p99: p99,
        delta_e_max: max,
        mean_ratio: std::array::from_fn(|c| {
            if sum_r[c] != 0.0 {
                sum_t[c] / sum_r[c]
            } else {
                f64::NAN
            }
        }),
    };
    (comparison, per_pixel)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Two 3×1 images that differ only in pixel 2 by 0.3 in every channel: with that pixel
    // masked out the comparison is exact (RMSE 0, counted once in `excluded_other`); without the
    // mask RMSE = √(0.3²/3) exactly (one of three pixels, all channels).
    #[test]
    fn excluded_pixels_do_not_count() {
        let reference = RgbImage {
            width: 3,
            height: 1,
            rgb: vec![[0.2; 3], [0.4; 3], [0.5; 3]],
        };
        let mut test = reference.clone();
        test.rgb[2] = [0.8; 3];
        let opts = CompareOptions {
            exclude_light: false,
        };
        let (all, _) = compare_images(&test, &reference, opts);
        assert!(
            (all.rmse - (0.09f64 / 3.0).sqrt()).abs() < 1e-12,
            "{}",
            all.rmse
        );
        assert_eq!(all.excluded_other, 0);
        let (masked, per_pixel) =
            compare_images_excluding(&test, &reference, opts, Some(&[false, false, true]));
        assert_eq!(
            (masked.rmse, masked.pixels, masked.excluded_other),
            (0.0, 2, 1)
        );
        assert!(per_pixel[2].is_none());
    }
}
