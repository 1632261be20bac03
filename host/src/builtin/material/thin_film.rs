//! `thin_film`: a smooth surface coated with one thin dielectric film (soap film, oil on
//! water, oxide on metal): reflectance and transmittance from the Airy sum per wavelength
//! ([`crate::material::thin_film`]).
//!
//! | parameter      | unit     | default  | meaning                                                        |
//! |----------------|----------|----------|----------------------------------------------------------------|
//! | `thickness_nm` | nm       | required | film thickness d ≥ 0 (0: the bare base)                        |
//! | `film`         | unitless | `1.33`   | film IOR: number ≥ 1, glass name, Cauchy or Sellmeier          |
//! | `base`         | unitless | `1.0`    | what the film sits on: an IOR (dielectric: reflects and transmits; `1.0` = a free film in air) or a metal name (`gold`, `silver`, `copper`, `aluminium`, or `au`, `ag`, `cu`, `al`: reflects only) |

use crate::builtin::spectral::Ior;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::metals::ComplexIorTable;
use crate::material::thin_film::{ThinFilm, ThinFilmBase};
use crate::material::Material;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "thin_film",
    aliases: &[],
    version: 1,
    description: "smooth surface with one thin-film coating (interference colours)",
    params: &[
        Param::required("thickness_nm", "nm", "film thickness d ≥ 0 (0: the bare base)"),
        Param::optional(
            "film",
            "",
            "1.33",
            "film IOR ≥ 1: number, glass name (N-BK7, N-SF11, F2, fused-silica), (cauchy: (a, b µm²)) or (sellmeier: (b: (..), c: (.. µm²)))",
        ),
        Param::optional(
            "base",
            "",
            "1.0",
            "what the film sits on: an IOR as for `film` (dielectric, reflects and transmits; 1.0 = a free film in air) or a metal name: gold, silver, copper, aluminium (au, ag, cu, al; reflects only)",
        ),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<ThinFilmParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThinFilmParams {
    /// Film thickness, nm.
    pub thickness_nm: f64,
    /// Film IOR (default 1.33, soapy water).
    #[serde(default)]
    pub film: Option<Ior>,
    /// Base IOR or metal name (default 1.0: a free film in air).
    #[serde(default)]
    pub base: Option<Ior>,
}

impl Embed for ThinFilmParams {}

/// Build the material.
pub fn build(p: &ThinFilmParams, _ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    if !(p.thickness_nm.is_finite() && p.thickness_nm >= 0.0) {
        return Err(param_err(
            "thickness_nm",
            format!("must be a finite number ≥ 0 nm, got {}", p.thickness_nm),
        ));
    }
    if p.thickness_nm > 1e5 {
        return Err(param_err(
            "thickness_nm",
            format!(
                "{} nm is not a thin film (interference fringes finer than any wavelength \
                 sampling; use at most 100000 nm)",
                p.thickness_nm
            ),
        ));
    }
    let film = p.film.clone().unwrap_or(Ior::Number(1.33)).build()?;
    if !(film.eval(550.0) >= 1.0) {
        return Err(param_err(
            "film",
            format!("film index {} at 550 nm is below 1", film.eval(550.0)),
        ));
    }
    let base = match p.base.clone().unwrap_or(Ior::Number(1.0)) {
        Ior::Glass(name) if ComplexIorTable::builtin(&name).is_ok() => ThinFilmBase::Conductor(
            ComplexIorTable::builtin(&name).map_err(|e| param_err("base", e))?,
        ),
        ior => ThinFilmBase::Dielectric(ior.build().map_err(|e| match e {
            FactoryError::Param(m) => param_err(
                "base",
                format!("{m} (nor is it a metal: gold, silver, copper, aluminium)"),
            ),
            other => other,
        })?),
    };
    let m =
        ThinFilm::new(p.thickness_nm as f32, film, base).map_err(|e| param_err("thin_film", e))?;
    Ok(Arc::new(m))
}
