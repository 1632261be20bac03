//! `emissive` (alias `area_light`): a surface that emits light; an object with this material
//! becomes an area light. It does not reflect.
//!
//! | parameter   | unit         | default | meaning                                                    |
//! |-------------|--------------|---------|------------------------------------------------------------|
//! | `radiance`  | W/(m²·sr·nm) | —       | spectral radiance: a `(nm, value)` table (absolute), an SPD spec/type (normalised, then `scale` is required), or `(texture: ..)` an image |
//! | `scale`     | W/(m²·sr)    | `1` for tables | multiplier of a table; integrated radiance for a named SPD |
//! | `luminance_cd_m2` | cd/m² | —     | instead of `scale`: the luminance the surface has (the spectrum gives the shape) |
//! | `two_sided` | —            | `false` | emit from both faces                                       |
//!
//! At most one of `scale` and `luminance_cd_m2` (one is required with a named SPD). The
//! luminance sets the integrated radiance to luminance_cd_m2 / K, K the spectrum's luminous
//! efficacy (lm/W, [`crate::light::luminous`]).
//!
//! `radiance` may be an image texture, `(texture: "file")` or `(texture: (file: .., filter: ..,
//! wrap: .., uv_scale: .., uv_offset: .., encoding: .., scale: ..))`: RGB images are radiance by
//! the illuminant method (`(1, 1, 1)` is the sRGB white of film luminance 1), spectral EXR images
//! spectral radiance in W/(m²·sr·nm); `scale` × `texture.scale` multiplies it and
//! `luminance_cd_m2` is refused (see `docs/textures.md`). On a quad, light positions are drawn by
//! the texture's power; on other shapes uniformly by area, with a warning.

use crate::builtin::spectral::{spd, Spectrum};
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::material::{Emissive, Material};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "emissive",
    aliases: &["area_light"],
    version: 2,
    description: "light-emitting surface (its object becomes an area light)",
    params: &[
        Param::required("radiance", "W/(m²·sr·nm)", "spectral radiance: (nm, value) table (absolute), an SPD spec/type (normalised; needs `scale`), or (texture: ..) an image (RGB by the illuminant method, spectral EXR as radiance)"),
        Param::optional("scale", "W/(m²·sr)", "1 for tables", "multiplier of a table; the integrated radiance for a named SPD"),
        Param::optional("luminance_cd_m2", "cd/m²", "—", "instead of `scale`: the surface's luminance (CIE 1931 V(λ), 683.002 lm/W); the spectrum gives the shape"),
        Param::optional("two_sided", "", "false", "emit from both faces"),
    ],
    build: Build::Material(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<EmissiveParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmissiveParams {
    /// Spectral radiance.
    pub radiance: Spectrum,
    /// Multiplier / integrated radiance.
    #[serde(default)]
    pub scale: Option<f64>,
    /// Luminance, cd/m² (instead of `scale`).
    #[serde(default)]
    pub luminance_cd_m2: Option<f64>,
    /// Emit from both faces.
    #[serde(default)]
    pub two_sided: bool,
}

impl Embed for EmissiveParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.radiance.embed(ctx)
    }
}

/// Build the material.
pub fn build(p: &EmissiveParams, ctx: &FactoryContext) -> Result<Arc<dyn Material>, FactoryError> {
    if let Spectrum::Texture(t) = &p.radiance {
        return textured(t, p, ctx);
    }
    let (spd, raw) = spd(&p.radiance, "radiance", ctx)?;
    // Tables are absolute spectral radiance (× optional scale); named SPDs are normalised and
    // need `scale` = integrated radiance in W/(m²·sr).
    if let (Some(_), Some(_)) = (p.scale, p.luminance_cd_m2) {
        return Err(param_err(
            "luminance_cd_m2",
            "give at most one of `scale` and `luminance_cd_m2`, not both",
        ));
    }
    let scale = match (raw, p.luminance_cd_m2) {
        (_, Some(cd_m2)) => {
            crate::builtin::light::from_photometric("luminance_cd_m2", cd_m2, spd.as_ref())?
        }
        (Some(integral), None) => {
            integral * crate::builtin::finite("scale", p.scale.unwrap_or(1.0))?
        }
        (None, None) => crate::builtin::finite(
            "scale",
            p.scale.ok_or_else(|| {
                param_err(
                    "scale",
                    "required with a named SPD: integrated radiance in W/(m²·sr) (or give \
                     `luminance_cd_m2`)",
                )
            })?,
        )?,
    };
    // The renderer holds the integrated radiance as f32: refuse what would become infinite.
    let scale = crate::builtin::check::radiometric("scale", scale, "W/(m²·sr)")?;
    Ok(Arc::new(Emissive::new(spd, scale, p.two_sided)))
}

/// An emitter whose radiance is an image (see [`crate::texture::emission_texture`]): RGB
/// images by the illuminant method, spectral EXR as spectral radiance; `texture.scale` ×
/// `scale` multiplies it.
fn textured(
    t: &crate::builtin::spectral::TextureRef,
    p: &EmissiveParams,
    ctx: &FactoryContext,
) -> Result<Arc<dyn Material>, FactoryError> {
    use crate::texture::emission_texture::EmissionTexture;
    use crate::texture::image_file::{self, Encoding};
    use crate::texture::image_texture::{Filter, TexelLookup, Wrap};
    let err = |e: String| param_err("radiance", e);
    if p.luminance_cd_m2.is_some() {
        return Err(param_err(
            "luminance_cd_m2",
            "not with a texture `radiance`: the image gives the radiance (use `scale` or \
             `texture.scale` to multiply it)",
        ));
    }
    let encoding = t
        .encoding
        .as_deref()
        .map(Encoding::parse)
        .transpose()
        .map_err(err)?;
    let filter = Filter::parse(t.filter.as_deref().unwrap_or("bilinear")).map_err(err)?;
    let wrap = Wrap::parse(t.wrap.as_deref().unwrap_or("repeat")).map_err(err)?;
    let pair = |name: &str, v: Option<(f64, f64)>, d: f64| -> Result<glam::Vec2, FactoryError> {
        let (a, b) = v.unwrap_or((d, d));
        if !(a.is_finite() && b.is_finite()) {
            return Err(param_err(
                "radiance",
                format!("`texture.{name}` must be finite"),
            ));
        }
        Ok(glam::Vec2::new(a as f32, b as f32))
    };
    let uv_scale = pair("uv_scale", t.uv_scale, 1.0)?;
    let uv_offset = pair("uv_offset", t.uv_offset, 0.0)?;
    let scale = t.scale.unwrap_or(1.0) * p.scale.unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(param_err(
            "scale",
            format!("`scale` × `texture.scale` must be a finite number > 0, got {scale}"),
        ));
    }
    let scale = crate::builtin::check::radiometric("scale", scale, "W/(m²·sr)")?;
    let path = ctx.resolve(&t.file);
    let (image, report) = image_file::load(&path, encoding).map_err(err)?;
    if report.replaced > 0 {
        eprintln!(
            "warning: {}: {} pixel values were negative or not finite and were set to 0",
            path.display(),
            report.replaced
        );
    }
    let (width, height) = image.size();
    let lookup = TexelLookup {
        width,
        height,
        filter,
        wrap,
        uv_scale,
        uv_offset,
    };
    let name = path.display().to_string();
    let texture = EmissionTexture::new(name, image, lookup, scale).map_err(err)?;
    let e = Emissive::textured(Arc::new(texture), p.two_sided).map_err(err)?;
    Ok(Arc::new(e))
}
