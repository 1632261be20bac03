//! `rough_plastic` (alias `roughplastic`): a diffuse base under a rough (GGX or Beckmann) clear
//! coating (Mitsuba 3's `roughplastic`): a blurred Fresnel highlight on top of a diffuse colour. The
//! model, its formula and its sources: [`crate::material::plastic`].
//!
//! | parameter              | unit     | default | meaning                                                  |
//! |------------------------|----------|---------|----------------------------------------------------------|
//! | `diffuse_reflectance`  | unitless | `0.5`   | the base's spectral reflectance ρ in [0, 1] (spectral value or image texture) |
//! | `specular_reflectance` | unitless | `1`     | factor on the coating's reflection in [0, 1] (1 is physical) |
//! | `int_ior`              | unitless | `1.49`  | the coating's index (as `plastic`'s)                     |
//! | `ext_ior`              | unitless | `1`     | the index of the medium outside                          |
//! | `nonlinear`            | —        | `false` | keep the colour shift of the light bouncing inside the coating |
//! | `roughness`            | unitless | —       | perceptual roughness r, α = r²                           |
//! | `alpha`                | unitless | `0.1`   | the distribution's α directly (wins over `roughness`)    |
//! | `distribution`         | —        | `"ggx"` | the microfacet distribution: `ggx` (sampled by visible normals) or `beckmann` (α the RMS slope; Mitsuba's default) |
//!
//! α below 0.001 is the smooth coating (`plastic`).

use crate::builtin::material::plastic::{
    parts, DIFFUSE_REFLECTANCE, EXT_IOR, NONLINEAR, SPECULAR_REFLECTANCE,
};
use crate::builtin::spectral::{alpha, Ior, Spectrum};
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::plastic::Coating;
use crate::material::{Material, Plastic};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "rough_plastic",
    aliases: &["roughplastic"],
    version: 1,
    description:
        "diffuse base under a rough (GGX or Beckmann) dielectric coating (Mitsuba's roughplastic)",
    params: &[
        DIFFUSE_REFLECTANCE,
        SPECULAR_REFLECTANCE,
        Param::optional(
            "int_ior",
            "",
            "1.49",
            "the coating's index of refraction (as plastic's)",
        ),
        EXT_IOR,
        NONLINEAR,
        Param::optional("roughness", "", "—", "perceptual roughness r ≥ 0; α = r²"),
        Param::optional(
            "alpha",
            "",
            "0.1",
            "the distribution's α directly (wins over `roughness`)",
        ),
        Param::optional(
            "distribution",
            "",
            "\"ggx\"",
            "microfacet distribution: ggx or beckmann (α the RMS slope)",
        ),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<RoughPlasticParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughPlasticParams {
    /// The base's reflectance.
    #[serde(default)]
    pub diffuse_reflectance: Option<Spectrum>,
    /// Factor on the coating's reflection.
    #[serde(default)]
    pub specular_reflectance: Option<Spectrum>,
    /// The coating's index.
    #[serde(default)]
    pub int_ior: Option<Ior>,
    /// The outside's index.
    #[serde(default)]
    pub ext_ior: Option<Ior>,
    /// Keep the internal scattering's colour shift.
    #[serde(default)]
    pub nonlinear: Option<bool>,
    /// Perceptual roughness.
    #[serde(default)]
    pub roughness: Option<f64>,
    /// The distribution's α.
    #[serde(default)]
    pub alpha: Option<f64>,
    /// Microfacet distribution.
    #[serde(default)]
    pub distribution: Option<String>,
}

impl Embed for RoughPlasticParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.diffuse_reflectance.embed(ctx)?;
        self.specular_reflectance.embed(ctx)
    }
}

/// Build the material.
pub fn build(
    p: &RoughPlasticParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so).
pub fn build_concrete(
    p: &RoughPlasticParams,
    ctx: &FactoryContext,
) -> Result<Plastic, FactoryError> {
    let a = alpha(p.alpha, p.roughness)?;
    let coating = match p.distribution.as_deref() {
        None | Some("ggx") => Coating::Ggx(a),
        Some("beckmann") => Coating::Beckmann(a),
        Some(other) => {
            return Err(param_err(
                "distribution",
                format!("`{other}` is not a distribution spectrace has (ggx, beckmann)"),
            ))
        }
    };
    parts(
        &p.diffuse_reflectance,
        &p.specular_reflectance,
        &p.int_ior,
        &p.ext_ior,
        p.nonlinear,
        coating,
        ctx,
    )
}
