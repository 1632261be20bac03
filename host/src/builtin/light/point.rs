//! `point`: an isotropic point light.
//!
//! | parameter  | unit        | default | meaning                                   |
//! |------------|-------------|---------|-------------------------------------------|
//! | `position` | scene units | —       | where the light is                        |
//! | `power`    | W           | —       | total radiant flux, ≥ 0                   |
//! | `flux_lm`  | lm          | —       | or: total luminous flux, ≥ 0              |
//! | `intensity_cd` | cd      | —       | or: luminous intensity, ≥ 0               |
//! | `spd`      | —           | `"e"`   | emission spectrum (SPD spectral value)    |
//!
//! Exactly one of `power`, `flux_lm` and `intensity_cd`. Radiant intensity
//! I(λ) = Φ · spd(λ) / 4π in every direction; photometric values are converted with the
//! spectrum's luminous efficacy K (lm/W, [`crate::light::luminous`]): Φ = flux_lm / K,
//! Φ = 4π · intensity_cd / K.

use super::{exactly_one, from_photometric, light_spd, non_negative};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{finite3, from_value, state_fns, Build, BuiltinType, Embed};
use crate::light::{Light, PointLight};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "point",
    aliases: &[],
    version: 2,
    description: "isotropic point light",
    params: &[
        Param::required("position", "scene units", "where the light is, (x, y, z)"),
        Param::optional(
            "power",
            "W",
            "—",
            "total radiant flux, ≥ 0; exactly one of `power`, `flux_lm`, `intensity_cd`",
        ),
        Param::optional(
            "flux_lm",
            "lm",
            "—",
            "or: total luminous flux, ≥ 0 (CIE 1931 V(λ), 683.002 lm/W)",
        ),
        Param::optional(
            "intensity_cd",
            "cd",
            "—",
            "or: luminous intensity in every direction, ≥ 0",
        ),
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
    #[serde(default)]
    pub power: Option<f64>,
    /// Luminous flux, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Luminous intensity, cd.
    #[serde(default)]
    pub intensity_cd: Option<f64>,
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
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(p: &PointParams, ctx: &FactoryContext) -> Result<PointLight, FactoryError> {
    let spd = light_spd(&p.spd, ctx)?;
    let power_w = match exactly_one(&[
        ("power", p.power),
        ("flux_lm", p.flux_lm),
        ("intensity_cd", p.intensity_cd),
    ])? {
        (0, w) => w,
        (1, lm) => from_photometric("flux_lm", lm, spd.as_ref())?,
        (_, cd) => 4.0 * std::f64::consts::PI * from_photometric("intensity_cd", cd, spd.as_ref())?,
    };
    Ok(PointLight::new(
        finite3("position", p.position)?,
        spd,
        non_negative("power", power_w, "W")?,
    ))
}
