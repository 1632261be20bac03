//! Where a caustic render's squared error sits, for `spectrace bench speed`: the caustic
//! scene's pixels split into regions found from the reference alone (as
//! `scripts/caustic_regions.py` does; docs/performance.md, "The caustic"), and the squared error
//! of a render summed per region over the pixels the benchmark's RMSE counts.
//!
//! | region      | pixels (160×120)     | what it shows                                          |
//! |-------------|----------------------|--------------------------------------------------------|
//! | lamp images | above the floor row, reference luminance > 0.08, dilated by one pixel | the 5 cm lamp seen reflected and refracted in the ball: only camera paths through the glass (s = 0) render it |
//! | caustic     | floor rows, luminance > 0.08, dilated | the focused light on the floor (its core, > 1.0, is left out of the RMSE) |
//! | rest        | everything else      | the directly and indirectly lit floor and wall         |
//!
//! The floor row is 70/120 of the image height (the ball's lowest visible point is above it,
//! the floor's caustic below). Luminance is Rec. 709's (linear sRGB) Y.

use crate::analysis::{light_mask, RgbImage};

/// Luminance above which a reference pixel belongs to the lamp images or the caustic.
const BRIGHT: f64 = 0.08;

/// Names of the regions, in the order of [`RegionSplit::sse`].
pub const REGION_NAMES: [&str; 3] = ["lamp images", "caustic", "rest"];

/// The columns of the benchmark's region table: a name and the regions (indices into
/// [`REGION_NAMES`]) it sums. The last leaves out the lamp images, whose expected error is
/// decided by samples too rare for a few runs to contain (docs/performance.md, "Several seeds
/// per renderer").
pub const REGION_GROUPS: [(&str, &[usize]); 4] = [
    ("lamp images", &[0]),
    ("caustic", &[1]),
    ("rest", &[2]),
    ("all but the lamp images", &[1, 2]),
];

/// The region of every pixel (index into [`REGION_NAMES`]), `None` where the benchmark's RMSE
/// leaves the pixel out (the reference's light mask).
#[derive(Clone, Debug)]
pub struct CausticRegions {
    region: Vec<Option<usize>>,
}

/// Squared error of one render summed per region, with the number of values (pixels × 3).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RegionSplit {
    /// Σ (a − b)² over the region's counted pixels and channels.
    pub sse: [f64; 3],
    /// Number of values (pixels × 3 channels) in each region.
    pub values: [usize; 3],
}

impl RegionSplit {
    /// Mean squared error over the regions `group` together.
    pub fn group_mse(&self, group: &[usize]) -> f64 {
        let sse: f64 = group.iter().map(|&i| self.sse[i]).sum();
        sse / group.iter().map(|&i| self.values[i]).sum::<usize>().max(1) as f64
    }
    /// Share of the squared error in the regions `group`.
    pub fn group_share(&self, group: &[usize]) -> f64 {
        group.iter().map(|&i| self.sse[i]).sum::<f64>() / self.sse.iter().sum::<f64>().max(1e-300)
    }
    /// Mean squared error over all regions: the benchmark's MSE (RMSE²).
    pub fn total_mse(&self) -> f64 {
        self.sse.iter().sum::<f64>() / self.values.iter().sum::<usize>().max(1) as f64
    }
}

fn luminance(p: &[f64; 3]) -> f64 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// `mask` grown by one pixel in the 8-neighbourhood.
fn dilate(mask: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut out = vec![false; mask.len()];
    for y in 0..h {
        for x in 0..w {
            if !mask[y * w + x] {
                continue;
            }
            for yy in y.saturating_sub(1)..(y + 2).min(h) {
                for xx in x.saturating_sub(1)..(x + 2).min(w) {
                    out[yy * w + xx] = true;
                }
            }
        }
    }
    out
}

