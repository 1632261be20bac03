//! Emission textures: the radiance of an emissive surface read from an image at the surface's
//! texture coordinates (the conventions of [`super::image_texture`]: `v` bottom to top,
//! `uv_scale`/`uv_offset`, `bilinear`/`nearest`, `repeat`/`clamp`).
//!
//! - RGB images (linear after decoding) are radiance by the illuminant method: per texel the
//!   sigmoid coefficients of `rgb / (2·max)` and the factor `2·max`
//!   ([`super::image_texture::emission_coeffs`]), giving `factor · S(λ) · W(λ)` with `W` the
//!   sRGB white (D65 of luminance 1): `(1, 1, 1)` is radiance whose ȳ-weighted mean is
//!   1 W/(m²·sr·nm) (film Y = 1, 683.002 · ∫ȳ ≈ 72 990 cd/m²), as the film reports it and as
//!   Mitsuba 3 reads RGB emitters. The bilinear filter blends the texels' *spectra*.
//! - Spectral EXR images (spectrace's layout) are spectral radiance in W/(m²·sr·nm) at their
//!   nodes, linear between nodes and 0 outside them.
//!
//! Everything is multiplied by `scale`. For light sampling each texel has a luminance
//! ([`EmissionTexture::luminance_at`], film units) and the texture a mean spectrum
//! ([`EmissionTexture::mean_spectrum`]), which steer where and at which wavelengths light paths
//! start.

use super::image_file::{LoadedImage, SpectralTexels};
use super::image_texture::{emission_coeffs, srgb_white, TexelLookup};
use crate::color::rgb_table::{eval_coeffs, t_of, RgbToSpectrumTable};
use crate::color::Observer;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::Vec2;

/// Per-texel radiance data.
enum Texels {
    /// `[c₀, c₁, c₂, factor]` per texel (illuminant method).
    Rgb(Vec<[f32; 4]>),
    /// Spectral radiance at wavelength nodes.
    Spectral(SpectralTexels),
}

/// An emission texture (see the module docs).
pub struct EmissionTexture {
    name: String,
    lookup: TexelLookup,
    texels: Texels,
    /// Film luminance (∫Lȳ/∫ȳ) per texel, at scale 1.
    luminance: Vec<f32>,
    scale: f32,
}

impl std::fmt::Debug for EmissionTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "EmissionTexture({}, {}×{}, scale {})",
            self.name, self.lookup.width, self.lookup.height, self.scale
        )
    }
}

