//! The parameters every built-in light shares: its spectrum (`spd`) and its amount, given as
//! exactly one of a radiometric or a photometric quantity.

use crate::builtin::param_err;
use crate::builtin::spectral::{spd, Spectrum};
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::{parse_spd_spec, Spd};
use std::sync::Arc;

/// A light's `spd` parameter; equal-energy `e` when absent.
pub fn light_spd(
    value: &Option<Spectrum>,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Spd>, FactoryError> {
    match value {
        Some(v) => Ok(spd(v, "spd", ctx)?.0),
        None => Ok(Arc::new(
            parse_spd_spec("e").map_err(|e| param_err("spd", e))?,
        )),
    }
}

/// A finite `value` ≥ 0 of parameter `name` in `unit`, representable as the f32 the light
/// stores (see [`crate::builtin::check::radiometric`]).
pub fn non_negative(name: &str, value: f64, unit: &str) -> Result<f32, FactoryError> {
    crate::builtin::check::radiometric(name, value, unit)
}

/// The one value given among alternative parameters of the same quantity (a power in W or a
/// flux in lm, …): its index in `given` and its value. An error names them all when none or
/// more than one is given.
pub fn exactly_one(given: &[(&str, Option<f64>)]) -> Result<(usize, f64), FactoryError> {
    let names = given
        .iter()
        .map(|(n, _)| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ");
    let present: Vec<usize> = (0..given.len()).filter(|&i| given[i].1.is_some()).collect();
    match present.as_slice() {
        [i] => Ok((*i, given[*i].1.unwrap_or(0.0))),
        [] => Err(param_err(
            given[0].0,
            format!("missing: give exactly one of {names}"),
        )),
        several => Err(param_err(
            given[several[1]].0,
            format!(
                "give exactly one of {names}, not both `{}` and `{}`",
                given[several[0]].0, given[several[1]].0
            ),
        )),
    }
}

/// A photometric `value` of parameter `param` (lm, cd, lx or cd/m²) as the radiometric value
/// (W, W/sr, W/m² or W/(m²·sr)) of light with normalised spectrum `spd` (see
/// [`crate::light::luminous`]).
pub fn from_photometric(param: &str, value: f64, spd: &dyn Spd) -> Result<f64, FactoryError> {
    crate::light::luminous::radiometric_from_photometric(param, value, spd)
        .map_err(FactoryError::Param)
}
