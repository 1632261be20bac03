//! Image textures: a material parameter looked up in an image at the surface's texture
//! coordinates.
//!
//! # Conventions
//! - Texture coordinates `(u, v)` come from the shape: a mesh's per-vertex uvs (OBJ `vt`, PLY
//!   `u`/`v` or `s`/`t`), else the triangle's barycentrics; a quad's `(s, t)` along its two
//!   edges from the first corner; a sphere's `u = φ/2π`, `v = θ/π` (θ from +y).
//! - `u` runs left to right over the image, `v` **bottom to top** (`v = 0` is the bottom row,
//!   as OBJ files and most modelling tools write uvs); `uv_scale` and `uv_offset` map
//!   `(u, v) → (u·su + ou, v·sv + ov)` first.
//! - Texel `(i, j)` (column i, row j from the top) has its centre at
//!   `((i + ½)/W, 1 − (j + ½)/H)`. `bilinear` blends the four nearest centres, `nearest` takes
//!   the texel containing the point.
//! - Wrap `repeat` (default) tiles the image; `clamp` extends its edge texels.
//!
//! Reflectance textures hold, per texel, the sigmoid coefficients of the texel's colour from
//! [`crate::color::rgb_table`] (12 bytes per texel) and blend the texels' *spectra*, so a
//! filtered value is a mix of valid reflectances (in [0, 1] at every wavelength). Spectral
//! textures (EXR in spectrace's spectral layout) interpolate linearly between wavelength
//! nodes and hold the end nodes' values outside them. Emission textures (per texel the
//! coefficients of `rgb / (2·max)` and the factor `2·max`) give `factor · S(λ) · W(λ)`, `W`
//! the colour space's white (CIE D65 scaled so that its luminance `∫Wȳ/∫ȳ` is 1), so that an
//! RGB value `(1, 1, 1)` is radiance of luminance 1 W/(m²·sr·nm)-weighted ȳ mean, as the
//! film reports it and as Mitsuba 3 reads RGB emitters.

use super::image_file::{RgbImage, SpectralTexels};
use crate::color::rgb_table::{eval_coeffs, t_of, RgbToSpectrumTable};
use crate::color::Observer;
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use crate::texture::SpectralTexture;
use glam::Vec2;
use std::sync::{Arc, OnceLock};

/// Reconstruction between texel centres.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// The texel containing the point.
    Nearest,
    /// The four nearest texel centres, weighted bilinearly.
    Bilinear,
}

impl Filter {
    /// `"nearest"` or `"bilinear"`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "nearest" => Ok(Self::Nearest),
            "bilinear" => Ok(Self::Bilinear),
            o => Err(format!(
                "unknown filter `{o}` (expected \"bilinear\" or \"nearest\")"
            )),
        }
    }
}

/// What happens outside [0, 1]².
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Tile the image.
    Repeat,
    /// Extend the edge texels.
    Clamp,
}

impl Wrap {
    /// `"repeat"` or `"clamp"`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "repeat" => Ok(Self::Repeat),
            "clamp" => Ok(Self::Clamp),
            o => Err(format!(
                "unknown wrap `{o}` (expected \"repeat\" or \"clamp\")"
            )),
        }
    }
}

/// Where a uv lands in an image: the texels and their weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelLookup {
    /// Image width (texels).
    pub width: u32,
    /// Image height (texels).
    pub height: u32,
    /// Filter.
    pub filter: Filter,
    /// Wrap mode.
    pub wrap: Wrap,
    /// `(su, sv)`.
    pub uv_scale: Vec2,
    /// `(ou, ov)`.
    pub uv_offset: Vec2,
}

impl TexelLookup {
    fn wrap_index(&self, i: i64, n: u32) -> usize {
        let n = n as i64;
        match self.wrap {
            Wrap::Repeat => i.rem_euclid(n) as usize,
            Wrap::Clamp => i.clamp(0, n - 1) as usize,
        }
    }

    /// Up to four `(texel index, weight)` pairs (weights sum to 1; unused taps weigh 0).
    #[inline]
    pub fn taps(&self, uv: Vec2) -> [(usize, f32); 4] {
        let s = uv.x * self.uv_scale.x + self.uv_offset.x;
        let t = uv.y * self.uv_scale.y + self.uv_offset.y;
        let (w, h) = (self.width as f32, self.height as f32);
        // Continuous texel coordinates with texel centres on integers + ½; rows from the top.
        let x = if s.is_finite() { s * w } else { 0.0 };
        let y = if t.is_finite() { (1.0 - t) * h } else { 0.0 };
        let index = |i: i64, j: i64| {
            self.wrap_index(j, self.height) * self.width as usize + self.wrap_index(i, self.width)
        };
        match self.filter {
            Filter::Nearest => {
                let i = index(x.floor() as i64, y.floor() as i64);
                [(i, 1.0), (i, 0.0), (i, 0.0), (i, 0.0)]
            }
            Filter::Bilinear => {
                let (x, y) = (x - 0.5, y - 0.5);
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (i0, j0) = (x0 as i64, y0 as i64);
                [
                    (index(i0, j0), (1.0 - fx) * (1.0 - fy)),
                    (index(i0 + 1, j0), fx * (1.0 - fy)),
                    (index(i0, j0 + 1), (1.0 - fx) * fy),
                    (index(i0 + 1, j0 + 1), fx * fy),
                ]
            }
        }
    }
}

