//! `lambertian` (alias `diffuse`): an ideal diffuse reflector.
//!
//! | parameter     | unit     | default | meaning                                        |
//! |---------------|----------|---------|------------------------------------------------|
//! | `reflectance` | unitless | `0.5`   | spectral reflectance in [0, 1] (spectral value or image texture) |
//!
//! BRDF f = ρ(λ)/π.

use crate::builtin::spectral::{texture, Spectrum};
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::material::{Lambertian, Material};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::texture::ConstantTexture;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "lambertian",
    aliases: &["diffuse"],
    version: 1,
    description: "ideal diffuse reflector, BRDF ρ(λ)/π",
    params: &[Param::optional(
        "reflectance",
        "",
        "0.5",
        "spectral reflectance in [0, 1]: number, spec, (nm, value) list, (rgb: ..) or an image (texture: \"file.png\") / (texture: (file: .., filter: .., ..)), see docs/textures.md",
    )],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<LambertianParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LambertianParams {
    /// Spectral reflectance.
    #[serde(default)]
    pub reflectance: Option<Spectrum>,
}

impl Embed for LambertianParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.reflectance.embed(ctx)
    }
}

/// Build the material.
pub fn build(
    p: &LambertianParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(
    p: &LambertianParams,
    ctx: &FactoryContext,
) -> Result<Lambertian, FactoryError> {
    let r = match &p.reflectance {
        Some(v) => texture(v, "reflectance", ctx)?,
        None => Arc::new(ConstantTexture(0.5)),
    };
    Ok(Lambertian::new(r))
}
