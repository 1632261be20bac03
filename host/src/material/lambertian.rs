//! Lambertian (ideal diffuse) reflection, two-sided: light arriving on either side is scattered
//! back into that side's hemisphere with f = R(λ)/π.

use super::{
    same_hemisphere, sample_cosine_lobe, BsdfSample, Material, MaterialFlags, ShadingContext,
    TransportMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::SpectralTexture;
use glam::{Vec2, Vec3A};
use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

/// Diffuse reflector with spectral reflectance `R(λ) ∈ [0, 1]`.
#[derive(Debug, Clone)]
pub struct Lambertian {
    reflectance: Arc<dyn SpectralTexture>,
    /// `reflectance.grey()`, asked once: a grey constant is used without a call per bounce.
    grey: Option<f32>,
}

impl Lambertian {
    /// A Lambertian surface; `reflectance` should stay within [0, 1] to conserve energy.
    pub fn new(reflectance: Arc<dyn SpectralTexture>) -> Self {
        let grey = reflectance.grey();
        Self { reflectance, grey }
    }

    /// `R/π` at `lambda` and `uv`.
    #[inline]
    fn f(&self, lambda: &SampledWavelengths, uv: Vec2) -> SampledSpectrum {
        match self.grey {
            Some(g) => SampledSpectrum::splat(g) * FRAC_1_PI,
            None => self.reflectance.eval(lambda, uv) * FRAC_1_PI,
        }
    }
}

impl Material for Lambertian {
    fn flags(&self) -> MaterialFlags {
        MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION
    }

    /// `eval` is `R/π` on `wo`'s side and 0 on the other; `sample` returns the same `R/π`.
    fn f_same_for_all_directions(&self) -> bool {
        true
    }

    /// One lobe: `sample_into` reads only `u`.
    fn ignores_lobe_sample(&self) -> bool {
        true
    }

    /// `sample` draws the cosine-weighted hemisphere and `pdf` is `|cos θi|/π` on `wo`'s side.
    fn cosine_weighted_pdf(&self) -> bool {
        true
    }

    fn spectrally_flat(&self) -> bool {
        self.grey.is_some()
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _u_lobe: f32,
        u: Vec2,
        _mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        let (wi, pdf) = sample_cosine_lobe(wo, u)?;
        Some(out.write(BsdfSample {
            wi,
            f: self.f(lambda, ctx.uv),
            pdf,
            flags: self.flags(),
            eta: 1.0,
        }))
    }

    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::zero();
        }
        self.f(lambda, ctx.uv)
    }

    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        if same_hemisphere(wo, wi) {
            wi.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
}
