//! Exposure of the PNG preview. The EXR always holds the physical values; the PNG shows them
//! times a linear multiplier: `render --exposure EV` (2^EV), else the scene's `png_exposure`,
//! else 1 — unless the image would then be nearly black or mostly clipped, in which case
//! [`auto_exposure`] picks one (and `render` says so in its summary).
//!
//! The rule (on the luminance Y of each pixel, as the PNG would show it at multiplier 1):
//! - nearly black: 99% of the pixels are below Y = 0.01 (8-bit sRGB value 25 of 255);
//! - mostly clipped: more than half of the pixels are above Y = 1.
//!
//! The multiplier then brings the log-average luminance of the lit pixels to 0.18 (middle
//! grey, the usual photographic key), but never so far that the brightest 5% of lit pixels
//! pass 0.9 — whichever is smaller.

use super::XyzImage;

/// Threshold of "nearly black": the 99th percentile of Y below this.
pub const NEARLY_BLACK_Y: f64 = 0.01;

/// An exposure picked for an image that would be unreadable at multiplier 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoExposure {
    /// Linear multiplier of the image.
    pub multiplier: f64,
    /// True when the image was nearly black (else it was mostly clipped).
    pub was_dark: bool,
}

impl AutoExposure {
    /// The multiplier in EV (log2).
    pub fn ev(&self) -> f64 {
        self.multiplier.log2()
    }
}

/// `q`-quantile of sorted values (nearest rank).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// The exposure `image` needs, or `None` when it reads well at multiplier 1 (or is entirely
/// black, which no exposure helps).
pub fn auto_exposure(image: &XyzImage) -> Option<AutoExposure> {
    let mut y: Vec<f64> = image
        .xyz
        .iter()
        .map(|p| if p[1].is_finite() { p[1].max(0.0) } else { 0.0 })
        .collect();
    if y.is_empty() {
        return None;
    }
    y.sort_by(f64::total_cmp);
    let dark = quantile(&y, 0.99) < NEARLY_BLACK_Y;
    let clipped = quantile(&y, 0.5) > 1.0;
    if !(dark || clipped) {
        return None;
    }
    let lit: Vec<f64> = y.iter().copied().filter(|&v| v > 0.0).collect();
    if lit.is_empty() {
        return None;
    }
    let log_avg = (lit.iter().map(|v| v.ln()).sum::<f64>() / lit.len() as f64).exp();
    let multiplier = (0.18 / log_avg).min(0.9 / quantile(&lit, 0.95));
    (multiplier.is_finite() && multiplier > 0.0).then_some(AutoExposure {
        multiplier,
        was_dark: dark,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(ys: &[f64]) -> XyzImage {
        XyzImage {
            width: ys.len() as u32,
            height: 1,
            xyz: ys.iter().map(|&y| [y, y, y]).collect(),
        }
    }

    // A well exposed image is left alone; a dark one (all Y ≈ 1e-4) is brought to the middle
    // grey key (0.18 / 1e-4 = 1800×, 10.8 EV, capped by 0.9 / p95 = 9000 → 1800 holds); a
    // clipped one is darkened; an all-black image gets no exposure.
    #[test]
    fn picks_an_exposure_only_when_needed() {
        assert_eq!(auto_exposure(&image(&[0.2, 0.5, 0.05, 0.8])), None);
        let dark = auto_exposure(&image(&[1e-4; 100])).unwrap();
        assert!(
            dark.was_dark && (dark.multiplier - 1800.0).abs() < 1e-6,
            "{dark:?}"
        );
        let bright = auto_exposure(&image(&[20.0, 30.0, 40.0, 50.0, 0.5])).unwrap();
        assert!(!bright.was_dark && bright.multiplier < 0.05, "{bright:?}");
        assert_eq!(auto_exposure(&image(&[0.0; 10])), None);
    }
}
