//! `dielectric`: a smooth dielectric interface (glass, water), reflecting and refracting.
//!
//! | parameter | unit     | default | meaning                                                  |
//! |-----------|----------|---------|----------------------------------------------------------|
//! | `ior`     | unitless | `1.5`   | index of refraction: number, glass name, Cauchy, Sellmeier |

use crate::builtin::spectral::Ior;
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::material::{Material, SmoothDielectric};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "dielectric",
    aliases: &[],
    version: 1,
    description: "smooth dielectric interface (Fresnel reflection and refraction)",
    params: &[Param::optional(
        "ior",
        "",
        "1.5",
        "index of refraction: number, glass name (N-BK7, N-SF11, F2, fused-silica), (cauchy: (a, b µm²)) or (sellmeier: (b: (..), c: (.. µm²)))",
    )],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<DielectricParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DielectricParams {
    /// Index of refraction (default 1.5).
    #[serde(default)]
    pub ior: Option<Ior>,
}

impl Embed for DielectricParams {}

/// Build the material.
pub fn build(
    p: &DielectricParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(
    p: &DielectricParams,
    _ctx: &FactoryContext,
) -> Result<SmoothDielectric, FactoryError> {
    let ior = p.ior.clone().unwrap_or(Ior::Number(1.5)).build()?;
    Ok(SmoothDielectric::new(ior))
}
