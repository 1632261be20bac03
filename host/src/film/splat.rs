//! A thread-safe splat film for light tracing and BDPT's t = 1 strategy: any thread adds XYZ at
//! any raster position.
//!
//! Sums are kept in 64-bit fixed point in atomics: integer addition is associative, so the total
//! is bitwise identical whatever order threads arrive in — determinism for a seed regardless of
//! thread count. The default quantum is 2⁻³² (XYZ units), giving a range of ±2³¹ ≈ 2·10⁹ per
//! pixel; scenes much brighter or dimmer than Y ≈ 1 should pick a quantum with
//! [`SplatFilm::with_quantum`] (e.g. 2⁻³² × the expected pixel value). Single contributions are
//! clamped to 2⁻¹¹ of the range (≈ 10⁶ by default) so a firefly cannot wrap a sum.

use super::XyzImage;
use std::sync::atomic::{AtomicI64, Ordering};

/// Default fixed-point quantum: 2⁻³² XYZ units.
pub const DEFAULT_QUANTUM: f64 = 1.0 / 4_294_967_296.0;

/// Accumulates splatted XYZ; read it with [`SplatFilm::image`] scaled by 1/(samples per pixel).
#[derive(Debug)]
pub struct SplatFilm {
    width: u32,
    height: u32,
    /// 1/quantum.
    scale: f64,
    /// Largest magnitude of one contribution.
    max_contribution: f64,
    sums: Vec<[AtomicI64; 3]>,
}

impl SplatFilm {
    /// A black splat film with the default quantum (2⁻³²).
    pub fn new(width: u32, height: u32) -> Self {
        Self::with_quantum(width, height, DEFAULT_QUANTUM)
    }

    /// A black splat film whose sums resolve `quantum` XYZ units (range ±2⁶³·quantum per pixel).
    /// A non-positive or non-finite quantum falls back to the default.
    pub fn with_quantum(width: u32, height: u32, quantum: f64) -> Self {
        let q = if quantum.is_finite() && quantum > 0.0 {
            quantum
        } else {
            DEFAULT_QUANTUM
        };
        let n = (width as usize) * (height as usize);
        Self {
            width,
            height,
            scale: 1.0 / q,
            max_contribution: q * 2f64.powi(52),
            sums: (0..n)
                .map(|_| [AtomicI64::new(0), AtomicI64::new(0), AtomicI64::new(0)])
                .collect(),
        }
    }

    /// Add `xyz` at continuous raster position (`px`, `py`) in pixels; positions off the film
    /// and non-finite values are ignored.
    pub fn splat(&self, px: f32, py: f32, xyz: [f64; 3]) {
        if !(px >= 0.0 && py >= 0.0) {
            return;
        }
        let (x, y) = (px as u32, py as u32);
        if x >= self.width || y >= self.height || xyz.iter().any(|v| !v.is_finite()) {
            return;
        }
        let cell = &self.sums[(y as usize) * self.width as usize + x as usize];
        for c in 0..3 {
            let v = (xyz[c].clamp(-self.max_contribution, self.max_contribution) * self.scale)
                .round() as i64;
            cell[c].fetch_add(v, Ordering::Relaxed);
        }
    }

    /// The splatted sums times `scale` (pbrt's convention: 1/spp, with spp light paths traced
    /// per pixel on average).
    pub fn image(&self, scale: f64) -> XyzImage {
        XyzImage {
            width: self.width,
            height: self.height,
            xyz: self
                .sums
                .iter()
                .map(|c| {
                    std::array::from_fn(|i| {
                        c[i].load(Ordering::Relaxed) as f64 / self.scale * scale
                    })
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splats from many threads in any order give the identical sum (fixed point is associative);
    /// the value is reproduced to the 2⁻³² quantum per contribution (1e-6 total over 8·10³ adds).
    #[test]
    fn concurrent_splats_are_deterministic() {
        let film = SplatFilm::new(2, 1);
        std::thread::scope(|s| {
            for t in 0..4 {
                let film = &film;
                s.spawn(move || {
                    for i in 0..2000 {
                        film.splat(0.5, 0.5, [0.1 * (t + 1) as f64, 1e-3 * i as f64, 0.0]);
                    }
                });
            }
        });
        let img = film.image(1.0);
        assert!((img.xyz[0][0] - 2000.0 * (0.1 + 0.2 + 0.3 + 0.4)).abs() < 1e-6);
        assert!((img.xyz[0][1] - 4.0 * 1e-3 * 1999.0 * 2000.0 / 2.0).abs() < 1e-6);
        assert_eq!(img.xyz[1], [0.0; 3]);
        // A coarser quantum still sums exactly in its units.
        let coarse = SplatFilm::with_quantum(1, 1, 1e-3);
        coarse.splat(0.0, 0.0, [1e9, 0.5, 0.0]);
        assert_eq!(coarse.image(1.0).xyz[0][..2], [1e9, 0.5]);
        film.splat(-1.0, 0.0, [1.0; 3]);
        film.splat(0.0, 0.0, [f64::NAN; 3]);
        assert!(film
            .image(1.0)
            .xyz
            .iter()
            .all(|p| p.iter().all(|v| v.is_finite())));
    }
}
