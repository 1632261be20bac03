//! `envmap`: an environment light from a latitude-longitude image (a photographed or rendered
//! sky): RGB OpenEXR, Radiance HDR (or PNG/JPEG), or a spectral OpenEXR in spectrace's layout.
//! Mapping, spectra and sampling: [`crate::light::envmap`] (the conventions of Mitsuba 3's
//! `envmap`, whose `to_world` is `transform` unchanged). A scene has at most one environment.
//!
//! | parameter     | unit | default  | meaning                                                      |
//! |---------------|------|----------|--------------------------------------------------------------|
//! | `file`        | —    | —        | image path, relative to the scene file                       |
//! | `scale`       | —    | `1`      | multiplier of the image's radiance, > 0                      |
//! | `illuminance` | lx   | —        | instead of `scale`: the illuminance the map gives on a horizontal, up-facing (+y) plane |
//! | `transform`   | —    | identity | row-major 4×4 local-to-world matrix; only its rotation is used |
//! | `encoding`    | —    | per format | `"srgb"` or `"linear"` for PNG/JPEG (default `srgb`); HDR and EXR are linear |
//!
//! An RGB pixel value `(1, 1, 1)` is the sRGB white (D65) of luminance 1 in the film's units
//! (ȳ-weighted mean spectral radiance 1 W/(m²·sr·nm)); spectral pixels are W/(m²·sr·nm).

use crate::builtin::{finite, from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::{EnvironmentLight, EnvironmentMap, Light};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::texture::image_file::{self, Encoding};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "envmap",
    aliases: &[],
    version: 1,
    description: "environment light from a latitude-longitude image (RGB or spectral)",
    params: &[
        Param::required(
            "file",
            "",
            "image path (EXR, HDR, PNG, JPEG; spectral EXR), relative to the scene file",
        ),
        Param::optional("scale", "", "1", "multiplier of the image's radiance, > 0"),
        Param::optional(
            "illuminance",
            "lx",
            "—",
            "instead of `scale`: illuminance on a horizontal up-facing (+y) plane",
        ),
        Param::optional(
            "transform",
            "",
            "identity",
            "row-major 4×4 local-to-world matrix (Mitsuba's to_world); only the rotation is used",
        ),
        Param::optional(
            "encoding",
            "",
            "srgb for PNG/JPEG",
            "\"srgb\" or \"linear\" (PNG/JPEG only)",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<EnvmapParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvmapParams {
    /// Image path.
    pub file: String,
    /// Radiance multiplier.
    #[serde(default)]
    pub scale: Option<f64>,
    /// Illuminance on a horizontal plane, lx.
    #[serde(default, alias = "illuminance_lx")]
    pub illuminance: Option<f64>,
    /// Row-major local-to-world matrix.
    #[serde(default)]
    pub transform: Option<[[f64; 4]; 4]>,
    /// Encoding of integer images.
    #[serde(default)]
    pub encoding: Option<String>,
}

impl Embed for EnvmapParams {
    /// The image is not copied into a blob: the path becomes absolute so the blob still finds it.
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.file = ctx.resolve(&self.file).to_string_lossy().into_owned();
        Ok(())
    }
}

/// Build the light.
pub fn build(p: &EnvmapParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(EnvironmentLight::new(Arc::new(source(p, ctx)?))))
}

/// The radiance source (what [`build`] wraps in an [`EnvironmentLight`]).
pub fn source(p: &EnvmapParams, ctx: &FactoryContext) -> Result<EnvironmentMap, FactoryError> {
    let encoding = p
        .encoding
        .as_deref()
        .map(Encoding::parse)
        .transpose()
        .map_err(|e| param_err("encoding", e))?;
    let path = ctx.resolve(&p.file);
    let (image, report) = image_file::load(&path, encoding).map_err(|e| param_err("file", e))?;
    if report.replaced > 0 {
        eprintln!(
            "warning: {}: {} pixel values were negative or not finite and were set to 0",
            path.display(),
            report.replaced
        );
    }
    const IDENTITY: [[f64; 4]; 4] = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let transform = p.transform.unwrap_or(IDENTITY);
    if p.scale.is_some() && p.illuminance.is_some() {
        return Err(param_err(
            "illuminance",
            "give at most one of `scale` and `illuminance`, not both",
        ));
    }
    let scale = finite("scale", p.scale.unwrap_or(1.0))?;
    if !(scale > 0.0) {
        return Err(param_err("scale", format!("must be > 0, got {scale}")));
    }
    let scale = crate::builtin::check::radiometric("scale", scale, "")?;
    let name = path.display().to_string();
    let map =
        EnvironmentMap::new(&name, image, &transform, scale).map_err(|e| param_err("file", e))?;
    let Some(lx) = p.illuminance else {
        return Ok(map);
    };
    let lx = finite("illuminance", lx)?;
    if !(lx > 0.0) {
        return Err(param_err(
            "illuminance",
            format!("must be > 0 lx, got {lx}"),
        ));
    }
    let unit = map.illuminance_at_unit_scale() * scale as f64;
    if !(unit > 0.0) {
        return Err(param_err(
            "illuminance",
            format!("{name}: the map gives no light on a horizontal up-facing plane, so an illuminance cannot set its scale"),
        ));
    }
    let s = crate::builtin::check::radiometric("illuminance", lx / unit * scale as f64, "")?;
    Ok(map.with_scale(s))
}
