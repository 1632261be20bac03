//! `near_field_luminaire`: a measured luminaire (IES LM-63 or EULUMDAT file, inline or baked
//! table) emitting from its luminous opening instead of a point (see
//! [`crate::light::near_field`]): close to a large panel, light arrives from the whole panel.
//!
//! Parameters: those of `luminaire` (`file`, `table`, `position`, `aim`, `c0`, `spd`,
//! `flux_lm`, `multiplier`, `tilt_deg`; see [`super::luminaire`]) and
//!
//! | parameter | unit | default        | meaning |
//! |-----------|------|----------------|---------|
//! | `size_m`  | m    | the file's     | luminous opening (width along C0, length along C90, height along the axis), overriding the file's |
//!
//! The opening's centre is `position`. A file whose opening is a point (all sizes 0, or only
//! one non-zero) is refused: it has no opening to emit from (use `luminaire`).

use super::luminaire::{build_luminaire, LuminaireParams};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::near_field::NearFieldLight;
use crate::light::Light;
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::CandelaTable;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "near_field_luminaire",
    aliases: &[],
    version: 1,
    description: "measured luminaire emitting from its luminous opening (area emission matching its candela table)",
    params: &[
        Param::optional("file", "", "", ".ies or .ldt file (give `file` or `table`)"),
        Param::optional("table", "cd", "", "candela table inline"),
        Param::required("position", "scene units", "centre of the luminous opening"),
        Param::optional("aim", "", "(0, -1, 0)", "photometric axis (nadir)"),
        Param::optional("c0", "", "(1, 0, 0)", "C0 half-plane direction"),
        Param::optional("spd", "", "\"a\"", "emission spectrum"),
        Param::optional("flux_lm", "lm", "the table's", "total luminous flux"),
        Param::optional("multiplier", "", "1", "factor on every candela value"),
        Param::optional("tilt_deg", "degrees", "from aim", "lamp tilt angle"),
        Param::optional("size_m", "m", "the file's", "luminous opening width, length, height"),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<NearFieldParams>()),
};

/// Parameters of [`TYPE`] (those of `luminaire` and `size_m`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NearFieldParams {
    /// Luminaire file.
    #[serde(default)]
    pub file: Option<String>,
    /// Inline table.
    #[serde(default)]
    pub table: Option<CandelaTable>,
    /// Centre of the opening, scene units.
    pub position: [f64; 3],
    /// Photometric axis.
    #[serde(default)]
    pub aim: Option<[f64; 3]>,
    /// C0 direction.
    #[serde(default)]
    pub c0: Option<[f64; 3]>,
    /// Spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Flux override, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Candela multiplier.
    #[serde(default)]
    pub multiplier: Option<f64>,
    /// Lamp tilt, degrees.
    #[serde(default)]
    pub tilt_deg: Option<f64>,
    /// Opening size override, m.
    #[serde(default)]
    pub size_m: Option<[f64; 3]>,
}

impl NearFieldParams {
    fn base(&self) -> LuminaireParams {
        LuminaireParams {
            file: self.file.clone(),
            table: self.table.clone(),
            position: self.position,
            aim: self.aim,
            c0: self.c0,
            spd: self.spd.clone(),
            flux_lm: self.flux_lm,
            multiplier: self.multiplier,
            tilt_deg: self.tilt_deg,
        }
    }
}

impl Embed for NearFieldParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        let mut b = self.base();
        b.embed(ctx)?;
        self.file = b.file;
        self.table = b.table;
        self.spd = b.spd;
        Ok(())
    }
}

/// Build the light.
pub fn build(p: &NearFieldParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    let point = build_luminaire(&p.base(), ctx)?;
    let size = match p.size_m {
        Some(s) => {
            if !s.iter().all(|v| v.is_finite() && *v >= 0.0) {
                return Err(param_err(
                    "size_m",
                    format!("{s:?}: three finite sizes ≥ 0 m"),
                ));
            }
            s
        }
        None => point.luminaire().size_m,
    };
    let size = size.map(f64::abs);
    if !NearFieldLight::has_opening(size) {
        return Err(param_err(
            "size_m",
            format!(
                "the luminous opening {size:?} m (width, length, height) has no area: give \
                 `size_m`, or use a `luminaire` (point) light"
            ),
        ));
    }
    let spd = point.spd();
    let k = luminous_efficacy_lm_per_w(spd.as_ref());
    Ok(Arc::new(NearFieldLight::new(
        point.position(),
        point.axes(),
        size,
        point.luminaire().clone(),
        spd,
        k,
    )))
}
