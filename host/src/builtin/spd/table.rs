//! `table`: an SPD tabulated inline (normalised to ∫ = 1).
//!
//! | parameter | unit | default | meaning                                  |
//! |-----------|------|---------|------------------------------------------|
//! | `values`  | nm, — | —      | `(nm, value)` pairs, increasing nm       |

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::Spd;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "table",
    aliases: &[],
    version: 1,
    description: "SPD tabulated inline as (nm, value) pairs, normalised",
    params: &[Param::required(
        "values",
        "nm, relative",
        "(nm, value) pairs, increasing nm",
    )],
    build: Build::Spd(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<TableParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableParams {
    /// The table (any spectral value is accepted, as before).
    pub values: Spectrum,
}

impl Embed for TableParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.values.embed(ctx)
    }
}

/// Build the SPD.
pub fn build(p: &TableParams, ctx: &FactoryContext) -> Result<Arc<dyn Spd>, FactoryError> {
    Ok(spd(&p.values, "values", ctx)?.0)
}
