//! A rough conductor (metal): GGX microfacets with the conductor Fresnel term for a spectral
//! complex IOR `n + i·k`, sampled with visible normals. Very small roughness becomes an ideal
//! specular reflector.

use super::metals::ComplexIorTable;
use super::microfacet::Ggx;
use super::{
    fresnel, reflect, same_hemisphere, BsdfSample, Material, MaterialFlags, ShadingContext,
    TransportMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};

/// GGX conductor. One-sided: only light from the normal's side is reflected.
#[derive(Debug, Clone)]
pub struct RoughConductor {
    ior: ComplexIorTable,
    ggx: Ggx,
}

impl RoughConductor {
    /// A conductor with complex IOR table `ior` and GGX width `alpha` (slope-space, ≥ 0).
    pub fn new(ior: ComplexIorTable, alpha: f32) -> Self {
        Self {
            ior,
            ggx: Ggx::new(alpha),
        }
    }

    fn fresnel(&self, cos: f32, lambda: &SampledWavelengths) -> SampledSpectrum {
        let mut out = [0.0; LANES];
        for (o, &l) in out.iter_mut().zip(lambda.lambda.iter()) {
            let (n, k) = self.ior.eval(l);
            *o = fresnel::conductor(cos.abs(), n, k);
        }
        SampledSpectrum(out)
    }
}

impl Material for RoughConductor {
    fn flags(&self) -> MaterialFlags {
        if self.ggx.effectively_smooth() {
            MaterialFlags::SPECULAR | MaterialFlags::REFLECTION
        } else {
            MaterialFlags::GLOSSY | MaterialFlags::REFLECTION
        }
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _u_lobe: f32,
        u: Vec2,
        _mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.ggx.effectively_smooth() {
            let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
            return Some(out.write(BsdfSample {
                wi,
                f: self.fresnel(wi.z, lambda) / wi.z,
                pdf: 1.0,
                flags: self.flags(),
                eta: 1.0,
            }));
        }
        let wm = self.ggx.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        let cos_om = wo.dot(wm);
        let pdf = self.ggx.d_visible(wo, wm) / (4.0 * cos_om.abs());
        if !(pdf > 0.0) {
            return None;
        }
        let f = self.fresnel(cos_om, lambda)
            * (self.ggx.d(wm) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z));
        Some(out.write(BsdfSample {
            wi,
            f,
            pdf,
            flags: self.flags(),
            eta: 1.0,
        }))
    }

    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> SampledSpectrum {
        if self.ggx.effectively_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
            return SampledSpectrum::zero();
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::zero();
        }
        let wm = wm.normalize();
        self.fresnel(wo.dot(wm), lambda)
            * (self.ggx.d(wm) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z))
    }

    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        if self.ggx.effectively_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        self.ggx.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs())
    }
}
