//! `directional`: a distant light (sun-like), parallel rays over the whole scene.
//!
//! | parameter    | unit | default | meaning                                          |
//! |--------------|------|---------|--------------------------------------------------|
//! | `direction`  | —    | —       | direction the light travels, (x, y, z), non-zero |
//! | `irradiance` | W/m² | —       | irradiance on a surface facing the light, ≥ 0    |
//! | `spd`        | —    | `"e"`   | emission spectrum (SPD spectral value)           |

use super::{light_spd, non_negative};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::{DirectionalLight, Light};
use crate::plugin::type_doc::Param;
use crate::scene::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "directional",
    aliases: &[],
    version: 1,
    description: "distant light with parallel rays",
    params: &[
        Param::required(
            "direction",
            "",
            "direction the light travels, (x, y, z), non-zero",
        ),
        Param::required(
            "irradiance",
            "W/m²",
            "irradiance on a surface facing the light, ≥ 0",
        ),
        Param::optional(
            "spd",
            "",
            "\"e\"",
            "emission spectrum: spec string, (nm, value) list or (type: .., params: ..)",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<DirectionalParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalParams {
    /// Travel direction.
    pub direction: [f64; 3],
    /// Irradiance, W/m².
    pub irradiance: f64,
    /// Emission spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
}

impl Embed for DirectionalParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &DirectionalParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    let d = DirectionalLight::new(
        crate::builtin::check::direction("direction", p.direction)?,
        light_spd(&p.spd, ctx)?,
        non_negative("irradiance", p.irradiance, "W/m²")?,
    )
    .map_err(|e| param_err("direction", e))?;
    Ok(Arc::new(d))
}
