//! The surface of an area light: emits `scale · S(λ)` radiance (W/(m²·sr·nm)) from its front
//! side (along the geometric normal) and reflects nothing, as the measured Cornell box light is
//! modelled by the anchor renderers.

use super::{BsdfSample, Material, MaterialFlags, ShadingContext, SpectralTexture, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// A black, one- or two-sided emitter.
#[derive(Debug, Clone)]
pub struct Emissive {
    radiance: Arc<dyn SpectralTexture>,
    two_sided: bool,
}

impl Emissive {
    /// An emitter of spectral radiance `radiance(λ)` in W/(m²·sr·nm).
    pub fn new(radiance: Arc<dyn SpectralTexture>, two_sided: bool) -> Self {
        Self {
            radiance,
            two_sided,
        }
    }

    /// The spectral radiance texture.
    pub fn radiance(&self) -> &Arc<dyn SpectralTexture> {
        &self.radiance
    }

    /// Whether the back side emits too.
    pub fn two_sided(&self) -> bool {
        self.two_sided
    }
}

impl Material for Emissive {
    fn flags(&self) -> MaterialFlags {
        MaterialFlags::EMISSIVE
    }

    fn sample(
        &self,
        _wo: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _u_lobe: f32,
        _u: Vec2,
        _mode: TransportMode,
    ) -> Option<BsdfSample> {
        None
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

    fn emitted(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if wo.z > 0.0 || (self.two_sided && wo.z < 0.0) {
            self.radiance.eval(lambda, ctx.uv)
        } else {
            SampledSpectrum::zero()
        }
    }
}
