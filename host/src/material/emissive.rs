//! The surface of an area light: emits `scale · S(λ)` radiance (W/(m²·sr·nm), `S` a normalised
//! SPD in 1/nm, `scale` in W/(m²·sr)) from its front side (along the geometric normal) and
//! reflects nothing, as the measured Cornell box light is modelled by the anchor renderers.

use super::dense::DenseSpectrum;
use super::{BsdfSample, EmissionProfile, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// A black, one- or two-sided emitter.
#[derive(Debug, Clone)]
pub struct Emissive {
    profile: EmissionProfile,
    radiance: DenseSpectrum,
}

impl Emissive {
    /// An emitter of spectral radiance `scale · spd(λ)`.
    pub fn new(spd: Arc<dyn Spd>, scale: f32, two_sided: bool) -> Self {
        Self {
            radiance: DenseSpectrum::from_spd(spd.clone(), scale),
            profile: EmissionProfile {
                spd,
                scale,
                two_sided,
            },
        }
    }
}

impl Material for Emissive {
    fn flags(&self) -> MaterialFlags {
        MaterialFlags::EMISSIVE
    }

    // Scatters nothing; its emission is judged by its light's spectrum.
    fn spectrally_flat(&self) -> bool {
        true
    }

    fn sample_into<'a>(
        &self,
        _wo: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _u_lobe: f32,
        _u: Vec2,
        _mode: TransportMode,
        _out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
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

    fn emission(&self) -> Option<EmissionProfile> {
        Some(self.profile.clone())
    }

    fn emitted(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        let _ = ctx;
        if wo.z > 0.0 || (self.profile.two_sided && wo.z < 0.0) {
            self.radiance.eval(lambda)
        } else {
            SampledSpectrum::zero()
        }
    }
}
