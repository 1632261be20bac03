//! The camera film: per-pixel exact XYZ sums ([`ExactSum`]) and sample counts. Rendering
//! threads fill private [`TileBuffer`]s that are merged afterwards; since the sums are exact,
//! the result is the same bits for any thread count, pass split, slice split or resumption.
//! Samples refused by the guard ([`check_sample`]) are counted (they keep their place in the
//! pixel's sample count, contributing zero) and never enter the sums.

use super::exact_sum::ExactSum;
use super::rejected::{check_sample, Rejection};
use serde::{Deserialize, Serialize};

/// Running sums for one pixel.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PixelSum {
    /// Σ XYZ estimates, exact.
    pub xyz: [ExactSum; 3],
    /// Number of samples (each has weight 1 under filter importance sampling).
    pub count: u64,
}

impl PixelSum {
    /// The mean XYZ (black without samples).
    pub fn mean(&self) -> [f64; 3] {
        if self.count == 0 {
            return [0.0; 3];
        }
        let n = self.count as f64;
        [0, 1, 2].map(|c| self.xyz[c].value() / n)
    }

    /// Add another pixel's sums.
    pub fn merge(&mut self, other: &PixelSum) {
        for c in 0..3 {
            self.xyz[c].merge(&other.xyz[c]);
        }
        self.count += other.count;
    }
}

/// A rectangle of pixel sums owned by one thread while it renders that tile.
#[derive(Clone, Debug, PartialEq)]
pub struct TileBuffer {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Width.
    pub w: u32,
    /// Height.
    pub h: u32,
    /// Row-major sums.
    pub pixels: Vec<PixelSum>,
    /// Samples refused by the guard, in the order met.
    pub rejected: Vec<Rejection>,
}

impl TileBuffer {
    /// An empty tile.
    pub fn new(x0: u32, y0: u32, w: u32, h: u32) -> Self {
        Self {
            x0,
            y0,
            w,
            h,
            pixels: vec![PixelSum::default(); (w * h) as usize],
            rejected: Vec::new(),
        }
    }

    /// Add one sample's XYZ to image pixel `(x, y)` (which must lie in the tile); `strategy`
    /// names what produced it, for the report if the guard refuses it.
    #[inline]
    pub fn add(&mut self, x: u32, y: u32, xyz: [f64; 3], strategy: &str) {
        let i = ((y - self.y0) * self.w + (x - self.x0)) as usize;
        let p = &mut self.pixels[i];
        p.count += 1;
        match check_sample(&xyz) {
            None => {
                for (s, v) in p.xyz.iter_mut().zip(xyz) {
                    s.add(v);
                }
            }
            Some(kind) => self.rejected.push(Rejection {
                x,
                y,
                strategy: strategy.to_string(),
                kind,
            }),
        }
    }

    /// Record a refused contribution of pixel `(x, y)` that is not a whole sample (one strategy
    /// of a BDPT sample): counted, not added.
    pub fn reject(&mut self, rejection: Rejection) {
        self.rejected.push(rejection);
    }
}

/// The whole camera film.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PixelFilm {
    width: u32,
    height: u32,
    pixels: Vec<PixelSum>,
}

impl PixelFilm {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![PixelSum::default(); (width as usize) * (height as usize)],
        }
    }

    /// (width, height).
    pub fn resolution(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The pixel sums, row-major.
    pub fn pixels(&self) -> &[PixelSum] {
        &self.pixels
    }

    /// Add a finished tile's sums (its rejections are the caller's to keep).
    pub fn merge(&mut self, tile: &TileBuffer) {
        for ty in 0..tile.h {
            for tx in 0..tile.w {
                let src = &tile.pixels[(ty * tile.w + tx) as usize];
                let dst = &mut self.pixels
                    [((tile.y0 + ty) as usize) * self.width as usize + (tile.x0 + tx) as usize];
                dst.merge(src);
            }
        }
    }

    /// Add another film of the same size.
    pub fn merge_film(&mut self, other: &PixelFilm) {
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            a.merge(b);
        }
    }

    /// Mean XYZ per pixel (pixels without samples are black).
    pub fn image(&self) -> super::XyzImage {
        super::XyzImage {
            width: self.width,
            height: self.height,
            xyz: self.pixels.iter().map(PixelSum::mean).collect(),
        }
    }

    /// Total number of samples taken.
    pub fn sample_count(&self) -> u64 {
        self.pixels.iter().map(|p| p.count).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::FilmState;

    /// The guard: a NaN, an infinite and a negative sample each keep their place in the pixel's
    /// sample count (they contribute zero) but never reach the sums; each is recorded with its
    /// pixel and strategy, and the film's report and diagnostic layer show them. The mean is
    /// exactly (1 + 2) / 5.
    #[test]
    fn refused_samples_are_counted_not_added() {
        let mut tile = TileBuffer::new(2, 1, 2, 2);
        tile.add(3, 2, [1.0, 1.0, 1.0], "pt camera path");
        tile.add(3, 2, [f64::NAN, 0.0, 0.0], "pt camera path");
        tile.add(3, 2, [f64::INFINITY, 0.0, 0.0], "pt camera path");
        tile.add(3, 2, [0.0, -1e-9, 0.0], "bdpt camera film (t ≥ 2)");
        tile.add(3, 2, [2.0, 2.0, 2.0], "pt camera path");
        let mut film = FilmState::new(4, 3, false);
        film.camera.merge(&tile);
        film.record_rejected(&tile.rejected);
        assert_eq!(film.image().xyz[2 * 4 + 3], [0.6; 3]);
        assert_eq!(film.camera.sample_count(), 5);
        assert_eq!(film.rejected.total(), 3);
        assert_eq!(film.rejected.negative, 1);
        assert_eq!(film.rejected.layer(12)[11], 3.0);
        let report = film.rejected.summary().join("\n");
        assert!(
            report.contains("pt camera path: 2") && report.contains("(3, 2): 3"),
            "{report}"
        );
    }
}
