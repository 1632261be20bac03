//! `plastic`: a diffuse base under a smooth clear coating (Mitsuba 3's `plastic`): a sharp
//! Fresnel reflection on top of a diffuse colour that the coating darkens and saturates a
//! little. The model, its formula and its sources: [`crate::material::plastic`].
//!
//! | parameter              | unit     | default | meaning                                                  |
//! |------------------------|----------|---------|----------------------------------------------------------|
//! | `diffuse_reflectance`  | unitless | `0.5`   | the base's spectral reflectance ρ in [0, 1] (spectral value or image texture) |
//! | `specular_reflectance` | unitless | `1`     | factor on the coating's reflection in [0, 1] (1 is physical) |
//! | `int_ior`              | unitless | `1.49`  | the coating's index: number, glass name, Cauchy, Sellmeier (as `dielectric`'s `ior`) |
//! | `ext_ior`              | unitless | `1`     | the index of the medium outside (as `int_ior`)           |
//! | `nonlinear`            | —        | `false` | keep the colour shift of the light bouncing inside the coating: ρ/(1 − ρ·R_int) instead of ρ/(1 − R_int) |
//!
//! The defaults are Mitsuba's (polypropylene, 1.49), with spectrace's outside of index 1.

use crate::builtin::spectral::{texture, Ior, Spectrum};
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::plastic::Coating;
use crate::material::{Material, Plastic, SpectralIor};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::texture::{ConstantTexture, SpectralTexture};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The parameters `plastic` and `rough_plastic` share (their documentation rows).
pub(super) const DIFFUSE_REFLECTANCE: Param = Param::optional(
    "diffuse_reflectance",
    "",
    "0.5",
    "the base's spectral reflectance in [0, 1]: number, spec, (nm, value) list, (rgb: ..) or an image (texture: ..), see docs/textures.md",
);
/// See [`DIFFUSE_REFLECTANCE`].
pub(super) const SPECULAR_REFLECTANCE: Param = Param::optional(
    "specular_reflectance",
    "",
    "1",
    "factor in [0, 1] on the coating's reflection (as diffuse_reflectance; 1 is physical)",
);
/// See [`DIFFUSE_REFLECTANCE`].
pub(super) const EXT_IOR: Param = Param::optional(
    "ext_ior",
    "",
    "1",
    "the outside medium's index (as int_ior)",
);
/// See [`DIFFUSE_REFLECTANCE`].
pub(super) const NONLINEAR: Param = Param::optional(
    "nonlinear",
    "",
    "false",
    "keep the colour shift of light bouncing inside the coating (ρ/(1 − ρR) instead of ρ/(1 − R))",
);

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "plastic",
    aliases: &[],
    version: 1,
    description: "diffuse base under a smooth dielectric coating (Mitsuba's plastic)",
    params: &[
        DIFFUSE_REFLECTANCE,
        SPECULAR_REFLECTANCE,
        Param::optional("int_ior", "", "1.49", "the coating's index of refraction: number, glass name (N-BK7, N-SF11, F2, fused-silica), (cauchy: (a, b µm²)) or (sellmeier: (b: (..), c: (.. µm²)))"),
        EXT_IOR,
        NONLINEAR,
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<PlasticParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlasticParams {
    /// The base's reflectance.
    #[serde(default)]
    pub diffuse_reflectance: Option<Spectrum>,
    /// Factor on the coating's reflection.
    #[serde(default)]
    pub specular_reflectance: Option<Spectrum>,
    /// The coating's index.
    #[serde(default)]
    pub int_ior: Option<Ior>,
    /// The outside's index.
    #[serde(default)]
    pub ext_ior: Option<Ior>,
    /// Keep the internal scattering's colour shift.
    #[serde(default)]
    pub nonlinear: Option<bool>,
}

impl Embed for PlasticParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.diffuse_reflectance.embed(ctx)?;
        self.specular_reflectance.embed(ctx)
    }
}

/// Build the material.
pub fn build(p: &PlasticParams, ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type (the standard plugin library holds it so).
pub fn build_concrete(p: &PlasticParams, ctx: &FactoryContext) -> Result<Plastic, FactoryError> {
    parts(
        &p.diffuse_reflectance,
        &p.specular_reflectance,
        &p.int_ior,
        &p.ext_ior,
        p.nonlinear,
        Coating::Smooth,
        ctx,
    )
}

/// One index parameter: `ior` built as `dielectric` builds it, its errors naming `name`.
fn index(v: &Option<Ior>, name: &str, default: f64) -> Result<SpectralIor, FactoryError> {
    v.clone()
        .unwrap_or(Ior::Number(default))
        .build()
        .map_err(|e| match e {
            FactoryError::Param(m) => FactoryError::Param(m.replacen(
                "parameter `ior`",
                &format!("parameter `{name}`"),
                1,
            )),
            other => other,
        })
}

/// The plastic of both built-ins.
pub(crate) fn parts(
    diffuse: &Option<Spectrum>,
    specular: &Option<Spectrum>,
    int_ior: &Option<Ior>,
    ext_ior: &Option<Ior>,
    nonlinear: Option<bool>,
    coating: Coating,
    ctx: &FactoryContext,
) -> Result<Plastic, FactoryError> {
    let diffuse: Arc<dyn SpectralTexture> = match diffuse {
        Some(v) => texture(v, "diffuse_reflectance", ctx)?,
        None => Arc::new(ConstantTexture(0.5)),
    };
    let specular = match specular {
        Some(v) => Some(texture(v, "specular_reflectance", ctx)?),
        None => None,
    };
    let int = index(int_ior, "int_ior", 1.49)?;
    let ext = index(ext_ior, "ext_ior", 1.0)?;
    // The coating must be a real interface at every wavelength the renderer uses.
    for nm in (360..=830).step_by(10) {
        let eta = int.eval(nm as f32) / ext.eval(nm as f32);
        if !(eta.is_finite() && eta > 0.0) {
            return Err(param_err(
                "int_ior",
                format!("int_ior / ext_ior = {eta} at {nm} nm: expected a finite ratio > 0"),
            ));
        }
    }
    Ok(Plastic::new(
        diffuse,
        specular,
        int,
        ext,
        coating,
        nonlinear.unwrap_or(false),
    ))
}
