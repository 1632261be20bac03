//! Built-in lights (besides area lights, which are emissive objects), one per file.

pub mod directional;
pub mod environment;
pub mod luminaire;
pub mod point;
pub mod spot;

use crate::builtin::param_err;
use crate::builtin::spectral::{spd, Spectrum};
use crate::scene::{FactoryContext, FactoryError};
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
