//! `gldf`: a luminaire from a GLDF container (see [`crate::photometry::gldf`]): the photometry
//! of a product variant's emitter, with the spectrum of the emitter's light source from the
//! container, as a `luminaire` (point) or, with `near_field: true`, a `near_field_luminaire`.
//!
//! | parameter    | unit        | default          | meaning |
//! |--------------|-------------|------------------|---------|
//! | `file`       | —           | —                | `.gldf` file, relative to the scene file |
//! | `variant`    | —           | the first        | product variant id |
//! | `emitter`    | —           | the variant's first | emitter id (of that variant) |
//! | `position`   | scene units | —                | photometric centre |
//! | `aim`        | —           | `(0, -1, 0)`     | photometric axis (nadir) |
//! | `c0`         | —           | `(1, 0, 0)`      | C0 half-plane direction |
//! | `flux_lm`    | lm          | the photometry's | total luminous flux override |
//! | `multiplier` | —           | `1`              | factor on every candela value |
//! | `spd`        | —           | the container's  | spectrum, only when the container has none for the emitter (then required) |
//! | `near_field` | —           | `false`          | emit from the photometry's luminous opening |
//!
//! A container spectrum and an `spd` together are refused (which one was meant?).

use super::luminaire::{build_luminaire, LuminaireParams};
use super::near_field::NearFieldParams;
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, Build, BuiltinType};
use crate::light::Light;
use crate::photometry::gldf::Gldf;
use crate::photometry::CandelaTable;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "gldf",
    aliases: &[],
    version: 1,
    description: "luminaire from a GLDF container: a variant's emitter photometry with the container's spectrum",
    params: &[
        Param::required("file", "", ".gldf file, relative to the scene file"),
        Param::optional("variant", "", "the first", "product variant id"),
        Param::optional("emitter", "", "the variant's first", "emitter id"),
        Param::required("position", "scene units", "photometric centre, (x, y, z)"),
        Param::optional("aim", "", "(0, -1, 0)", "photometric axis (nadir)"),
        Param::optional("c0", "", "(1, 0, 0)", "C0 half-plane direction"),
        Param::optional("flux_lm", "lm", "the photometry's", "total luminous flux"),
        Param::optional("multiplier", "", "1", "factor on every candela value"),
        Param::optional("spd", "", "the container's", "spectrum when the container has none"),
        Param::optional("near_field", "", "false", "emit from the luminous opening"),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: None,
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GldfParams {
    /// Container file.
    pub file: String,
    /// Variant id.
    #[serde(default)]
    pub variant: Option<String>,
    /// Emitter id.
    #[serde(default)]
    pub emitter: Option<String>,
    /// Photometric centre, scene units.
    pub position: [f64; 3],
    /// Photometric axis.
    #[serde(default)]
    pub aim: Option<[f64; 3]>,
    /// C0 direction.
    #[serde(default)]
    pub c0: Option<[f64; 3]>,
    /// Flux override, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Candela multiplier.
    #[serde(default)]
    pub multiplier: Option<f64>,
    /// Spectrum when the container has none.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Emit from the luminous opening.
    #[serde(default)]
    pub near_field: Option<bool>,
}

/// Build the light.
pub fn build(p: &GldfParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    let path = ctx.resolve(&p.file);
    let mut g = Gldf::open(&path).map_err(|e| param_err("file", e))?;
    for w in &g.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let (v, e) = g
        .choose(p.variant.as_deref(), p.emitter.as_deref())
        .map_err(|m| {
            param_err(
                if p.emitter.is_some() {
                    "emitter"
                } else {
                    "variant"
                },
                format!("{}: {m}", path.display()),
            )
        })?;
    let lum = g.luminaire_of(&e).map_err(|er| param_err("file", er))?;
    let spd = match (g.spectrum_of(&e), &p.spd) {
        (Some(s), None) => Spectrum::Pairs(s.clone()),
        (None, Some(s)) => s.clone(),
        (Some(_), Some(_)) => {
            return Err(param_err(
                "spd",
                format!(
                "emitter `{}` has a spectrum in the container; `spd` would replace it (remove one)",
                e.id
            ),
            ))
        }
        (None, None) => {
            return Err(param_err(
                "spd",
                format!(
                    "emitter `{}` of variant `{}` has no spectrum in the container: give `spd`",
                    e.id, v.id
                ),
            ))
        }
    };
    let source = format!("{} variant {} emitter {}", path.display(), v.id, e.id);
    let table = CandelaTable::from_luminaire(&lum, &source);
    if p.near_field.unwrap_or(false) {
        let nf = NearFieldParams {
            file: None,
            table: Some(table),
            position: p.position,
            aim: p.aim,
            c0: p.c0,
            spd: Some(spd),
            flux_lm: p.flux_lm,
            multiplier: p.multiplier,
            tilt_deg: None,
            size_m: None,
        };
        return super::near_field::build(&nf, ctx);
    }
    let lp = LuminaireParams {
        file: None,
        table: Some(table),
        position: p.position,
        aim: p.aim,
        c0: p.c0,
        spd: Some(spd),
        flux_lm: p.flux_lm,
        multiplier: p.multiplier,
        tilt_deg: None,
    };
    Ok(Arc::new(build_luminaire(&lp, ctx)?))
}
