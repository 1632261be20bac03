//! `fluorescent`: a diffuse surface that re-radiates light at longer wavelengths, from a
//! measured bispectral matrix or from the parametric model (see
//! [`crate::material::fluorescent`]). pt, lt and bdpt shift wavelengths at it (see
//! `integrator::fluorescence`); with fluorescence switched off it shows its reflectance only.
//!
//! | parameter       | unit              | default | meaning                                                    |
//! |-----------------|-------------------|---------|------------------------------------------------------------|
//! | `bfc`           | path or name      | —       | measured matrix: a `.BFC` file (relative to the scene file) or a bundled sample by name (`CIBA12`, `CIPLAW10`, `HERPICER`, `HERPIORA`, `IXCRLALE`, `PHP8HP1C`, `POLGREE`, `TEXTYELL`) |
//! | `reflectance`   | [0, 1]            | `0`     | model: non-fluorescent reflectance ρ(λ) (number, spec or `(nm, value)` list) |
//! | `absorption`    | [0, 1]            | —       | model: fraction a(λᵢ) of the light at λᵢ the dye absorbs (ρ + a ≤ 1) |
//! | `emission`      | SPD (normalised)  | —       | model: shape e(λₒ) of the re-emitted light                  |
//! | `quantum_yield` | [0, 1]            | `1`     | model: photons emitted per photon absorbed                  |
//! | `reradiate`     | —                 | `true`  | `false`: the non-fluorescent twin (same reflectance, no re-radiation) |
//!
//! Give either `bfc` or the model (`absorption` and `emission`, optionally `reflectance` and
//! `quantum_yield`). The model re-radiates r(λᵢ → λₒ) = a(λᵢ)·Q·(λᵢ/λₒ)·e(λₒ) for λₒ > λᵢ.

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{check, from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::fluorescent::{bundled_bfc, Fluorescent, BUNDLED_SAMPLES};
use crate::material::Material;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::bfc::BfcFile;
use crate::spectrum::bispectral_matrix::BispectralMatrix;
use crate::spectrum::fluorescence_model::FluorescenceModel;
use crate::spectrum::SpectralCurve;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "fluorescent",
    aliases: &[],
    version: 1,
    description: "diffuse fluorescent surface: measured bispectral matrix or excitation × emission × quantum yield",
    params: &[
        Param::optional(
            "bfc",
            "",
            "—",
            "measured matrix: a .BFC path (relative to the scene file) or a bundled sample name (CIBA12, CIPLAW10, HERPICER, HERPIORA, IXCRLALE, PHP8HP1C, POLGREE, TEXTYELL)",
        ),
        Param::optional(
            "reflectance",
            "",
            "0",
            "model: non-fluorescent reflectance in [0, 1]: number, spec or (nm, value) list",
        ),
        Param::optional(
            "absorption",
            "",
            "—",
            "model: fraction absorbed at each excitation wavelength, [0, 1] with reflectance + absorption ≤ 1",
        ),
        Param::optional(
            "emission",
            "",
            "—",
            "model: emission spectrum shape (normalised SPD: spec, (nm, value) list or SPD type)",
        ),
        Param::optional(
            "quantum_yield",
            "",
            "1",
            "model: photons emitted per photon absorbed, [0, 1]",
        ),
        Param::optional(
            "reradiate",
            "",
            "true",
            "false: the non-fluorescent twin (the same reflectance, no re-radiation)",
        ),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<FluorescentParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluorescentParams {
    /// Measured matrix: path or bundled name.
    #[serde(default)]
    pub bfc: Option<String>,
    /// Model: reflectance.
    #[serde(default)]
    pub reflectance: Option<Spectrum>,
    /// Model: absorption.
    #[serde(default)]
    pub absorption: Option<Spectrum>,
    /// Model: emission SPD.
    #[serde(default)]
    pub emission: Option<Spectrum>,
    /// Model: quantum yield.
    #[serde(default)]
    pub quantum_yield: Option<f64>,
    /// `false`: the non-fluorescent twin.
    #[serde(default)]
    pub reradiate: Option<bool>,
    /// A `.BFC` file's text, stored at pack time so a blob does not depend on the file. Always
    /// written (bincode is not self-describing: a skipped field could not be read back).
    #[serde(default)]
    pub bfc_text: Option<String>,
}

impl Embed for FluorescentParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        if let Some(b) = &self.bfc {
            if bundled_bfc(b).is_none() && self.bfc_text.is_none() {
                let path = ctx.resolve(b);
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| param_err("bfc", format!("{}: {e}", path.display())))?;
                self.bfc_text = Some(text);
            }
        }
        self.reflectance.embed(ctx)?;
        self.absorption.embed(ctx)?;
        self.emission.embed(ctx)
    }
}

