//! A rough dielectric boundary (frosted glass): GGX microfacets, Fresnel-weighted choice between
//! reflection and refraction on the sampled visible microfacet (Walter et al. 2007 with Heitz's
//! visible-normal sampling). A spectral IOR makes every event dispersive (hero lane only).

use super::microfacet::Ggx;
use super::{
    fresnel, reflect, refract, same_hemisphere, BsdfSample, EffectsOff, Material, MaterialFlags,
    ShadingContext, SmoothDielectric, SpectralIor, TransportMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// GGX dielectric boundary; outside (normal side) n = 1.
#[derive(Debug, Clone)]
pub struct RoughDielectric {
    ior: SpectralIor,
    ggx: Ggx,
    smooth: SmoothDielectric,
}

impl RoughDielectric {
    /// A boundary with inside IOR `ior` and GGX width `alpha`.
    pub fn new(ior: SpectralIor, alpha: f32) -> Self {
        Self {
            ior,
            ggx: Ggx::new(alpha),
            smooth: SmoothDielectric::new(ior),
        }
    }

    fn dispersive(&self) -> MaterialFlags {
        if self.ior.is_dispersive() {
            MaterialFlags::DISPERSIVE
        } else {
            MaterialFlags::NONE
        }
    }

    /// The microfacet normal joining `wo` and `wi` (upper hemisphere), the relative IOR of the
    /// event and whether it is a reflection; `None` for degenerate or back-facing configurations.
    fn half_vector(&self, wo: Vec3A, wi: Vec3A, eta: f32) -> Option<(Vec3A, f32, bool)> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflection = same_hemisphere(wo, wi);
        let etap = if reflection {
            1.0
        } else if wo.z > 0.0 {
            eta
        } else {
            1.0 / eta
        };
        let wm = wi * etap + wo;
        if wm.length_squared() == 0.0 {
            return None;
        }
        let mut wm = wm.normalize();
        if wm.z < 0.0 {
            wm = -wm;
        }
        // Microfacets seen from behind do not contribute.
        if wm.dot(wi) * wi.z < 0.0 || wm.dot(wo) * wo.z < 0.0 {
            return None;
        }
        Some((wm, etap, reflection))
    }
}

impl Material for RoughDielectric {
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
        Some((Arc::new(Self::new(ior, self.ggx.alpha())), text))
    }

    fn flags(&self) -> MaterialFlags {
        if self.ggx.effectively_smooth() {
            return self.smooth.flags();
        }
        MaterialFlags::GLOSSY
            | MaterialFlags::REFLECTION
            | MaterialFlags::TRANSMISSION
            | self.dispersive()
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        if self.ggx.effectively_smooth() {
            return self
                .smooth
                .sample_into(wo, ctx, lambda, u_lobe, u, mode, out);
        }
        if wo.z == 0.0 {
            return None;
        }
        let eta = self.ior.eval(lambda.lambda[0]);
        let wm = self.ggx.sample_wm(wo, u);
        let cos_om = wo.dot(wm);
        let r = fresnel::dielectric(cos_om, eta);
        let t = 1.0 - r;
        let d_vis = self.ggx.d_visible(wo, wm);
        if u_lobe < r || t <= 0.0 {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            let pdf = d_vis / (4.0 * cos_om.abs()) * r;
            let f = self.ggx.d(wm) * self.ggx.g(wo, wi) * r / (4.0 * wi.z * wo.z).abs();
            if !(pdf > 0.0) {
                return None;
            }
            return Some(out.write(BsdfSample {
                wi,
                f: SampledSpectrum::splat(f),
                pdf,
                flags: MaterialFlags::GLOSSY | MaterialFlags::REFLECTION | self.dispersive(),
                eta: 1.0,
            }));
        }
        // A microfacet facing away from wo cannot refract it.
        if cos_om * wo.z <= 0.0 {
            return None;
        }
        // Microfacet normal on wo's side, relative IOR as seen from wo's side.
        let (n, etap) = if wo.z > 0.0 {
            (wm, eta)
        } else {
            (-wm, 1.0 / eta)
        };
        let wi = refract(wo, n, etap)?;
        if same_hemisphere(wo, wi) || wi.z == 0.0 {
            return None;
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        if denom == 0.0 {
            return None;
        }
        let dwm_dwi = wi.dot(wm).abs() / denom;
        let pdf = d_vis * dwm_dwi * t;
        let mut f = t
            * self.ggx.d(wm)
            * self.ggx.g(wo, wi)
            * (wi.dot(wm) * wo.dot(wm) / (wi.z * wo.z * denom)).abs();
        if mode == TransportMode::Radiance {
            f /= etap * etap;
        }
        if !(pdf > 0.0) {
            return None;
        }
        Some(out.write(BsdfSample {
            wi,
            f: SampledSpectrum::splat(f),
            pdf,
            flags: MaterialFlags::GLOSSY | MaterialFlags::TRANSMISSION | self.dispersive(),
            eta: etap,
        }))
    }

    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum {
        if self.ggx.effectively_smooth() {
            return SampledSpectrum::zero();
        }
        let eta = self.ior.eval(lambda.lambda[0]);
        let Some((wm, etap, reflection)) = self.half_vector(wo, wi, eta) else {
            return SampledSpectrum::zero();
        };
        let r = fresnel::dielectric(wo.dot(wm), eta);
        if reflection {
            let f = self.ggx.d(wm) * self.ggx.g(wo, wi) * r / (4.0 * wi.z * wo.z).abs();
            return SampledSpectrum::splat(f);
        }
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * wi.z * wo.z;
        if denom == 0.0 {
            return SampledSpectrum::zero();
        }
        let mut f = (1.0 - r)
            * self.ggx.d(wm)
            * self.ggx.g(wo, wi)
            * (wi.dot(wm) * wo.dot(wm) / denom).abs();
        if mode == TransportMode::Radiance {
            f /= etap * etap;
        }
        SampledSpectrum::splat(f)
    }

    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        if self.ggx.effectively_smooth() {
            return 0.0;
        }
        let eta = self.ior.eval(lambda.lambda[0]);
        let Some((wm, etap, reflection)) = self.half_vector(wo, wi, eta) else {
            return 0.0;
        };
        let r = fresnel::dielectric(wo.dot(wm), eta);
        let d_vis = self.ggx.d_visible(wo, wm);
        if reflection {
            d_vis / (4.0 * wo.dot(wm).abs()) * r
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            if denom == 0.0 {
                return 0.0;
            }
            d_vis * wi.dot(wm).abs() / denom * (1.0 - r)
        }
    }
}
