//! `mirror`: a perfect specular reflector.
//!
//! | parameter     | unit     | default | meaning                                        |
//! |---------------|----------|---------|------------------------------------------------|
//! | `reflectance` | unitless | `1`     | spectral reflectance in [0, 1] (spectral value or image texture) |

use crate::builtin::spectral::{texture, Spectrum};
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::material::{Material, Mirror};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::texture::ConstantTexture;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "mirror",
    aliases: &[],
    version: 1,
    description: "perfect specular reflector",
    params: &[Param::optional(
        "reflectance",
        "",
        "1",
        "spectral reflectance in [0, 1]: number, spec, (nm, value) list, (rgb: ..) or an image (texture: \"file.png\") / (texture: (file: .., filter: .., ..)), see docs/textures.md",
    )],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<MirrorParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorParams {
    /// Spectral reflectance.
    #[serde(default)]
    pub reflectance: Option<Spectrum>,
}

impl Embed for MirrorParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.reflectance.embed(ctx)
    }
}

/// Build the material.
pub fn build(p: &MirrorParams, ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(p: &MirrorParams, ctx: &FactoryContext) -> Result<Mirror, FactoryError> {
    let r = match &p.reflectance {
        Some(v) => texture(v, "reflectance", ctx)?,
        None => Arc::new(ConstantTexture(1.0)),
    };
    Ok(Mirror::new(r))
}