/// A reflectance texture from an RGB image: per-texel sigmoid coefficients.
pub struct RgbReflectanceTexture {
    name: String,
    lookup: TexelLookup,
    coeffs: Vec<[f32; 3]>,
    scale: f32,
}

impl std::fmt::Debug for RgbReflectanceTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "RgbReflectanceTexture({}, {}×{})",
            self.name, self.lookup.width, self.lookup.height
        )
    }
}

impl RgbReflectanceTexture {
    /// Uplift every texel of `image` through the shared table (components clamped into
    /// [0, 1]); `scale` in [0, 1] multiplies the reflectance. Also returns how many texel
    /// components lay above 1 (clamped).
    pub fn new(
        name: impl Into<String>,
        image: &RgbImage,
        filter: Filter,
        wrap: Wrap,
        uv_scale: Vec2,
        uv_offset: Vec2,
        scale: f32,
    ) -> (Self, usize) {
        let table = RgbToSpectrumTable::srgb();
        let clamped = image.pixels.iter().flatten().filter(|&&v| v > 1.0).count();
        let coeffs = image.pixels.iter().map(|&c| table.lookup(c)).collect();
        (
            Self {
                name: name.into(),
                lookup: TexelLookup {
                    width: image.width,
                    height: image.height,
                    filter,
                    wrap,
                    uv_scale,
                    uv_offset,
                },
                coeffs,
                scale,
            },
            clamped,
        )
    }
}

impl SpectralTexture for RgbReflectanceTexture {
    fn eval(&self, lambda: &SampledWavelengths, uv: Vec2) -> SampledSpectrum {
        let taps = self.lookup.taps(uv);
        let t: [f32; LANES] = std::array::from_fn(|k| t_of(lambda.lambda[k]));
        let mut out = [0.0f32; LANES];
        for &(i, w) in &taps {
            if w == 0.0 {
                continue;
            }
            let c = self.coeffs[i];
            for k in 0..LANES {
                out[k] += w * eval_coeffs(c, t[k]);
            }
        }
        SampledSpectrum(out.map(|v| v * self.scale))
    }
}

/// A texture from a spectral EXR: values at wavelength nodes per texel.
pub struct SpectralImageTexture {
    name: String,
    lookup: TexelLookup,
    texels: SpectralTexels,
    scale: f32,
    /// Hold the end nodes' values outside the nodes (reflectances) instead of 0 (radiance).
    hold_ends: bool,
}

impl std::fmt::Debug for SpectralImageTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SpectralImageTexture({}, {}×{}, {} nodes)",
            self.name, self.lookup.width, self.lookup.height, self.texels.nodes
        )
    }
}

impl SpectralImageTexture {
    /// A texture over `texels`, × `scale`; `hold_ends` as for reflectances.
    pub fn new(
        name: impl Into<String>,
        texels: SpectralTexels,
        lookup: TexelLookup,
        scale: f32,
        hold_ends: bool,
    ) -> Self {
        Self {
            name: name.into(),
            lookup,
            texels,
            scale,
            hold_ends,
        }
    }

    /// The largest value of any texel at any node (for range checks).
    pub fn max_value(&self) -> f32 {
        self.texels.values.iter().copied().fold(0.0, f32::max) * self.scale
    }
}

impl SpectralTexture for SpectralImageTexture {
    fn eval(&self, lambda: &SampledWavelengths, uv: Vec2) -> SampledSpectrum {
        let taps = self.lookup.taps(uv);
        let tx = &self.texels;
        let last = tx.node(tx.nodes - 1);
        let l: [f32; LANES] = std::array::from_fn(|k| {
            let l = lambda.lambda[k];
            if self.hold_ends {
                l.clamp(tx.start, last)
            } else {
                l
            }
        });
        let mut out = [0.0f32; LANES];
        for &(i, w) in &taps {
            if w == 0.0 {
                continue;
            }
            for k in 0..LANES {
                out[k] += w * tx.value(i, l[k]);
            }
        }
        SampledSpectrum(out.map(|v| v * self.scale))
    }
}