impl CausticRegions {
    /// The regions of the caustic scene's `reference`.
    pub fn new(reference: &RgbImage) -> Self {
        let (w, h) = (reference.width as usize, reference.height as usize);
        let floor_row = (h as f64 * 70.0 / 120.0).round() as usize;
        let bright = |upper: bool| -> Vec<bool> {
            (0..w * h)
                .map(|i| {
                    let above = i / w < floor_row;
                    above == upper && luminance(&reference.rgb[i]) > BRIGHT
                })
                .collect()
        };
        let lamp = dilate(&bright(true), w, h);
        let caustic = dilate(&bright(false), w, h);
        let excluded = light_mask(reference);
        let region = (0..w * h)
            .map(|i| {
                let above = i / w < floor_row;
                if excluded[i] {
                    None
                } else if above && lamp[i] {
                    Some(0)
                } else if !above && caustic[i] {
                    Some(1)
                } else {
                    Some(2)
                }
            })
            .collect();
        Self { region }
    }

    /// Pixels counted in each region.
    pub fn pixels(&self) -> [usize; 3] {
        let mut n = [0; 3];
        for r in self.region.iter().flatten() {
            n[*r] += 1;
        }
        n
    }

    /// The squared error of `test` against `reference` per region. Pixels with a non-finite
    /// channel are left out, as `spectrace compare` does. The images must have the size of the
    /// reference these regions were made from.
    pub fn split(&self, test: &RgbImage, reference: &RgbImage) -> RegionSplit {
        let mut out = RegionSplit::default();
        for ((r, t), f) in self.region.iter().zip(&test.rgb).zip(&reference.rgb) {
            let Some(r) = *r else { continue };
            if t.iter().chain(f.iter()).any(|v| !v.is_finite()) {
                continue;
            }
            out.sse[r] += (0..3).map(|c| (t[c] - f[c]) * (t[c] - f[c])).sum::<f64>();
            out.values[r] += 3;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{compare_images, CompareOptions};

    // A synthetic 8×12 reference: one bright pixel above the floor row (row 7 of 12) and one
    // below; a light pixel (> 1) below. The regions are the dilated bright pixels on their side
    // of the floor row, the light and its 4-neighbour rim are left out, and the regions' total
    // MSE equals `spectrace compare --exclude-light`'s RMSE² (exact up to rounding: 1e-12
    // relative, the same sums in another order).
    #[test]
    fn regions_follow_the_reference_and_sum_to_the_benchmark_mse() {
        let (w, h) = (8u32, 12u32);
        let mut rgb = vec![[0.01; 3]; (w * h) as usize];
        rgb[(2 * w + 3) as usize] = [0.5; 3]; // lamp image, row 2
        rgb[(9 * w + 2) as usize] = [0.3; 3]; // caustic, row 9
        rgb[(10 * w + 6) as usize] = [5.0; 3]; // light (left out)
        let reference = RgbImage {
            width: w,
            height: h,
            rgb,
        };
        let regions = CausticRegions::new(&reference);
        // Lamp: 3×3 around (3, 2). Excluded: the light at (6, 10) and its 4 neighbours.
        // Caustic: 3×3 around (2, 9) and the 4 not excluded of the 3×3 around the light.
        assert_eq!(regions.pixels(), [9, 13, 96 - 9 - 13 - 5]);
        let test = RgbImage {
            width: w,
            height: h,
            rgb: (0..w * h)
                .map(|i| [0.01 + 0.001 * (i % 7) as f64, 0.02, 0.0])
                .collect(),
        };
        let split = regions.split(&test, &reference);
        let (c, _) = compare_images(
            &test,
            &reference,
            CompareOptions {
                exclude_light: true,
            },
        );
        let mse = c.rmse * c.rmse;
        assert!(
            (split.total_mse() - mse).abs() <= 1e-12 * mse,
            "{split:?} {mse}"
        );
        // A group of all three regions is the whole; shares of a partition sum to one.
        assert!((split.group_mse(&[0, 1, 2]) - mse).abs() <= 1e-12 * mse);
        let shares: f64 = (0..3).map(|i| split.group_share(&[i])).sum();
        assert!((shares - 1.0).abs() < 1e-12, "{shares}");
    }
}
