//! `spec`: an SPD given by a spec string (normalised to ∫ = 1).
//!
//! | parameter | unit | default | meaning                                                          |
//! |-----------|------|---------|------------------------------------------------------------------|
//! | `spec`    | —    | —       | spectral value: bundled name, `blackbody:T`, CSV path, `name(..)` |

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::Spd;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "spec",
    aliases: &[],
    version: 1,
    description: "SPD from a spec string (bundled name, blackbody:T, CSV path, …), normalised",
    params: &[Param::required(
        "spec",
        "",
        "spec string: d65, a, fl11, blackbody:T, gaussian:C:FWHM, line:NM, a CSV path, …",
    )],
    build: Build::Spd(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<SpecParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpecParams {
    /// The spec.
    pub spec: Spectrum,
}

impl Embed for SpecParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spec.embed(ctx)
    }
}

/// Build the SPD.
pub fn build(p: &SpecParams, ctx: &FactoryContext) -> Result<Arc<dyn Spd>, FactoryError> {
    Ok(spd(&p.spec, "spec", ctx)?.0)
}
