//! `conductor` (alias `rough_conductor`): a metal, smooth or rough (GGX), with a complex IOR.
//!
//! | parameter   | unit     | default       | meaning                                          |
//! |-------------|----------|---------------|--------------------------------------------------|
//! | `metal`     | —        | `"aluminium"` | a bundled metal's n, k tables                    |
//! | `n`         | unitless | —             | `(nm, n)` pairs (with `k`, instead of `metal`)   |
//! | `k`         | unitless | —             | `(nm, k)` pairs at the same wavelengths as `n`   |
//! | `roughness` | unitless | —             | perceptual roughness r, α = r²                   |
//! | `alpha`     | unitless | `0.1`         | GGX α directly (wins over `roughness`)           |

use crate::builtin::spectral::alpha;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::metals::ComplexIorTable;
use crate::material::{Material, RoughConductor};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "conductor",
    aliases: &["rough_conductor"],
    version: 1,
    description: "metal with a spectral complex IOR, smooth or rough (GGX)",
    params: &[
        Param::optional(
            "metal",
            "",
            "\"aluminium\"",
            "bundled metal: aluminium, gold, silver, copper (or al, au, ag, cu)",
        ),
        Param::optional("n", "", "—", "(nm, n) pairs; with `k` instead of `metal`"),
        Param::optional("k", "", "—", "(nm, k) pairs at the wavelengths of `n`"),
        Param::optional("roughness", "", "—", "perceptual roughness r ≥ 0; α = r²"),
        Param::optional("alpha", "", "0.1", "GGX α directly (wins over `roughness`)"),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<ConductorParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorParams {
    /// Bundled metal name.
    #[serde(default)]
    pub metal: Option<String>,
    /// Real part of the IOR, `(nm, n)`.
    #[serde(default)]
    pub n: Option<Vec<(f64, f64)>>,
    /// Imaginary part, `(nm, k)`.
    #[serde(default)]
    pub k: Option<Vec<(f64, f64)>>,
    /// Perceptual roughness.
    #[serde(default)]
    pub roughness: Option<f64>,
    /// GGX α.
    #[serde(default)]
    pub alpha: Option<f64>,
}

impl Embed for ConductorParams {}

/// Build the material.
pub fn build(p: &ConductorParams, ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so, to call it without
/// a second dynamic call).
pub fn build_concrete(
    p: &ConductorParams,
    _ctx: &FactoryContext,
) -> Result<RoughConductor, FactoryError> {
    let table = match (&p.n, &p.k) {
        (Some(n), Some(k)) => {
            let ln: Vec<f64> = n.iter().map(|x| x.0).collect();
            let lk: Vec<f64> = k.iter().map(|x| x.0).collect();
            if ln != lk {
                return Err(param_err("k", "must use the same wavelengths as `n`"));
            }
            // n > 0 and k ≥ 0, finite and representable: anything else is not a metal.
            for &(l, v) in n {
                if !(v.is_finite() && v > 0.0 && v <= crate::builtin::check::MAX_F32) {
                    return Err(param_err(
                        "n",
                        format!("value {v} at {l} nm must be finite and > 0"),
                    ));
                }
            }
            for &(l, v) in k {
                if !(0.0..=crate::builtin::check::MAX_F32).contains(&v) {
                    return Err(param_err(
                        "k",
                        format!("value {v} at {l} nm must be finite and ≥ 0"),
                    ));
                }
            }
            let rows: Vec<(f32, f32, f32)> = n
                .iter()
                .zip(k)
                .map(|(&(l, n), &(_, k))| (l as f32, n as f32, k as f32))
                .collect();
            ComplexIorTable::from_rows(&rows).map_err(|e| param_err("n", e))?
        }
        _ => ComplexIorTable::builtin(p.metal.as_deref().unwrap_or("aluminium"))
            .map_err(|e| param_err("metal", e))?,
    };
    Ok(RoughConductor::new(table, alpha(p.alpha, p.roughness)?))
}
