//! Spectral textures: what a material asks when it needs a wavelength-dependent parameter
//! (reflectance, emission) at a surface point. Implementations adapt tabulated curves, RGB
//! uplifts or plugin spectra; materials never know which.

use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec2;
use std::fmt::Debug;
use std::sync::Arc;

/// A wavelength-dependent quantity that may vary over the surface (`uv`). Unitless for
/// reflectances; W/(m²·sr·nm) for emission.
pub trait SpectralTexture: Send + Sync + Debug {
    /// Value at each lane's wavelength.
    fn eval(&self, lambda: &SampledWavelengths, uv: Vec2) -> SampledSpectrum;

    /// `Some(v)` when the value is `v` at every wavelength and everywhere (a grey constant);
    /// `None` otherwise or when unknown.
    fn grey(&self) -> Option<f32> {
        None
    }
}

/// The same value at every wavelength and everywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantTexture(pub f32);

impl SpectralTexture for ConstantTexture {
    fn eval(&self, _lambda: &SampledWavelengths, _uv: Vec2) -> SampledSpectrum {
        SampledSpectrum::splat(self.0)
    }

    fn grey(&self) -> Option<f32> {
        Some(self.0)
    }
}

/// A spatially uniform spectrum given by any function of wavelength (nm), scaled; evaluated
/// from a 1 nm resampling ([`DenseSpectrum`]).
///
/// Built from the spectrum module's curves, SPDs and uplifted RGB colours by the scene factory.
pub struct CurveTexture {
    name: String,
    scale: f32,
    dense: DenseSpectrum,
}

impl CurveTexture {
    /// `scale · curve(λ)`; `name` is only for diagnostics.
    pub fn new(
        name: impl Into<String>,
        scale: f32,
        curve: Arc<dyn Fn(f32) -> f32 + Send + Sync>,
    ) -> Self {
        Self {
            name: name.into(),
            scale,
            dense: DenseSpectrum::new(Arc::new(move |l| scale * curve(l))),
        }
    }

    /// A piecewise-linear table of `(λ nm, value)` pairs, sorted by λ, zero outside its range
    /// (as the measured Cornell data is defined).
    pub fn piecewise_linear(name: impl Into<String>, scale: f32, table: Vec<(f32, f32)>) -> Self {
        let curve = move |l: f32| piecewise_linear_eval(&table, l);
        Self::new(name, scale, Arc::new(curve))
    }

    /// The value at one wavelength (nm).
    #[inline]
    pub fn value(&self, lambda_nm: f32) -> f32 {
        self.dense.value(lambda_nm)
    }
}

impl Debug for CurveTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CurveTexture")
            .field("name", &self.name)
            .field("scale", &self.scale)
            .finish()
    }
}

impl SpectralTexture for CurveTexture {
    fn eval(&self, lambda: &SampledWavelengths, _uv: Vec2) -> SampledSpectrum {
        self.dense.eval(lambda)
    }
}

/// Linear interpolation in a sorted `(x, y)` table; 0 outside `[x_first, x_last]`.
pub fn piecewise_linear_eval(table: &[(f32, f32)], x: f32) -> f32 {
    let (Some(first), Some(last)) = (table.first(), table.last()) else {
        return 0.0;
    };
    if !(x >= first.0 && x <= last.0) {
        return 0.0;
    }
    let i = table.partition_point(|p| p.0 <= x);
    if i == 0 {
        return first.1;
    }
    if i >= table.len() {
        return last.1;
    }
    let (x0, y0) = table[i - 1];
    let (x1, y1) = table[i];
    if x1 <= x0 {
        return y1;
    }
    let t = (x - x0) / (x1 - x0);
    y0 + t * (y1 - y0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Interpolation is exact at nodes and linear between (1e-6: f32 rounding), zero outside.
    #[test]
    fn piecewise_linear_interpolates_and_is_zero_outside() {
        let t = vec![(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)];
        assert_eq!(piecewise_linear_eval(&t, 399.9), 0.0);
        assert_eq!(piecewise_linear_eval(&t, 700.1), 0.0);
        assert!((piecewise_linear_eval(&t, 500.0) - 8.0).abs() < 1e-6);
        assert!((piecewise_linear_eval(&t, 700.0) - 18.4).abs() < 1e-6);
        assert!((piecewise_linear_eval(&t, 550.0) - 11.8).abs() < 1e-5);
    }
}
