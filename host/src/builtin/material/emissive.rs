//! `emissive` (alias `area_light`): a surface that emits light; an object with this material
//! becomes an area light. It does not reflect.
//!
//! | parameter   | unit         | default | meaning                                                    |
//! |-------------|--------------|---------|------------------------------------------------------------|
//! | `radiance`  | W/(m²·sr·nm) | —       | spectral radiance: a `(nm, value)` table (absolute), or an SPD spec/type (normalised, then `scale` is required) |
//! | `scale`     | W/(m²·sr)    | `1` for tables | multiplier of a table; integrated radiance for a named SPD |
//! | `luminance_cd_m2` | cd/m² | —     | instead of `scale`: the luminance the surface has (the spectrum gives the shape) |
//! | `two_sided` | —            | `false` | emit from both faces                                       |
//!
//! At most one of `scale` and `luminance_cd_m2` (one is required with a named SPD). The
//! luminance sets the integrated radiance to luminance_cd_m2 / K, K the spectrum's luminous
//! efficacy (lm/W, [`crate::light::luminous`]).

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::{Emissive, Material};
use crate::plugin::type_doc::Param;
use crate::scene::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "emissive",
    aliases: &["area_light"],
    version: 2,
    description: "light-emitting surface (its object becomes an area light)",
    params: &[
        Param::required("radiance", "W/(m²·sr·nm)", "spectral radiance: (nm, value) table (absolute) or an SPD spec/type (normalised; needs `scale`)"),
        Param::optional("scale", "W/(m²·sr)", "1 for tables", "multiplier of a table; the integrated radiance for a named SPD"),
        Param::optional("luminance_cd_m2", "cd/m²", "—", "instead of `scale`: the surface's luminance (CIE 1931 V(λ), 683.002 lm/W); the spectrum gives the shape"),
        Param::optional("two_sided", "", "false", "emit from both faces"),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<EmissiveParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmissiveParams {
    /// Spectral radiance.
    pub radiance: Spectrum,
    /// Multiplier / integrated radiance.
    #[serde(default)]
    pub scale: Option<f64>,
    /// Luminance, cd/m² (instead of `scale`).
    #[serde(default)]
    pub luminance_cd_m2: Option<f64>,
    /// Emit from both faces.
    #[serde(default)]
    pub two_sided: bool,
}

impl Embed for EmissiveParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.radiance.embed(ctx)
    }
}

/// Build the material.
pub fn build(p: &EmissiveParams, ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    let (spd, raw) = spd(&p.radiance, "radiance", ctx)?;
    // Tables are absolute spectral radiance (× optional scale); named SPDs are normalised and
    // need `scale` = integrated radiance in W/(m²·sr).
    if let (Some(_), Some(_)) = (p.scale, p.luminance_cd_m2) {
        return Err(param_err(
            "luminance_cd_m2",
            "give at most one of `scale` and `luminance_cd_m2`, not both",
        ));
    }
    let scale = match (raw, p.luminance_cd_m2) {
        (_, Some(cd_m2)) => {
            crate::builtin::light::from_photometric("luminance_cd_m2", cd_m2, spd.as_ref())?
        }
        (Some(integral), None) => {
            integral * crate::builtin::finite("scale", p.scale.unwrap_or(1.0))?
        }
        (None, None) => crate::builtin::finite(
            "scale",
            p.scale.ok_or_else(|| {
                param_err(
                    "scale",
                    "required with a named SPD: integrated radiance in W/(m²·sr) (or give \
                     `luminance_cd_m2`)",
                )
            })?,
        )?,
    };
    // The renderer holds the integrated radiance as f32: refuse what would become infinite.
    let scale = crate::builtin::check::radiometric("scale", scale, "W/(m²·sr)")?;
    Ok(Arc::new(Emissive::new(spd, scale, p.two_sided)))
}
