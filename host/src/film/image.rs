//! A finished (or partial) image: mean XYZ per pixel, row-major from the top-left pixel.

use crate::color::RgbColorSpace;

/// Per-pixel CIE XYZ (film convention, see the module docs of [`crate::film`]).
#[derive(Clone, Debug, PartialEq)]
pub struct XyzImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width·height` XYZ triples, row-major, top row first.
    pub xyz: Vec<[f64; 3]>,
}

impl XyzImage {
    /// Linear RGB in `space` for every pixel (no white adaptation: XYZ are absolute, as Mitsuba's
    /// film converts them).
    pub fn to_rgb(&self, space: &RgbColorSpace) -> Vec<[f64; 3]> {
        // The matrix once, not per pixel (it is an inverse of a product of inverses).
        let m = space.xyz_to_rgb_matrix();
        self.xyz
            .iter()
            .map(|&v| crate::color::matrix3::mul_vec(&m, v))
            .collect()
    }

    /// Mean XYZ over the image.
    pub fn mean_xyz(&self) -> [f64; 3] {
        let n = self.xyz.len().max(1) as f64;
        let mut m = [0.0; 3];
        for p in &self.xyz {
            for c in 0..3 {
                m[c] += p[c];
            }
        }
        m.map(|v| v / n)
    }

    /// Number of pixels with a NaN or infinite component.
    pub fn non_finite_count(&self) -> usize {
        self.xyz
            .iter()
            .filter(|p| p.iter().any(|v| !v.is_finite()))
            .count()
    }
}
