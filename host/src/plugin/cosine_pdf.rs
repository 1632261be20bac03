//! Checking a plugin material's claim that it samples with the cosine-weighted density
//! (the `COSINE_PDF` bit), once, when it is built. The host then
//! computes `pdf(wo, wi)` itself as `|cos θi|/π` on `wo`'s side and 0 on the other
//! ([`cosine_pdf`]) instead of calling the plugin; a material that claims it wrongly would get
//! wrong MIS weights (a biased image wherever its real density differs) with no noise to show
//! it. So the probe asks the material what the host relies on: `sample`'s own density is the
//! cosine density of the direction it returns, on `wo`'s side, and `pdf` agrees at every probed
//! direction, 0 on the other side.
//!
//! | probe | values |
//! |---|---|
//! | wavelengths, nm | [`flatness::SET_A_NM`](super::flatness::SET_A_NM) (every lane live, density 1/nm) |
//! | outgoing directions (local frame) | normal, 37° in x–z, and one below the surface |
//! | uniforms (lobe, direction) | three fixed triples |
//! | incident directions for `pdf` | the sampled one and [`same_f::PROBE_WI`](super::same_f::PROBE_WI) (each on both sides) |
//! | surface | at the origin, normals +z, uv (0.5, 0.5) |
//! | agreement | `sample`'s density and `pdf` on `wo`'s side within [`REL_TOLERANCE`](super::flatness::REL_TOLERANCE) of `|cos θi|/π`; `pdf` exactly 0 on the other side |
//!
//! 9 samples and at most 90 densities: nothing next to building a scene. What the probe cannot
//! see (another density at directions it did not try) stays the plugin's responsibility, as the
//! API's documentation says.

use super::flatness::close;
use super::same_f::{for_each_probe_sample, probe_directions};
use crate::material::{same_hemisphere, Material, MaterialFlags};
use glam::Vec3A;
use std::f32::consts::FRAC_1_PI;

/// The cosine-weighted density of `wi` given `wo` (1/sr): `|cos θi|/π` on `wo`'s side, 0 on the
/// other. The same expression, in the same order, as the built-in Lambertian's `pdf`, so a
/// plugin built from it gets the same bits.
#[inline]
pub fn cosine_pdf(wo: Vec3A, wi: Vec3A) -> f32 {
    if same_hemisphere(wo, wi) {
        wi.z.abs() * FRAC_1_PI
    } else {
        0.0
    }
}

/// `Ok` when the probes find `m` sampling with the cosine-weighted density; else what they
/// found, as the end of a sentence. `m` is asked through its own `pdf` (the plugin's), never
/// through [`cosine_pdf`].
pub fn check(m: &dyn Material) -> Result<(), String> {
    if m.flags().contains(MaterialFlags::SPECULAR) {
        return Err("it has a specular lobe, whose density is not the cosine's".to_string());
    }
    for_each_probe_sample(m, |probe, wo, s| {
        let expected = cosine_pdf(wo, s.wi);
        if !same_hemisphere(wo, s.wi) || !close(s.pdf, expected) {
            return Err(format!(
                "`sample` at wo = {wo} returns wi = {} with density {} 1/sr where the \
                     cosine-weighted density is {expected} 1/sr",
                s.wi, s.pdf
            ));
        }
        for wi in probe_directions(s.wi) {
            let p = m.pdf(wo, wi, &probe.ctx, &probe.lambda, probe.mode);
            let expected = cosine_pdf(wo, wi);
            let agrees = if expected > 0.0 {
                close(p, expected)
            } else {
                p == 0.0
            };
            if !agrees {
                return Err(format!(
                    "`pdf` at wo = {wo}, wi = {wi} returns {p} 1/sr where the \
                         cosine-weighted density is {expected} 1/sr"
                ));
            }
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::lambertian::Lambertian;
    use crate::material::{BsdfSample, MaterialFlags, ShadingContext, TransportMode};
    use crate::plugin::flatness::SET_A_NM;
    use crate::plugin::same_f::PROBE_WI;
    use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};
    use crate::texture::spectral_texture::ConstantTexture;
    use glam::Vec2;
    use std::sync::Arc;

    /// A liar: Lambertian values, but directions drawn uniformly over the hemisphere (density
    /// 1/(2π)), with `sample` and `pdf` honest about that density.
    #[derive(Debug)]
    struct Uniform(Lambertian);

    impl Material for Uniform {
        fn flags(&self) -> MaterialFlags {
            self.0.flags()
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
            let z = u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * std::f32::consts::PI * u.y;
            let wi = Vec3A::new(r * phi.cos(), r * phi.sin(), z.copysign(wo.z));
            let mut s = self.0.sample(wo, ctx, lambda, u_lobe, u, mode)?;
            s.wi = wi;
            s.pdf = 0.5 * FRAC_1_PI;
            Some(out.write(s))
        }
        fn eval(
            &self,
            wo: Vec3A,
            wi: Vec3A,
            ctx: &ShadingContext,
            lambda: &SampledWavelengths,
            mode: TransportMode,
        ) -> SampledSpectrum {
            self.0.eval(wo, wi, ctx, lambda, mode)
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
                0.5 * FRAC_1_PI
            } else {
                0.0
            }
        }
    }

    // The built-in Lambertian passes (its density is the cosine's, bit for bit: the probe's
    // comparisons are exact for it); a material sampling uniformly is found out by `sample`'s
    // own density, and the message names the call and both densities.
    #[test]
    fn the_probe_accepts_lambertian_and_finds_another_density() {
        let grey = Lambertian::new(Arc::new(ConstantTexture(0.5)));
        assert_eq!(check(&grey), Ok(()));
        let e = check(&Uniform(grey)).unwrap_err();
        assert!(
            e.contains("`sample`") && e.contains("0.15915") && e.contains("cosine-weighted"),
            "{e}"
        );
    }

    // The host's density is the built-in Lambertian's, bit for bit, on both sides.
    #[test]
    fn the_host_density_is_the_lambertian_one() {
        let grey = Lambertian::new(Arc::new(ConstantTexture(0.5)));
        let ctx = ShadingContext::at(Vec3A::ZERO, Vec3A::Z, Vec3A::Z, Vec2::splat(0.5));
        let lambda = SampledWavelengths {
            lambda: SET_A_NM,
            pdf: [1.0; LANES],
            lanes: LaneMask::ALL,
        };
        let wo = Vec3A::new(0.6, 0.0, 0.8);
        for &[x, y, z] in &PROBE_WI {
            for wi in [Vec3A::new(x, y, z), Vec3A::new(x, y, -z)] {
                let builtin = grey.pdf(wo, wi, &ctx, &lambda, TransportMode::Radiance);
                assert_eq!(cosine_pdf(wo, wi).to_bits(), builtin.to_bits(), "{wi}");
            }
        }
    }
}
