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

/// GGX conductor. Two-sided, as a metal sheet is and as the lambertian and mirror materials
/// are: light from below the shading normal is reflected by the same lobe mirrored through the
/// surface (the BSDF is evaluated in the frame flipped to `wo`'s side).
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

    /// `w` with its `z` negated when `flip`: the frame turned to the side `wo` is on.
    #[inline]
    fn side(w: Vec3A, flip: bool) -> Vec3A {
        if flip {
            Vec3A::new(w.x, w.y, -w.z)
        } else {
            w
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
        if wo.z == 0.0 {
            return None;
        }
        if self.ggx.effectively_smooth() {
            let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
            return Some(out.write(BsdfSample {
                wi,
                f: self.fresnel(wi.z, lambda) / wi.z.abs(),
                pdf: 1.0,
                flags: self.flags(),
                eta: 1.0,
            }));
        }
        let flip = wo.z < 0.0;
        let wo = Self::side(wo, flip);
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
            wi: Self::side(wi, flip),
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
        if self.ggx.effectively_smooth() || !same_hemisphere(wo, wi) {
            return SampledSpectrum::zero();
        }
        let flip = wo.z < 0.0;
        let (wo, wi) = (Self::side(wo, flip), Self::side(wi, flip));
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
        if self.ggx.effectively_smooth() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let flip = wo.z < 0.0;
        let (wo, wi) = (Self::side(wo, flip), Self::side(wi, flip));
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        self.ggx.d_visible(wo, wm) / (4.0 * wo.dot(wm).abs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The conductor is two-sided: with both directions mirrored through the surface, eval,
    /// pdf and a sample (same random numbers, mirrored result) are the same numbers. Tolerance:
    /// exact equality for eval and pdf (the same arithmetic on the same values), 1e-6 for the
    /// sampled direction. Before the fix the back side returned zero and no sample.
    #[test]
    fn back_side_mirrors_the_front() {
        let lambda = SampledWavelengths::sample_visible(0.37);
        let ctx = ShadingContext::default();
        let mirror = |w: Vec3A| Vec3A::new(w.x, w.y, -w.z);
        for alpha in [0.0, 0.05, 0.3] {
            let m = RoughConductor::new(ComplexIorTable::builtin("copper").unwrap(), alpha);
            let wo = Vec3A::new(0.3, -0.2, 0.6).normalize();
            let wi = Vec3A::new(-0.5, 0.1, 0.4).normalize();
            let mode = TransportMode::Radiance;
            let front = m.eval(wo, wi, &ctx, &lambda, mode);
            let back = m.eval(mirror(wo), mirror(wi), &ctx, &lambda, mode);
            assert_eq!(front.0, back.0, "eval, alpha {alpha}");
            let pf = m.pdf(wo, wi, &ctx, &lambda, mode);
            let pb = m.pdf(mirror(wo), mirror(wi), &ctx, &lambda, mode);
            assert_eq!(pf, pb, "pdf, alpha {alpha}");
            let u = Vec2::new(0.31, 0.77);
            let sf = m.sample(wo, &ctx, &lambda, 0.5, u, mode).unwrap();
            let sb = m.sample(mirror(wo), &ctx, &lambda, 0.5, u, mode).unwrap();
            assert!((mirror(sf.wi) - sb.wi).length() < 1e-6, "alpha {alpha}");
            assert_eq!(sf.f.0, sb.f.0);
            assert_eq!(sf.pdf, sb.pdf);
            // Light arriving from the other side is not reflected.
            assert_eq!(m.eval(wo, mirror(wi), &ctx, &lambda, mode).0, [0.0; LANES]);
        }
    }
}
