//! Checking a plugin material's claim to be spectrally flat (the `SPECTRALLY_FLAT` bit), once, when it is
//! built. A flat material is rendered with the exact colour of its paths' emitters
//! (`integrator::flat_colour`); a material that claims it wrongly would get the wrong colour
//! with no noise to show it. The claim is cheap to test where it matters most: the material is
//! asked the same questions at two sets of four wavelengths and must answer alike.
//!
//! | probe | values |
//! |---|---|
//! | wavelengths, nm | [`SET_A_NM`] and [`SET_B_NM`] (every lane live, density 1/nm) |
//! | outgoing directions (local frame) | normal, 37° in x–z, and one below the surface |
//! | uniforms (lobe, direction) | three fixed triples |
//! | surface | at the origin, normals +z, uv (0.5, 0.5) |
//! | agreement | every lane of `sample`'s value and of `eval` at the sampled direction within [`REL_TOLERANCE`] of one value; `sample`'s direction, density and absorption the same at both sets |
//!
//! 9 samples and 9 evaluations per wavelength set: nothing next to building a scene. A material
//! that declares DISPERSIVE or fluoresces contradicts the claim by its own flags. What the probe
//! cannot see (a texture that varies in colour elsewhere on the surface) stays the plugin's
//! responsibility, as the API's documentation says.

use crate::material::{Material, MaterialFlags, ShadingContext, TransportMode};
use crate::spectrum::{LaneMask, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};

/// First probe set, nm.
pub const SET_A_NM: [f32; LANES] = [380.0, 480.0, 580.0, 680.0];
/// Second probe set, nm.
pub const SET_B_NM: [f32; LANES] = [430.0, 530.0, 630.0, 780.0];
/// Relative difference allowed between lanes: f32 arithmetic done per lane may round a grey
/// material's value differently (a few ulp, 1e-7 relative); a coloured one differs by far more.
pub const REL_TOLERANCE: f32 = 1e-5;

fn lanes(nm: [f32; LANES]) -> SampledWavelengths {
    SampledWavelengths {
        lambda: nm,
        pdf: [1.0; LANES],
        lanes: LaneMask::ALL,
    }
}

pub(super) fn close(a: f32, b: f32) -> bool {
    a == b || (a - b).abs() <= REL_TOLERANCE * a.abs().max(b.abs())
}

/// `Ok` when the probes find `m` flat; else what they found, as the end of a sentence.
/// `flags` are the material's, `reradiates` whether it offered re-radiation.
pub fn check(m: &dyn Material, flags: MaterialFlags, reradiates: bool) -> Result<(), String> {
    if flags.contains(MaterialFlags::DISPERSIVE) {
        return Err("it also declares DISPERSIVE (directions that depend on wavelength)".into());
    }
    if flags.contains(MaterialFlags::FLUORESCENT) || reradiates {
        return Err("it fluoresces (shifts wavelengths)".into());
    }
    let ctx = ShadingContext::at(Vec3A::ZERO, Vec3A::Z, Vec3A::Z, Vec2::splat(0.5));
    let (la, lb) = (lanes(SET_A_NM), lanes(SET_B_NM));
    let wos = [
        Vec3A::Z,
        Vec3A::new(0.6, 0.0, 0.8),
        Vec3A::new(-0.48, 0.6, -0.64),
    ];
    let us = [(0.1, 0.2, 0.3), (0.5, 0.7, 0.9), (0.9, 0.05, 0.6)];
    let mode = TransportMode::Radiance;
    let flat = |v: &[f32; LANES], w: &[f32; LANES]| v.iter().chain(w).all(|&x| close(x, v[0]));
    for wo in wos {
        for (u0, u1, u2) in us {
            let u = Vec2::new(u1, u2);
            let (a, b) = (
                m.sample(wo, &ctx, &la, u0, u, mode),
                m.sample(wo, &ctx, &lb, u0, u, mode),
            );
            let (a, b) = match (a, b) {
                (None, None) => continue,
                (Some(a), Some(b)) => (a, b),
                _ => {
                    return Err(format!(
                        "`sample` at wo = {wo} absorbs at {:?} nm and not at {:?} nm or the \
                         other way round",
                        SET_A_NM, SET_B_NM
                    ))
                }
            };
            if a.wi != b.wi || !close(a.pdf, b.pdf) {
                return Err(format!(
                    "`sample` at wo = {wo} draws a different direction or density at {:?} nm \
                     ({}, pdf {}) than at {:?} nm ({}, pdf {})",
                    SET_A_NM, a.wi, a.pdf, SET_B_NM, b.wi, b.pdf
                ));
            }
            if !flat(&a.f.0, &b.f.0) {
                return Err(format!(
                    "`sample` at wo = {wo} returns {:?} at {:?} nm and {:?} at {:?} nm \
                     (lanes differ by more than {REL_TOLERANCE} relative)",
                    a.f.0, SET_A_NM, b.f.0, SET_B_NM
                ));
            }
            let (ea, eb) = (
                m.eval(wo, a.wi, &ctx, &la, mode),
                m.eval(wo, a.wi, &ctx, &lb, mode),
            );
            if !flat(&ea.0, &eb.0) {
                return Err(format!(
                    "`eval` at wo = {wo}, wi = {} returns {:?} at {:?} nm and {:?} at {:?} nm \
                     (lanes differ by more than {REL_TOLERANCE} relative)",
                    a.wi, ea.0, SET_A_NM, eb.0, SET_B_NM
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::lambertian::Lambertian;
    use crate::texture::spectral_texture::{ConstantTexture, CurveTexture};
    use std::sync::Arc;

    // A grey Lambertian passes; one whose reflectance rises from 0.2 at 380 nm to 0.8 at
    // 780 nm is found out by its sampled values, naming `sample` and both wavelength sets;
    // the flags DISPERSIVE and FLUORESCENT contradict the claim by themselves.
    #[test]
    fn the_probe_accepts_grey_and_finds_colour() {
        let grey = Lambertian::new(Arc::new(ConstantTexture(0.5)));
        assert_eq!(check(&grey, grey.flags(), false), Ok(()));
        let ramp = CurveTexture::piecewise_linear("ramp", 1.0, vec![(380.0, 0.2), (780.0, 0.8)]);
        let coloured = Lambertian::new(Arc::new(ramp));
        let e = check(&coloured, coloured.flags(), false).unwrap_err();
        assert!(
            e.contains("`sample`") && e.contains("380.0") && e.contains("780.0"),
            "{e}"
        );
        let e = check(&grey, grey.flags() | MaterialFlags::DISPERSIVE, false).unwrap_err();
        assert!(e.contains("DISPERSIVE"), "{e}");
        assert!(check(&grey, grey.flags(), true)
            .unwrap_err()
            .contains("fluoresces"));
    }
}
