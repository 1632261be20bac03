//! The per-pixel largest single-sample luminance, for firefly checks of the splatting drivers.

use std::sync::atomic::{AtomicU64, Ordering};

/// Largest single-sample luminance Y (before the 1/spp scaling) that reached each pixel, kept
/// with atomics so splats from any thread can record it (non-negative f64 bit patterns order
/// like the values, so an integer `fetch_max` is exact).
#[derive(Debug)]
pub struct PixelMaxY {
    width: u32,
    height: u32,
    bits: Vec<AtomicU64>,
}

impl PixelMaxY {
    /// All zero.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            bits: (0..width as usize * height as usize)
                .map(|_| AtomicU64::new(0))
                .collect(),
        }
    }

    /// Record `|y|` at raster position (`px`, `py`) (ignored off the film or if not finite).
    #[inline]
    pub fn record(&self, px: f32, py: f32, y: f64) {
        if !(px >= 0.0 && py >= 0.0 && y.is_finite()) {
            return;
        }
        let (x, yy) = (px as u32, py as u32);
        if x < self.width && yy < self.height {
            self.bits[yy as usize * self.width as usize + x as usize]
                .fetch_max(y.abs().to_bits(), Ordering::Relaxed);
        }
    }

    /// The maxima, row-major.
    pub fn values(&self) -> Vec<f64> {
        self.bits
            .iter()
            .map(|b| f64::from_bits(b.load(Ordering::Relaxed)))
            .collect()
    }
}