/// CIE D65 scaled so that `∫W(λ)ȳ(λ)dλ / ∫ȳ(λ)dλ = 1` (CIE 1931 2°), on a 1 nm table: the
/// white of linear sRGB as emission.
pub fn srgb_white() -> &'static DenseSpectrum {
    static CELL: OnceLock<DenseSpectrum> = OnceLock::new();
    CELL.get_or_init(|| {
        let d65: Arc<dyn crate::spectrum::Spd> =
            Arc::new(crate::spectrum::parse_spd_spec("d65").expect("bundled D65"));
        let obs = crate::color::CieObserverKind::Cie1931_2.get();
        let (mut num, mut den) = (0.0, 0.0);
        for l in 360..=830 {
            let y = obs.xyz_bar(l as f64)[1];
            num += d65.value(l as f64) * y;
            den += y;
        }
        DenseSpectrum::from_spd(d65, (den / num) as f32)
    })
}

/// Per-texel emission coefficients: the sigmoid coefficients of `rgb / (2·max)` and the
/// factor `2·max` (0 for black), so that `factor · S(λ) · W(λ)` has RGB `rgb`.
pub fn emission_coeffs(table: &RgbToSpectrumTable, rgb: [f32; 3]) -> [f32; 4] {
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    if !(m > 0.0) {
        return [0.0, 0.0, 0.0, 0.0];
    }
    let f = 2.0 * m;
    let c = table.lookup(rgb.map(|v| v / f));
    [c[0], c[1], c[2], f]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lookup(w: u32, h: u32, filter: Filter, wrap: Wrap) -> TexelLookup {
        TexelLookup {
            width: w,
            height: h,
            filter,
            wrap,
            uv_scale: Vec2::ONE,
            uv_offset: Vec2::ZERO,
        }
    }

    fn value(l: &TexelLookup, img: &[f32], uv: Vec2) -> f32 {
        l.taps(uv).iter().map(|&(i, w)| w * img[i]).sum()
    }

    /// The conventions, exactly: a texel centre gives its own value (bilinear and nearest),
    /// v = 0 is the bottom row, midway between two centres is their mean, `repeat` wraps
    /// across the edge and `clamp` holds the edge value (1e-6: f32 rounding).
    #[test]
    fn filtering_and_wrapping() {
        // 4 × 2 image, row 0 (top) = 0..4, row 1 (bottom) = 10..14.
        let img = [0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0, 13.0];
        let bl = lookup(4, 2, Filter::Bilinear, Wrap::Repeat);
        let nn = lookup(4, 2, Filter::Nearest, Wrap::Repeat);
        let cl = lookup(4, 2, Filter::Bilinear, Wrap::Clamp);
        let centre = |i: f32, j: f32| Vec2::new((i + 0.5) / 4.0, 1.0 - (j + 0.5) / 2.0);
        for j in 0..2 {
            for i in 0..4 {
                let want = img[j * 4 + i];
                assert!((value(&bl, &img, centre(i as f32, j as f32)) - want).abs() < 1e-6);
                assert!((value(&nn, &img, centre(i as f32, j as f32)) - want).abs() < 1e-6);
            }
        }
        // Bottom-left corner region is row 1.
        assert_eq!(value(&nn, &img, Vec2::new(0.01, 0.01)), 10.0);
        // Between the centres of texels 1 and 2 in the top row.
        assert!((value(&bl, &img, Vec2::new(0.5, 0.75)) - 1.5).abs() < 1e-6);
        // u = 0 on the top row's centre line: repeat mixes texels 3 and 0, clamp holds 0.
        assert!((value(&bl, &img, Vec2::new(0.0, 0.75)) - 1.5).abs() < 1e-6);
        assert!((value(&cl, &img, Vec2::new(0.0, 0.75)) - 0.0).abs() < 1e-6);
        // uv outside [0,1] repeats.
        assert!((value(&bl, &img, Vec2::new(1.5, 0.75)) - 1.5).abs() < 1e-6);
    }

    /// The white of linear sRGB has luminance 1 by construction and the chromaticity of D65
    /// (x, y) = (0.3127, 0.3290) to 1e-3 (the 1 nm table against the rounded standard).
    #[test]
    fn white_is_d65_of_unit_luminance() {
        let w = srgb_white();
        let obs = crate::color::CieObserverKind::Cie1931_2.get();
        let (mut xyz, mut iy) = ([0.0f64; 3], 0.0);
        for l in 360..=830 {
            let b = obs.xyz_bar(l as f64);
            let v = w.value(l as f32) as f64;
            for k in 0..3 {
                xyz[k] += v * b[k];
            }
            iy += b[1];
        }
        assert!((xyz[1] / iy - 1.0).abs() < 1e-4, "{}", xyz[1] / iy);
        let s = xyz[0] + xyz[1] + xyz[2];
        assert!((xyz[0] / s - 0.3127).abs() < 1e-3 && (xyz[1] / s - 0.3290).abs() < 1e-3);
    }
}
