//! An ideal specular mirror with a spectral reflectance (a delta BSDF: sampled, never evaluated).

use super::{BsdfSample, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::SpectralTexture;
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// Perfect mirror reflecting `R(λ)` of the incident light about the shading normal.
#[derive(Debug, Clone)]
pub struct Mirror {
    reflectance: Arc<dyn SpectralTexture>,
}

impl Mirror {
    /// A mirror with reflectance `R(λ) ∈ [0, 1]`.
    pub fn new(reflectance: Arc<dyn SpectralTexture>) -> Self {
        Self { reflectance }
    }
}

impl Material for Mirror {
    fn flags(&self) -> MaterialFlags {
        MaterialFlags::SPECULAR | MaterialFlags::REFLECTION
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _u_lobe: f32,
        _u: Vec2,
        _mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
        Some(out.write(BsdfSample {
            wi,
            f: self.reflectance.eval(lambda, ctx.uv) / wi.z.abs(),
            pdf: 1.0,
            flags: self.flags(),
            eta: 1.0,
        }))
    }

    fn eval(
        &self,
        _wo: Vec3A,
        _wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn pdf(
        &self,
        _wo: Vec3A,
        _wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        0.0
    }
}