/// Luminance of linear sRGB (ITU-R BT.709 primaries, D65 white): the Y row of the RGB→XYZ
/// matrix.
fn srgb_luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl EmissionTexture {
    /// The texture of `image` looked up through `lookup` (its size must be the image's), ×
    /// `scale` (finite, ≥ 0).
    pub fn new(
        name: impl Into<String>,
        image: LoadedImage,
        lookup: TexelLookup,
        scale: f32,
    ) -> Result<Self, String> {
        let name = name.into();
        if (lookup.width, lookup.height) != image.size() {
            return Err(format!("{name}: lookup and image sizes differ"));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(format!(
                "{name}: the scale must be finite and ≥ 0, got {scale}"
            ));
        }
        let (texels, luminance) = match image {
            LoadedImage::Rgb(img) => {
                let table = RgbToSpectrumTable::srgb();
                let lum = img.pixels.iter().map(|&c| srgb_luminance(c)).collect();
                let coeffs = img
                    .pixels
                    .iter()
                    .map(|&c| emission_coeffs(table, c))
                    .collect();
                (Texels::Rgb(coeffs), lum)
            }
            LoadedImage::Spectral(s) => {
                let obs = crate::color::CieObserverKind::Cie1931_2.get();
                let ybar: Vec<(f32, f64)> = (360..=830)
                    .step_by(5)
                    .map(|l| (l as f32, obs.xyz_bar(l as f64)[1]))
                    .collect();
                let norm: f64 = ybar.iter().map(|(_, y)| y).sum();
                let n = (s.width as usize) * (s.height as usize);
                let lum = (0..n)
                    .map(|i| {
                        (ybar
                            .iter()
                            .map(|&(l, y)| s.value(i, l) as f64 * y)
                            .sum::<f64>()
                            / norm) as f32
                    })
                    .collect();
                (Texels::Spectral(s), lum)
            }
        };
        Ok(Self {
            name,
            lookup,
            texels,
            luminance,
            scale,
        })
    }

    /// The file it came from (for messages).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// `scale`.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Spectral radiance W/(m²·sr·nm) per lane at texture coordinates `uv`.
    pub fn eval(&self, uv: Vec2, lambda: &SampledWavelengths) -> SampledSpectrum {
        let taps = self.lookup.taps(uv);
        let mut out = [0.0f32; LANES];
        match &self.texels {
            Texels::Rgb(c) => {
                let t: [f32; LANES] = std::array::from_fn(|k| t_of(lambda.lambda[k]));
                for &(i, w) in &taps {
                    if w == 0.0 || c[i][3] == 0.0 {
                        continue;
                    }
                    let ci = c[i];
                    for k in 0..LANES {
                        out[k] += w * ci[3] * eval_coeffs([ci[0], ci[1], ci[2]], t[k]);
                    }
                }
                let white = srgb_white().eval(lambda);
                for (o, wl) in out.iter_mut().zip(white.0) {
                    *o *= wl;
                }
            }
            Texels::Spectral(s) => {
                for &(i, w) in &taps {
                    if w == 0.0 {
                        continue;
                    }
                    for (o, &l) in out.iter_mut().zip(&lambda.lambda) {
                        *o += w * s.value(i, l);
                    }
                }
            }
        }
        SampledSpectrum(out.map(|v| v * self.scale))
    }

    /// Film luminance (∫Lȳ/∫ȳ, × `scale`) at `uv`, reconstructed by the texture's own filter
    /// from the texels' luminances (exact for the filter: luminance is linear in the spectra
    /// the filter blends).
    pub fn luminance_at(&self, uv: Vec2) -> f32 {
        self.lookup
            .taps(uv)
            .iter()
            .map(|&(i, w)| w * self.luminance[i])
            .sum::<f32>()
            * self.scale
    }

    /// The texels' mean spectral radiance (× `scale`) as `(nm, W/(m²·sr·nm))` on a 5 nm grid
    /// over 360–830 nm (RGB) or at the nodes (spectral). RGB textures average at most ~4096
    /// texels spread evenly over the image: the mean steers the light-path wavelengths and
    /// the light's share of light selection, not the radiance itself.
    pub fn mean_spectrum(&self) -> Vec<(f64, f64)> {
        match &self.texels {
            Texels::Rgb(c) => {
                let stride = c.len().div_ceil(4096).max(1);
                let picked: Vec<&[f32; 4]> = c.iter().step_by(stride).collect();
                let n = picked.len().max(1) as f64;
                let white = srgb_white();
                (360..=830)
                    .step_by(5)
                    .map(|l| {
                        let lf = l as f32;
                        let t = t_of(lf);
                        let sum: f64 = picked
                            .iter()
                            .filter(|ci| ci[3] > 0.0)
                            .map(|ci| (ci[3] * eval_coeffs([ci[0], ci[1], ci[2]], t)) as f64)
                            .sum();
                        (
                            l as f64,
                            sum / n * white.value(lf) as f64 * self.scale as f64,
                        )
                    })
                    .collect()
            }
            Texels::Spectral(s) => {
                let n = (s.width as usize) * (s.height as usize);
                (0..s.nodes)
                    .map(|k| {
                        let sum: f64 = (0..n).map(|i| s.values[i * s.nodes + k] as f64).sum();
                        (s.node(k) as f64, sum / n as f64 * self.scale as f64)
                    })
                    .collect()
            }
        }
    }

    /// How many texels one unit of texture coordinates spans, `(⌈W·|su|⌉, ⌈H·|sv|⌉)` (at least
    /// 1; for the light's power grid).
    pub fn texels_shown(&self) -> (u32, u32) {
        let l = &self.lookup;
        let f = |n: u32, s: f32| ((n as f32 * s.abs()).ceil().clamp(1.0, 1e6)) as u32;
        (f(l.width, l.uv_scale.x), f(l.height, l.uv_scale.y))
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.luminance.len() * 4
            + match &self.texels {
                Texels::Rgb(c) => c.len() * 16,
                Texels::Spectral(s) => s.values.len() * 4,
            }
    }
}
