//! `directional`: a distant light (sun-like), parallel rays over the whole scene.
//!
//! | parameter    | unit | default | meaning                                          |
//! |--------------|------|---------|--------------------------------------------------|
//! | `direction`  | —    | —       | direction the light travels, (x, y, z), non-zero |
//! | `irradiance` | W/m² | —       | irradiance on a surface facing the light, ≥ 0    |
//! | `spd`        | —    | `"e"`   | emission spectrum (SPD spectral value)           |
//!
//! Exactly one of `irradiance` and `illuminance_lx`; E = illuminance_lx / K with K the
//! spectrum's luminous efficacy (lm/W, [`crate::light::luminous`]).

use super::{exactly_one, from_photometric, light_spd, non_negative};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::{DirectionalLight, Light};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "directional",
    aliases: &[],
    version: 2,
    description: "distant light with parallel rays",
    params: &[
        Param::required(
            "direction",
            "",
            "direction the light travels, (x, y, z), non-zero",
        ),
        Param::optional(
            "irradiance",
            "W/m²",
            "—",
            "irradiance on a surface facing the light, ≥ 0; exactly one of `irradiance`, `illuminance_lx`",
        ),
        Param::optional(
            "illuminance_lx",
            "lx",
            "—",
            "or: illuminance on a surface facing the light, ≥ 0 (CIE 1931 V(λ), 683.002 lm/W)",
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
    #[serde(default)]
    pub irradiance: Option<f64>,
    /// Illuminance, lx.
    #[serde(default)]
    pub illuminance_lx: Option<f64>,
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
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(
    p: &DirectionalParams,
    ctx: &FactoryContext,
) -> Result<DirectionalLight, FactoryError> {
    let spd = light_spd(&p.spd, ctx)?;
    let irradiance = match exactly_one(&[
        ("irradiance", p.irradiance),
        ("illuminance_lx", p.illuminance_lx),
    ])? {
        (0, e) => e,
        (_, lx) => from_photometric("illuminance_lx", lx, spd.as_ref())?,
    };
    DirectionalLight::new(
        crate::builtin::check::direction("direction", p.direction)?,
        spd,
        non_negative("irradiance", irradiance, "W/m²")?,
    )
    .map_err(|e| param_err("direction", e))
}
