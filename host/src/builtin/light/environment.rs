//! `environment`: light arriving from outside the scene, the same radiance from every direction
//! (a uniform sky); every ray that leaves the scene sees it. A scene has at most one.
//!
//! | parameter  | unit         | default        | meaning                                                    |
//! |------------|--------------|----------------|------------------------------------------------------------|
//! | `radiance` | W/(m²·sr·nm) | `"e"`          | spectral radiance: a `(nm, value)` table (absolute), or an SPD spec/type (normalised, then `scale` is required) |
//! | `scale`    | W/(m²·sr)    | `1` for tables | multiplier of a table; integrated radiance for a named SPD |

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{finite, from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::{ConstantEnvironment, EnvironmentLight, Light};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::parse_spd_spec;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "environment",
    aliases: &[],
    version: 1,
    description: "uniform sky: the same radiance from every direction outside the scene",
    params: &[
        Param::optional(
            "radiance",
            "W/(m²·sr·nm)",
            "\"e\"",
            "spectral radiance: (nm, value) table (absolute) or an SPD spec/type (normalised; needs `scale`)",
        ),
        Param::optional(
            "scale",
            "W/(m²·sr)",
            "1 for tables",
            "multiplier of a table; the integrated radiance for a named SPD, > 0",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<EnvironmentParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentParams {
    /// Spectral radiance.
    #[serde(default)]
    pub radiance: Option<Spectrum>,
    /// Multiplier / integrated radiance.
    #[serde(default)]
    pub scale: Option<f64>,
}

impl Embed for EnvironmentParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.radiance.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &EnvironmentParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(EnvironmentLight::new(Arc::new(source(p, ctx)?))))
}

/// The light's radiance source (what [`build`] wraps in an [`EnvironmentLight`]).
pub fn source(
    p: &EnvironmentParams,
    ctx: &FactoryContext,
) -> Result<ConstantEnvironment, FactoryError> {
    // As for `emissive`: a table is absolute spectral radiance (× optional `scale`); a named
    // SPD is normalised and `scale` is the integrated radiance.
    let (spd, raw) = match &p.radiance {
        Some(v) => spd(v, "radiance", ctx)?,
        None => (
            Arc::new(parse_spd_spec("e").map_err(|e| param_err("radiance", e))?) as _,
            None,
        ),
    };
    let scale = match raw {
        Some(integral) => integral * finite("scale", p.scale.unwrap_or(1.0))?,
        None => finite(
            "scale",
            p.scale.ok_or_else(|| {
                param_err(
                    "scale",
                    "required with a named SPD: integrated radiance in W/(m²·sr)",
                )
            })?,
        )?,
    };
    // Held as f32 by the renderer: refuse what would become infinite.
    let scale = crate::builtin::check::radiometric("scale", scale, "W/(m²·sr)")?;
    ConstantEnvironment::new(spd, scale).map_err(|e| param_err("scale", e))
}
