//! The camera film: per-pixel XYZ sums in f64. Rendering threads fill private [`TileBuffer`]s
//! that are merged in a fixed order, so the result is bitwise independent of thread count.

use super::XyzImage;

/// Running sums for one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelSum {
    /// Σ XYZ estimates.
    pub xyz: [f64; 3],
    /// Number of samples (each has weight 1 under filter importance sampling).
    pub count: f64,
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
        }
    }

    /// Add one sample's XYZ to image pixel `(x, y)` (which must lie in the tile).
    #[inline]
    pub fn add(&mut self, x: u32, y: u32, xyz: [f64; 3]) {
        let i = ((y - self.y0) * self.w + (x - self.x0)) as usize;
        let p = &mut self.pixels[i];
        p.xyz[0] += xyz[0];
        p.xyz[1] += xyz[1];
        p.xyz[2] += xyz[2];
        p.count += 1.0;
    }
}

/// The whole film.
#[derive(Clone, Debug, PartialEq)]
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

    /// Add a finished tile's sums.
    pub fn merge(&mut self, tile: &TileBuffer) {
        for ty in 0..tile.h {
            for tx in 0..tile.w {
                let src = tile.pixels[(ty * tile.w + tx) as usize];
                let dst = &mut self.pixels
                    [((tile.y0 + ty) as usize) * self.width as usize + (tile.x0 + tx) as usize];
                for c in 0..3 {
                    dst.xyz[c] += src.xyz[c];
                }
                dst.count += src.count;
            }
        }
    }

    /// Mean XYZ per pixel (pixels without samples are black).
    pub fn image(&self) -> XyzImage {
        XyzImage {
            width: self.width,
            height: self.height,
            xyz: self
                .pixels
                .iter()
                .map(|p| {
                    if p.count > 0.0 {
                        p.xyz.map(|v| v / p.count)
                    } else {
                        [0.0; 3]
                    }
                })
                .collect(),
        }
    }

    /// Total number of samples taken.
    pub fn sample_count(&self) -> f64 {
        self.pixels.iter().map(|p| p.count).sum()
    }
}
