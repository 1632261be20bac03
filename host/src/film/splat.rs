//! A thread-safe splat film for light tracing and BDPT's t = 1 strategies: any thread adds XYZ
//! at any raster position.
//!
//! Sums are exact ([`ExactSum`]) behind one lock per pixel: exact addition is associative, so
//! the total is the same bits whatever order threads arrive in, and it cannot saturate or wrap
//! however bright the scene (the fixed-point sums this replaces wrapped above ~2·10⁹ per pixel).
//! Locks are per pixel, so two threads only wait for each other when they hit the same pixel at
//! the same moment. Refused samples (NaN, ±∞, negative: [`check_sample`]) are counted, never
//! added.

use super::exact_sum::ExactSum;
use super::rejected::{check_sample, Rejection};
use super::XyzImage;
use std::sync::Mutex;

/// Accumulates splatted XYZ; read it with [`SplatFilm::image`] scaled by 1/(samples per pixel),
/// or take the exact sums with [`SplatFilm::into_sums`].
#[derive(Debug)]
pub struct SplatFilm {
    width: u32,
    height: u32,
    sums: Vec<Mutex<[ExactSum; 3]>>,
    rejected: Mutex<Vec<Rejection>>,
}

impl SplatFilm {
    /// A black splat film.
    pub fn new(width: u32, height: u32) -> Self {
        let n = (width as usize) * (height as usize);
        Self {
            width,
            height,
            sums: (0..n).map(|_| Mutex::new(Default::default())).collect(),
            rejected: Mutex::new(Vec::new()),
        }
    }

    /// (width, height).
    pub fn resolution(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Add `xyz` at continuous raster position (`px`, `py`) in pixels; positions off the film
    /// are ignored, refused samples are counted under the strategy name `splat`.
    pub fn splat(&self, px: f32, py: f32, xyz: [f64; 3]) {
        self.splat_as(px, py, xyz, "splat");
    }

    /// [`splat`](Self::splat), naming the `strategy` that made the sample for the report.
    pub fn splat_as(&self, px: f32, py: f32, xyz: [f64; 3], strategy: &str) {
        if !(px >= 0.0 && py >= 0.0) {
            return;
        }
        let (x, y) = (px as u32, py as u32);
        if x >= self.width || y >= self.height {
            return;
        }
        if let Some(kind) = check_sample(&xyz) {
            self.rejected
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(Rejection {
                    x,
                    y,
                    strategy: strategy.to_string(),
                    kind,
                });
            return;
        }
        let mut cell = self.sums[(y as usize) * self.width as usize + x as usize]
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        for (s, v) in cell.iter_mut().zip(xyz) {
            s.add(v);
        }
    }

    /// Record a refused contribution at pixel `(x, y)` that never reached [`splat_as`](Self::splat_as).
    pub fn reject(&self, rejection: Rejection) {
        self.rejected
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(rejection);
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
                    let c = c.lock().unwrap_or_else(|e| e.into_inner());
                    [0, 1, 2].map(|i| c[i].value() * scale)
                })
                .collect(),
        }
    }

    /// The exact sums (row-major) and the refused samples.
    pub fn into_sums(self) -> (Vec<[ExactSum; 3]>, Vec<Rejection>) {
        (
            self.sums
                .into_iter()
                .map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
                .collect(),
            self.rejected
                .into_inner()
                .unwrap_or_else(|e| e.into_inner()),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splats from many threads in any order give the identical sum (exact sums are
    /// associative); the value equals the exactly known total rounded once (tolerance 1 ulp of
    /// the result, from the final rounding). Sums far beyond the old fixed-point range (1e30
    /// per splat) are kept; NaN and negative splats are refused and counted.
    #[test]
    fn concurrent_splats_are_deterministic() {
        let film = SplatFilm::new(2, 1);
        std::thread::scope(|s| {
            for t in 0..4 {
                let film = &film;
                s.spawn(move || {
                    for i in 0..2000 {
                        film.splat(0.5, 0.5, [0.1 * (t + 1) as f64, 1e-3 * i as f64, 1e30]);
                    }
                });
            }
        });
        let img = film.image(1.0);
        let ulp = |v: f64| v * f64::EPSILON;
        let x = 2000.0 * (0.1 + 0.2 + 0.3 + 0.4);
        assert!((img.xyz[0][0] - x).abs() <= ulp(x), "{}", img.xyz[0][0]);
        let y = 4.0 * 1e-3 * 1999.0 * 2000.0 / 2.0;
        assert!((img.xyz[0][1] - y).abs() <= 4.0 * ulp(y));
        assert!((img.xyz[0][2] - 8000.0 * 1e30).abs() <= ulp(8e33));
        assert_eq!(img.xyz[1], [0.0; 3]);
        film.splat(-1.0, 0.0, [1.0; 3]);
        film.splat(0.0, 0.0, [f64::NAN; 3]);
        film.splat(1.0, 0.0, [-1.0, 0.0, 0.0]);
        let (sums, rejected) = film.into_sums();
        assert_eq!(rejected.len(), 2);
        assert!(sums[1].iter().all(ExactSum::is_zero));
    }
}
