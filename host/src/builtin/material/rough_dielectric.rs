//! `rough_dielectric`: a microfacet (GGX) dielectric interface.
//!
//! | parameter   | unit     | default | meaning                                              |
//! |-------------|----------|---------|------------------------------------------------------|
//! | `ior`       | unitless | `1.5`   | index of refraction (as for `dielectric`)            |
//! | `roughness` | unitless | —       | perceptual roughness r, α = r²                       |
//! | `alpha`     | unitless | `0.1`   | GGX α directly (wins over `roughness`)               |

use crate::builtin::spectral::{alpha, Ior};
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::material::{Material, RoughDielectric};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "rough_dielectric",
    aliases: &[],
    version: 1,
    description: "rough dielectric interface (GGX microfacets)",
    params: &[
        Param::optional(
            "ior",
            "",
            "1.5",
            "index of refraction (as for `dielectric`)",
        ),
        Param::optional("roughness", "", "—", "perceptual roughness r ≥ 0; α = r²"),
        Param::optional("alpha", "", "0.1", "GGX α directly (wins over `roughness`)"),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<RoughDielectricParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughDielectricParams {
    /// Index of refraction (default 1.5).
    #[serde(default)]
    pub ior: Option<Ior>,
    /// Perceptual roughness.
    #[serde(default)]
    pub roughness: Option<f64>,
    /// GGX α.
    #[serde(default)]
    pub alpha: Option<f64>,
}

impl Embed for RoughDielectricParams {}

/// Build the material.
pub fn build(
    p: &RoughDielectricParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(
    p: &RoughDielectricParams,
    _ctx: &FactoryContext,
) -> Result<RoughDielectric, FactoryError> {
    Ok(RoughDielectric::new(
        p.ior.clone().unwrap_or(Ior::Number(1.5)).build()?,
        alpha(p.alpha, p.roughness)?,
    ))
}
