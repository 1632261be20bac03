//! Checking a plugin material's claim that its BSDF value is the same for every direction
//! (the `SAME_VALUE_ALL_DIRECTIONS` bit), once, when it is built. The path
//! tracer then lends a sampled direction's value to next-event estimation at the same point
//! instead of evaluating the material again; a material that claims it wrongly would get a wrong
//! direct light with no noise to show it. So the probe asks the material what the path tracer
//! relies on: `sample` stays on `wo`'s side, and `eval` returns exactly the sampled value at
//! every direction on that side and 0 on the other.
//!
//! | probe | values |
//! |---|---|
//! | wavelengths, nm | [`flatness::SET_A_NM`](super::flatness::SET_A_NM) (every lane live, density 1/nm) |
//! | outgoing directions (local frame) | normal, 37° in x–z, and one below the surface |
//! | uniforms (lobe, direction) | three fixed triples |
//! | incident directions evaluated | the sampled one and [`PROBE_WI`] (each on both sides) |
//! | surface | at the origin, normals +z, uv (0.5, 0.5) |
//! | agreement | every lane of `eval` on `wo`'s side within [`REL_TOLERANCE`] of the sampled value; exactly 0 on the other side |
//!
//! 9 samples and at most 90 evaluations: nothing next to building a scene. What the probe cannot
//! see (a texture that changes the value elsewhere on the surface is fine: the claim is about
//! directions at one point) stays the plugin's responsibility, as the API's documentation says.

use super::flatness::{close, SET_A_NM};
use crate::material::{same_hemisphere, BsdfSample, Material, ShadingContext, TransportMode};
use crate::spectrum::{LaneMask, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};

/// Incident directions (local frame, upper side; each is also tried mirrored below) at which
/// `eval` must return the sampled value: the normal, 60° and 84° from it, three azimuths.
pub const PROBE_WI: [[f32; 3]; 4] = [
    [0.0, 0.0, 1.0],
    [0.866_025_4, 0.0, 0.5],
    [-0.248_689_9, 0.961_262_6, 0.104_528_46],
    [0.3, -0.4, 0.866_025_4],
];

/// `Ok` when the probes find `f(wo, ·)` of `m` the same for every direction on `wo`'s side and
/// 0 on the other; else what they found, as the end of a sentence.
pub fn check(m: &dyn Material) -> Result<(), String> {
    for_each_probe_sample(m, |probe, wo, s| {
        if !same_hemisphere(wo, s.wi) {
            return Err(format!(
                "`sample` at wo = {wo} returns wi = {} on the other side of the surface",
                s.wi
            ));
        }
        for wi in probe_directions(s.wi) {
            let f = m.eval(wo, wi, &probe.ctx, &probe.lambda, probe.mode);
            let same_side = same_hemisphere(wo, wi);
            let agrees = f.0.iter().zip(&s.f.0).all(
                |(&e, &v)| {
                    if same_side {
                        close(e, v)
                    } else {
                        e == 0.0
                    }
                },
            );
            if !agrees {
                let expected = if same_side { s.f.0 } else { [0.0; LANES] };
                return Err(format!(
                    "`eval` at wo = {wo}, wi = {wi} returns {:?} at {:?} nm where {:?} was \
                         expected ({})",
                    f.0,
                    SET_A_NM,
                    expected,
                    if same_side {
                        "the value `sample` returned for that wo"
                    } else {
                        "0 on the other side"
                    }
                ));
            }
        }
        Ok(())
    })
}

/// The surface, wavelengths and transport mode every probe of a material's claim uses (see the
/// module's table).
pub(super) struct Probe {
    pub ctx: ShadingContext,
    pub lambda: SampledWavelengths,
    pub mode: TransportMode,
}

/// Calls `visit(probe, wo, sample)` for each of the probe's nine `sample` calls of `m` (three
/// outgoing directions × three uniform triples; directions `m` does not sample are skipped),
/// stopping at the first error.
pub(super) fn for_each_probe_sample(
    m: &dyn Material,
    mut visit: impl FnMut(&Probe, Vec3A, &BsdfSample) -> Result<(), String>,
) -> Result<(), String> {
    let probe = Probe {
        ctx: ShadingContext::at(Vec3A::ZERO, Vec3A::Z, Vec3A::Z, Vec2::splat(0.5)),
        lambda: SampledWavelengths {
            lambda: SET_A_NM,
            pdf: [1.0; LANES],
            lanes: LaneMask::ALL,
        },
        mode: TransportMode::Radiance,
    };
    let wos = [
        Vec3A::Z,
        Vec3A::new(0.6, 0.0, 0.8),
        Vec3A::new(-0.48, 0.6, -0.64),
    ];
    let us = [(0.1, 0.2, 0.3), (0.5, 0.7, 0.9), (0.9, 0.05, 0.6)];
    for wo in wos {
        for (u0, u1, u2) in us {
            let sample = m.sample(
                wo,
                &probe.ctx,
                &probe.lambda,
                u0,
                Vec2::new(u1, u2),
                probe.mode,
            );
            if let Some(s) = sample {
                visit(&probe, wo, &s)?;
            }
        }
    }
    Ok(())
}

/// The sampled direction `wi`, then [`PROBE_WI`], each also mirrored below the surface.
pub(super) fn probe_directions(wi: Vec3A) -> impl Iterator<Item = Vec3A> {
    let probes = PROBE_WI
        .iter()
        .flat_map(|&[x, y, z]| [Vec3A::new(x, y, z), Vec3A::new(x, y, -z)]);
    std::iter::once(wi).chain(probes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::lambertian::Lambertian;
    use crate::material::{BsdfSample, MaterialFlags};
    use crate::spectrum::SampledSpectrum;
    use crate::texture::spectral_texture::{ConstantTexture, CurveTexture};
    use std::sync::Arc;

    /// A glossy-looking liar: Lambertian sampling, but `eval` grows with cos θi.
    #[derive(Debug)]
    struct CosineWeighted(Lambertian);

    impl Material for CosineWeighted {
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
            let mut s = self.0.sample(wo, ctx, lambda, u_lobe, u, mode)?;
            s.f *= s.wi.z.abs();
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
            self.0.eval(wo, wi, ctx, lambda, mode) * wi.z.abs()
        }
        fn pdf(
            &self,
            wo: Vec3A,
            wi: Vec3A,
            ctx: &ShadingContext,
            lambda: &SampledWavelengths,
            mode: TransportMode,
        ) -> f32 {
            self.0.pdf(wo, wi, ctx, lambda, mode)
        }
    }

    // The built-in Lambertian, grey or coloured, passes (its value is one per point whatever the
    // direction); a material whose value depends on wi is found out by `eval`, and the message
    // names the call and the wavelengths.
    #[test]
    fn the_probe_accepts_lambertian_and_finds_direction_dependence() {
        let grey = Lambertian::new(Arc::new(ConstantTexture(0.5)));
        assert_eq!(check(&grey), Ok(()));
        let ramp = CurveTexture::piecewise_linear("ramp", 1.0, vec![(380.0, 0.2), (780.0, 0.8)]);
        assert_eq!(check(&Lambertian::new(Arc::new(ramp))), Ok(()));
        let e = check(&CosineWeighted(grey)).unwrap_err();
        assert!(e.contains("`eval`") && e.contains("380.0"), "{e}");
    }
}