/// A reflectance-like curve in [0, 1] (number, spec or table; not RGB, not an SPD type).
fn curve(v: &Spectrum, param: &str, ctx: &FactoryContext) -> Result<SpectralCurve, FactoryError> {
    let c = match v {
        Spectrum::Number(x) => SpectralCurve::Constant(*x),
        Spectrum::Spec(s) => {
            let r = ctx.resolve(s);
            let spec = if r.is_file() {
                r.to_string_lossy().into_owned()
            } else {
                s.clone()
            };
            SpectralCurve::parse(&spec).map_err(|e| param_err(param, e))?
        }
        Spectrum::Pairs(p) => {
            let (l, v) = p.iter().copied().unzip();
            SpectralCurve::tabulated(l, v).map_err(|e| param_err(param, e))?
        }
        Spectrum::File { nm, values, .. } => {
            SpectralCurve::tabulated(nm.clone(), values.clone()).map_err(|e| param_err(param, e))?
        }
        Spectrum::Rgb(_) | Spectrum::Typed { .. } | Spectrum::Texture(_) => {
            return Err(param_err(
                param,
                "expected a number, spec string or (nm, value) list",
            ))
        }
    };
    match &c {
        SpectralCurve::Constant(x) => check::unit_interval(param, *x, None)?,
        SpectralCurve::Tabulated { lambda, value } => {
            for (l, v) in lambda.iter().zip(value) {
                check::unit_interval(param, *v, Some(*l))?;
            }
        }
    }
    Ok(c)
}

/// Build the material.
pub fn build(
    p: &FluorescentParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    let model_given = p.absorption.is_some()
        || p.emission.is_some()
        || p.reflectance.is_some()
        || p.quantum_yield.is_some();
    if let Some(b) = &p.bfc {
        if model_given {
            return Err(param_err(
                "bfc",
                "give either `bfc` or the model (`absorption`, `emission`, `reflectance`, `quantum_yield`), not both",
            ));
        }
        let file = match (&p.bfc_text, bundled_bfc(b)) {
            (_, Some(text)) => BfcFile::parse(text, &format!("{b} (bundled)")),
            (Some(text), None) => BfcFile::parse(text, b),
            (None, None) => {
                let path = ctx.resolve(b);
                if !path.is_file() {
                    return Err(param_err(
                        "bfc",
                        format!(
                            "{} is not a file, and `{b}` is not a bundled sample ({})",
                            path.display(),
                            BUNDLED_SAMPLES.join(", ")
                        ),
                    ));
                }
                BfcFile::read(&path)
            }
        }
        .map_err(|e| param_err("bfc", e))?;
        let m = BispectralMatrix::from_bfc(&file).map_err(|e| param_err("bfc", e))?;
        return Ok(finish(Fluorescent::new(Arc::new(m)), p));
    }
    let (Some(absorption), Some(emission)) = (&p.absorption, &p.emission) else {
        return Err(FactoryError::Param(
            "give `bfc` (a measured matrix) or the model's `absorption` and `emission`".into(),
        ));
    };
    let reflectance = match &p.reflectance {
        Some(r) => curve(r, "reflectance", ctx)?,
        None => SpectralCurve::Constant(0.0),
    };
    let absorption = curve(absorption, "absorption", ctx)?;
    let (emission, _) = spd(emission, "emission", ctx)?;
    let q = p.quantum_yield.unwrap_or(1.0);
    check::unit_interval("quantum_yield", q, None)?;
    let model = FluorescenceModel::new(&ctx.item, reflectance, absorption, emission, q)
        .map_err(|e| FactoryError::Param(e.to_string()))?;
    Ok(finish(Fluorescent::from_model(model), p))
}

/// The material, or its non-fluorescent twin when `reradiate: false`.
fn finish(m: Fluorescent, p: &FluorescentParams) -> Arc<dyn Material> {
    if p.reradiate == Some(false) {
        Arc::new(m.twin())
    } else {
        Arc::new(m)
    }
}
