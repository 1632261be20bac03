//! `point`: an isotropic point light.
//!
//! | parameter  | unit        | default | meaning                                   |
//! |------------|-------------|---------|-------------------------------------------|
//! | `position` | scene units | —       | where the light is                        |
//! | `power`    | W           | —       | total radiant flux, ≥ 0                   |
//! | `spd`      | —           | `"e"`   | emission spectrum (SPD spectral value)    |
//!
//! Radiant intensity I(λ) = Φ · spd(λ) / 4π in every direction.

use super::{light_spd, non_negative};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{finite3, from_value, state_fns, Build, BuiltinType, Embed};
use crate::light::{Light, PointLight};
use crate::plugin::type_doc::Param;
use crate::scene::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "point",
    aliases: &[],
    version: 1,
    description: "isotropic point light",
    params: &[
        Param::required("position", "scene units", "where the light is, (x, y, z)"),
        Param::required("power", "W", "total radiant flux, ≥ 0"),
        Param::optional(
            "spd",
            "",
            "\"e\"",
            "emission spectrum: spec string, (nm, value) list or (type: .., params: ..)",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<PointParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointParams {
    /// Position, scene units.
    pub position: [f64; 3],
    /// Radiant flux, W.
    pub power: f64,
    /// Emission spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
}

impl Embed for PointParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &PointParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(PointLight::new(
        finite3("position", p.position)?,
        light_spd(&p.spd, ctx)?,
        non_negative("power", p.power, "W")?,
    )))
}
