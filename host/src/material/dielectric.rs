//! A smooth dielectric interface (glass, water) with a spectral IOR: Fresnel-weighted choice
//! between specular reflection and refraction. With a wavelength-dependent IOR the event is
//! dispersive: the hero wavelength alone decides the direction and the sample carries
//! [`MaterialFlags::DISPERSIVE`] so the integrator drops the other lanes.

use super::{
    fresnel, refract, BsdfSample, EffectsOff, Material, MaterialFlags, ShadingContext, SpectralIor,
    TransportMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// Smooth dielectric boundary; the outside (normal side) is vacuum/air with n = 1.
#[derive(Debug, Clone)]
pub struct SmoothDielectric {
    ior: SpectralIor,
}

impl SmoothDielectric {
    /// A boundary with the given inside IOR.
    pub fn new(ior: SpectralIor) -> Self {
        Self { ior }
    }
}

impl Material for SmoothDielectric {
    fn flags(&self) -> MaterialFlags {
        let mut f =
            MaterialFlags::SPECULAR | MaterialFlags::REFLECTION | MaterialFlags::TRANSMISSION;
        if self.ior.is_dispersive() {
            f |= MaterialFlags::DISPERSIVE;
        }
        f
    }

    // Fresnel reflectance and refraction depend on the IOR alone.
    fn spectrally_flat(&self) -> bool {
        !self.ior.is_dispersive()
    }

    fn without_effects(&self, off: &EffectsOff) -> Option<(Arc<dyn Material>, String)> {
        if !(off.dispersion && self.ior.is_dispersive()) {
            return None;
        }
        let ior = self.ior.frozen_at(off.reference_nm);
        let text = format!(
            "dispersion off: IOR {:.4} (its value at {} nm) at every wavelength",
            ior.eval(off.reference_nm),
            off.reference_nm
        );
        Some((Arc::new(Self::new(ior)), text))
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        _u: Vec2,
        mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let eta = self.ior.eval(lambda.lambda[0]);
        let dispersive = if self.ior.is_dispersive() {
            MaterialFlags::DISPERSIVE
        } else {
            MaterialFlags::NONE
        };
        let r = fresnel::dielectric(wo.z, eta);
        let t = 1.0 - r;
        if u_lobe < r || t <= 0.0 {
            let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
            return Some(out.write(BsdfSample {
                wi,
                f: SampledSpectrum::splat(r / wi.z.abs()),
                pdf: r,
                flags: MaterialFlags::SPECULAR | MaterialFlags::REFLECTION | dispersive,
                eta: 1.0,
            }));
        }
        // Refraction: the normal on wo's side and the relative IOR seen from there.
        let (n, etap) = if wo.z > 0.0 {
            (Vec3A::Z, eta)
        } else {
            (-Vec3A::Z, 1.0 / eta)
        };
        let wi = refract(wo, n, etap)?;
        let mut ft = t / wi.z.abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        Some(out.write(BsdfSample {
            wi,
            f: SampledSpectrum::splat(ft),
            pdf: t,
            flags: MaterialFlags::SPECULAR | MaterialFlags::TRANSMISSION | dispersive,
            eta: etap,
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
