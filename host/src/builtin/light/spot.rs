//! `spot`: a spot light with a smooth falloff between an inner and an outer cone.
//!
//! | parameter     | unit        | default | meaning                                        |
//! |---------------|-------------|---------|------------------------------------------------|
//! | `position`    | scene units | —       | where the light is                             |
//! | `target`      | scene units | —       | a point on the cone's axis                     |
//! | `inner_angle` | degrees     | `20`    | half-angle of full intensity                   |
//! | `outer_angle` | degrees     | `30`    | half-angle where the intensity reaches zero    |
//! | `power`       | W           | —       | total radiant flux, ≥ 0                        |
//! | `flux_lm`     | lm          | —       | or: total luminous flux, ≥ 0                   |
//! | `intensity_cd`| cd          | —       | or: luminous intensity on the axis, ≥ 0        |
//! | `spd`         | —           | `"e"`   | emission spectrum (SPD spectral value)         |
//!
//! Exactly one of `power`, `flux_lm` and `intensity_cd`, converted with the spectrum's
//! luminous efficacy K (lm/W, [`crate::light::luminous`]): Φ = flux_lm / K, or the peak
//! intensity I₀ = intensity_cd / K W/sr and Φ = I₀ · Ω, Ω the falloff's solid angle
//! ([`crate::light::spot::falloff_solid_angle_sr`]).

use super::{exactly_one, from_photometric, light_spd, non_negative};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{
    finite, finite3, from_value, param_err, state_fns, Build, BuiltinType, Embed,
};
use crate::light::{Light, SpotLight};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "spot",
    aliases: &[],
    version: 2,
    description: "spot light with a smooth falloff between two cones",
    params: &[
        Param::required("position", "scene units", "where the light is, (x, y, z)"),
        Param::required("target", "scene units", "a point on the cone axis"),
        Param::optional(
            "inner_angle",
            "degrees",
            "20",
            "half-angle of full intensity",
        ),
        Param::optional(
            "outer_angle",
            "degrees",
            "30",
            "half-angle where the intensity reaches zero",
        ),
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
            "or: luminous intensity on the axis (inside the inner cone), ≥ 0",
        ),
        Param::optional(
            "spd",
            "",
            "\"e\"",
            "emission spectrum: spec string, (nm, value) list or (type: .., params: ..)",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<SpotParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpotParams {
    /// Position, scene units.
    pub position: [f64; 3],
    /// A point on the axis, scene units.
    pub target: [f64; 3],
    /// Inner half-angle, degrees.
    #[serde(default)]
    pub inner_angle: Option<f64>,
    /// Outer half-angle, degrees.
    #[serde(default)]
    pub outer_angle: Option<f64>,
    /// Radiant flux, W.
    #[serde(default)]
    pub power: Option<f64>,
    /// Luminous flux, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Luminous intensity on the axis, cd.
    #[serde(default)]
    pub intensity_cd: Option<f64>,
    /// Emission spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
}

impl Embed for SpotParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &SpotParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(p: &SpotParams, ctx: &FactoryContext) -> Result<SpotLight, FactoryError> {
    let position = finite3("position", p.position)?;
    let target = finite3("target", p.target)?;
    if !((target - position).length() > 0.0) {
        return Err(param_err(
            "target",
            format!("must differ from `position`, both are {:?}", p.position),
        ));
    }
    let inner = finite("inner_angle", p.inner_angle.unwrap_or(20.0))?;
    let outer = finite("outer_angle", p.outer_angle.unwrap_or(30.0))?;
    if !(outer > 0.0 && outer < 180.0) {
        return Err(param_err(
            "outer_angle",
            format!("{outer}° is outside (0, 180) degrees"),
        ));
    }
    if !(inner >= 0.0 && inner <= outer) {
        return Err(param_err(
            "inner_angle",
            format!("{inner}° is outside [0, outer_angle = {outer}] degrees"),
        ));
    }
    let spd = light_spd(&p.spd, ctx)?;
    let power_w = match exactly_one(&[
        ("power", p.power),
        ("flux_lm", p.flux_lm),
        ("intensity_cd", p.intensity_cd),
    ])? {
        (0, w) => w,
        (1, lm) => from_photometric("flux_lm", lm, spd.as_ref())?,
        (_, cd) => {
            from_photometric("intensity_cd", cd, spd.as_ref())?
                * crate::light::spot::falloff_solid_angle_sr(inner, outer)
        }
    };
    SpotLight::new(
        position,
        target,
        inner as f32,
        outer as f32,
        spd,
        non_negative("power", power_w, "W")?,
    )
    .map_err(FactoryError::Param)
}
