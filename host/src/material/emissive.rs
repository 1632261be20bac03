//! The surface of an area light: emits `scale · S(λ)` radiance (W/(m²·sr·nm), `S` a normalised
//! SPD in 1/nm, `scale` in W/(m²·sr)) from its front side (along the geometric normal) and
//! reflects nothing, as the measured Cornell box light is modelled by the anchor renderers.
//! A textured emitter ([`Emissive::textured`]) emits the [`EmissionTexture`]'s radiance at the
//! surface's texture coordinates instead; its profile then holds the texture's mean spectrum
//! (normalised) and mean integrated radiance, for light selection and wavelength sampling.

use super::{BsdfSample, EmissionProfile, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd, TabulatedSpd};
use crate::texture::emission_texture::EmissionTexture;
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// A black, one- or two-sided emitter.
#[derive(Debug, Clone)]
pub struct Emissive {
    profile: EmissionProfile,
    radiance: DenseSpectrum,
    texture: Option<Arc<EmissionTexture>>,
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
            texture: None,
        }
    }

    /// An emitter whose radiance is `texture`'s at the surface's texture coordinates. An error
    /// when the texture emits nothing.
    pub fn textured(texture: Arc<EmissionTexture>, two_sided: bool) -> Result<Self, String> {
        let mean = texture.mean_spectrum();
        let integral: f64 = mean
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
            .sum();
        let (nm, v): (Vec<f64>, Vec<f64>) = mean.into_iter().unzip();
        if !(integral > 0.0 && integral.is_finite()) {
            return Err(format!(
                "{}: the emission texture emits nothing (every texel is black)",
                texture.name()
            ));
        }
        let spd: Arc<dyn Spd> = Arc::new(
            TabulatedSpd::new(
                texture.name(),
                &nm,
                &v,
                crate::spectrum::Interpolation::Linear,
            )
            .map_err(|e| e.to_string())?,
        );
        let mut e = Self::new(spd, integral as f32, two_sided);
        e.texture = Some(texture);
        Ok(e)
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

    fn emission_texture(&self) -> Option<Arc<EmissionTexture>> {
        self.texture.clone()
    }

    fn emitted(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if wo.z > 0.0 || (self.profile.two_sided && wo.z < 0.0) {
            match &self.texture {
                Some(t) => t.eval(ctx.uv, lambda),
                None => self.radiance.eval(lambda),
            }
        } else {
            SampledSpectrum::zero()
        }
    }
}
