//! Spectral and index-of-refraction parameter values, shared by every built-in type.
//!
//! A **spectral value** ([`Spectrum`]) is written in a scene as
//! - a number (a constant; reflectances only),
//! - a spec string: a bundled name (`d65`, `a`, `fl11`, …), `blackbody:T`, `colorchecker:N`,
//!   a CSV path (relative to the scene file), or an SPD type with parameters `name(p: v, …)`
//!   (built-in or from a plugin),
//! - a list of `(nm, value)` pairs,
//! - `(rgb: (r, g, b))`, linear sRGB in [0, 1] uplifted to a smooth spectrum (reflectances),
//! - `(type: "...", params: (...))`, an SPD type (SPDs only),
//! - `(texture: "path.png")` or `(texture: (file: "path.exr", encoding: "srgb" | "linear",
//!   filter: "bilinear" | "nearest", wrap: "repeat" | "clamp", uv_scale: (su, sv),
//!   uv_offset: (ou, ov), scale: 1.0))`, an image texture (reflectances only; see
//!   [`crate::texture::image_texture`] for the conventions and `docs/textures.md`).
//!
//! In scene syntax (human-readable serde formats) these forms are untagged; in bincode (blobs)
//! they are tagged, and a CSV file read at pack time is stored as its table
//! ([`Spectrum::File`]), so a blob does not depend on the file.
//!
//! An **IOR** ([`Ior`]) is a number, a glass name (`N-BK7`, `N-SF11`, `F2`, `fused-silica`),
//! `(cauchy: (a, b))` (b in µm²) or `(sellmeier: (b: (..), c: (..)))` (c in µm²).

use super::{check, param_err, Embed};
use crate::color::uplift_srgb;
use crate::material::SpectralIor;
use crate::scene_file::params::{as_f64, as_f64_list, kind_of, Params};
use crate::scene_file::representation::reflectance_fn;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::spec::parse_spd_spec_with;
use crate::spectrum::{Spd, SpectralCurve, TabulatedSpd};
use crate::texture::{ConstantTexture, CurveTexture, SpectralTexture};
use ron::Value;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::sync::Arc;

/// A spectral parameter value (see the module docs for the scene forms).
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// A constant.
    Number(f64),
    /// A spec string.
    Spec(String),
    /// Inline `(nm, value)` pairs.
    Pairs(Vec<(f64, f64)>),
    /// Linear sRGB, uplifted.
    Rgb([f64; 3]),
    /// An SPD type with parameters.
    Typed {
        /// Type name.
        type_name: String,
        /// Its parameters (scene syntax).
        params: Value,
    },
    /// An image texture.
    Texture(TextureRef),
    /// A CSV spectrum embedded at pack time: behaves exactly like the spec `name` did.
    File {
        /// The spec it was read from (for messages and `blob inspect`).
        name: String,
        /// Wavelengths, nm.
        nm: Vec<f64>,
        /// Values.
        values: Vec<f64>,
    },
}

/// An image texture parameter: `(texture: "file")` or `(texture: (file: …, …))`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct TextureRef {
    /// Image path, relative to the scene file (absolute once embedded in a blob).
    pub file: String,
    /// `"srgb"` or `"linear"` (default: by format).
    pub encoding: Option<String>,
    /// `"bilinear"` (default) or `"nearest"`.
    pub filter: Option<String>,
    /// `"repeat"` (default) or `"clamp"`.
    pub wrap: Option<String>,
    /// `(su, sv)`, default (1, 1).
    pub uv_scale: Option<(f64, f64)>,
    /// `(ou, ov)`, default (0, 0).
    pub uv_offset: Option<(f64, f64)>,
    /// Multiplier, default 1.
    pub scale: Option<f64>,
}

impl TextureRef {
    const KEYS: [&'static str; 7] = [
        "file",
        "encoding",
        "filter",
        "wrap",
        "uv_scale",
        "uv_offset",
        "scale",
    ];

    fn from_value(v: &Value) -> Result<Self, String> {
        if let Value::String(file) = v {
            return Ok(Self {
                file: file.clone(),
                ..Self::default()
            });
        }
        let Value::Map(_) = v else {
            return Err(format!(
                "`texture`: expected a path or (file: .., ..), got {}",
                kind_of(v)
            ));
        };
        let p = Params::new(v);
        p.expect_only(&Self::KEYS)
            .map_err(|e| format!("`texture`: {e}"))?;
        let string = |k: &str| -> Result<Option<String>, String> {
            match p.get(k) {
                None => Ok(None),
                Some(Value::String(s)) => Ok(Some(s.clone())),
                Some(o) => Err(format!(
                    "`texture.{k}`: expected a string, got {}",
                    kind_of(o)
                )),
            }
        };
        let pair = |k: &str| -> Result<Option<(f64, f64)>, String> {
            match p.get(k) {
                None => Ok(None),
                Some(x) => as_f64_list(x)
                    .filter(|l| l.len() == 2)
                    .map(|l| Some((l[0], l[1])))
                    .ok_or_else(|| format!("`texture.{k}`: expected two numbers")),
            }
        };
        Ok(Self {
            file: string("file")?.ok_or("`texture`: `file` is required")?,
            encoding: string("encoding")?,
            filter: string("filter")?,
            wrap: string("wrap")?,
            uv_scale: pair("uv_scale")?,
            uv_offset: pair("uv_offset")?,
            scale: match p.get("scale") {
                None => None,
                Some(x) => Some(as_f64(x).ok_or("`texture.scale`: expected a number")?),
            },
        })
    }

    fn is_plain(&self) -> bool {
        *self
            == Self {
                file: self.file.clone(),
                ..Self::default()
            }
    }
}

impl Serialize for TextureRef {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("TextureRef", 7)?;
        st.serialize_field("file", &self.file)?;
        macro_rules! opt {
            ($k:literal, $f:expr) => {
                match &$f {
                    Some(v) => st.serialize_field($k, v)?,
                    None => st.skip_field($k)?,
                }
            };
        }
        opt!("encoding", self.encoding);
        opt!("filter", self.filter);
        opt!("wrap", self.wrap);
        opt!("uv_scale", self.uv_scale);
        opt!("uv_offset", self.uv_offset);
        opt!("scale", self.scale);
        st.end()
    }
}

/// The tagged form of [`Spectrum`] in bincode (which cannot read untagged data).
#[derive(Serialize, Deserialize)]
enum Tagged {
    Number(f64),
    Spec(String),
    Pairs(Vec<(f64, f64)>),
    Rgb([f64; 3]),
    /// Params as RON text: bincode cannot carry a self-describing `ron::Value`.
    Typed(String, String),
    File(String, Vec<f64>, Vec<f64>),
    #[allow(clippy::type_complexity)]
    Texture(
        String,
        Option<String>,
        Option<String>,
        Option<String>,
        Option<(f64, f64)>,
        Option<(f64, f64)>,
        Option<f64>,
    ),
}

impl Spectrum {
    /// Read the scene forms from a value; the message says what was expected.
    pub fn from_value(v: &Value) -> Result<Self, String> {
        if let Some(x) = as_f64(v) {
            return Ok(Spectrum::Number(x));
        }
        match v {
            Value::String(s) => Ok(Spectrum::Spec(s.clone())),
            Value::Seq(items) => {
                let mut out = Vec::with_capacity(items.len());
                for (i, it) in items.iter().enumerate() {
                    match as_f64_list(it).filter(|p| p.len() == 2) {
                        Some(p) => out.push((p[0], p[1])),
                        None => return Err(format!("entry {i} is not a (nm, value) pair")),
                    }
                }
                Ok(Spectrum::Pairs(out))
            }
            Value::Map(_) => {
                let p = Params::new(v);
                if let Some(t) = p.get("texture") {
                    p.expect_only(&["texture"]).map_err(|e| e.to_string())?;
                    return Ok(Spectrum::Texture(TextureRef::from_value(t)?));
                }
                if let Some(rgb) = p.get("rgb") {
                    let rgb = as_f64_list(rgb)
                        .filter(|l| l.len() == 3)
                        .ok_or("expected (rgb: (r, g, b))")?;
                    return Ok(Spectrum::Rgb([rgb[0], rgb[1], rgb[2]]));
                }
                if let Some(name) = p.get("file") {
                    let Value::String(name) = name else {
                        return Err("`file` must be a string".into());
                    };
                    let table = p.get("table").ok_or("an embedded file needs `table`")?;
                    let Spectrum::Pairs(pairs) = Spectrum::from_value(table)? else {
                        return Err("`table` must be a list of (nm, value) pairs".into());
                    };
                    let (nm, values) = pairs.into_iter().unzip();
                    return Ok(Spectrum::File {
                        name: name.clone(),
                        nm,
                        values,
                    });
                }
                if let Some(t) = p.get("type") {
                    let Value::String(type_name) = t else {
                        return Err("`type` must be a string".into());
                    };
                    p.expect_only(&["type", "params"]).map_err(|e| e.to_string())?;
                    return Ok(Spectrum::Typed {
                        type_name: type_name.clone(),
                        params: p.get("params").cloned().unwrap_or(Value::Unit),
                    });
                }
                Err("expected (rgb: (r, g, b)) or (type: \"...\", params: (...))".into())
            }
            other => Err(format!(
                "expected a number, spec string, (nm, value) list, (rgb: ..) or (type: .., params: ..), got {}",
                kind_of(other)
            )),
        }
    }

    fn tagged(&self) -> Tagged {
        match self.clone() {
            Spectrum::Number(x) => Tagged::Number(x),
            Spectrum::Spec(s) => Tagged::Spec(s),
            Spectrum::Pairs(p) => Tagged::Pairs(p),
            Spectrum::Rgb(c) => Tagged::Rgb(c),
            Spectrum::Typed { type_name, params } => {
                Tagged::Typed(type_name, ron::to_string(&params).unwrap_or_default())
            }
            Spectrum::File { name, nm, values } => Tagged::File(name, nm, values),
            Spectrum::Texture(t) => Tagged::Texture(
                t.file,
                t.encoding,
                t.filter,
                t.wrap,
                t.uv_scale,
                t.uv_offset,
                t.scale,
            ),
        }
    }

    fn from_tagged(t: Tagged) -> Result<Self, String> {
        Ok(match t {
            Tagged::Number(x) => Spectrum::Number(x),
            Tagged::Spec(s) => Spectrum::Spec(s),
            Tagged::Pairs(p) => Spectrum::Pairs(p),
            Tagged::Rgb(c) => Spectrum::Rgb(c),
            Tagged::Typed(type_name, params) => Spectrum::Typed {
                type_name,
                params: ron::from_str(&params).map_err(|e| format!("bad SPD parameters: {e}"))?,
            },
            Tagged::File(name, nm, values) => Spectrum::File { name, nm, values },
            Tagged::Texture(file, encoding, filter, wrap, uv_scale, uv_offset, scale) => {
                Spectrum::Texture(TextureRef {
                    file,
                    encoding,
                    filter,
                    wrap,
                    uv_scale,
                    uv_offset,
                    scale,
                })
            }
        })
    }

    /// A spec string that names a file next to the scene, resolved; else the string itself.
    fn resolved_spec(s: &str, ctx: &FactoryContext) -> String {
        let resolved = ctx.resolve(s);
        if resolved.is_file() {
            resolved.to_string_lossy().into_owned()
        } else {
            s.to_string()
        }
    }
}

impl Serialize for Spectrum {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if !s.is_human_readable() {
            return self.tagged().serialize(s);
        }
        #[derive(Serialize)]
        struct Rgb {
            rgb: (f64, f64, f64),
        }
        #[derive(Serialize)]
        struct Typed<'a> {
            #[serde(rename = "type")]
            type_name: &'a str,
            params: &'a Value,
        }
        #[derive(Serialize)]
        struct PlainTexture<'a> {
            texture: &'a str,
        }
        #[derive(Serialize)]
        struct FullTexture<'a> {
            texture: &'a TextureRef,
        }
        #[derive(Serialize)]
        struct File<'a> {
            file: &'a str,
            table: Vec<(f64, f64)>,
        }
        match self {
            Spectrum::Number(x) => s.serialize_f64(*x),
            Spectrum::Spec(t) => s.serialize_str(t),
            Spectrum::Pairs(p) => p.serialize(s),
            Spectrum::Rgb(c) => Rgb {
                rgb: (c[0], c[1], c[2]),
            }
            .serialize(s),
            Spectrum::Typed { type_name, params } => Typed { type_name, params }.serialize(s),
            Spectrum::Texture(t) if t.is_plain() => PlainTexture { texture: &t.file }.serialize(s),
            Spectrum::Texture(t) => FullTexture { texture: t }.serialize(s),
            Spectrum::File { name, nm, values } => File {
                file: name,
                table: nm.iter().copied().zip(values.iter().copied()).collect(),
            }
            .serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Spectrum {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        if d.is_human_readable() {
            let v = Value::deserialize(d)?;
            Spectrum::from_value(&v).map_err(D::Error::custom)
        } else {
            Spectrum::from_tagged(Tagged::deserialize(d)?).map_err(D::Error::custom)
        }
    }
}

impl Embed for Spectrum {
    /// A spec naming a CSV file next to the scene becomes [`Spectrum::File`].
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        // Images are not copied into blobs (a blob's state is scene text): the path becomes
        // absolute so the blob still finds the file.
        if let Spectrum::Texture(t) = self {
            t.file = ctx.resolve(&t.file).to_string_lossy().into_owned();
            return Ok(());
        }
        if let Spectrum::Spec(s) = self {
            let resolved = ctx.resolve(s);
            if resolved.is_file() {
                let (nm, values) =
                    crate::spectrum::spec::raw_table_for_spec(&resolved.to_string_lossy())
                        .ok_or_else(|| FactoryError::Param(format!("`{s}`: not a readable table")))?
                        .map_err(|e| FactoryError::Param(format!("`{s}`: {e}")))?;
                *self = Spectrum::File {
                    name: s.clone(),
                    nm,
                    values,
                };
            }
        }
        Ok(())
    }
}

impl Embed for Option<Spectrum> {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        match self {
            Some(s) => s.embed(ctx),
            None => Ok(()),
        }
    }
}

/// A reflectance-like parameter as a texture. Tables and curves follow `ctx.representation`
/// (step reading, RGB uplift); `(rgb: ..)` values are uplifts already.
pub fn texture(
    value: &Spectrum,
    param: &str,
    ctx: &FactoryContext,
) -> Result<Arc<dyn SpectralTexture>, FactoryError> {
    let curve = match value {
        Spectrum::Number(x) => {
            check::unit_interval(param, *x, None)?;
            return Ok(Arc::new(ConstantTexture(*x as f32)));
        }
        Spectrum::Spec(s) => SpectralCurve::parse(&Spectrum::resolved_spec(s, ctx))
            .map_err(|e| param_err(param, e))?,
        Spectrum::Pairs(p) => {
            let (l, v) = p.iter().copied().unzip();
            SpectralCurve::tabulated(l, v).map_err(|e| param_err(param, e))?
        }
        Spectrum::File { nm, values, .. } => {
            SpectralCurve::tabulated(nm.clone(), values.clone()).map_err(|e| param_err(param, e))?
        }
        Spectrum::Rgb(rgb) => {
            if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(param_err(param, "rgb components must lie in [0, 1]"));
            }
            let rgb = rgb.to_vec();
            let poly = uplift_srgb([rgb[0], rgb[1], rgb[2]]);
            check::reflectance_curve(param, &[], &|l| poly.value(l))?;
            return Ok(Arc::new(CurveTexture::new(
                format!("rgb {rgb:?}"),
                1.0,
                Arc::new(move |l| poly.value(l as f64) as f32),
            )));
        }
        Spectrum::Texture(t) => return image_texture(t, param, ctx),
        Spectrum::Typed { .. } => {
            return Err(param_err(
                param,
                "expected a number, spec string, (nm, value) list or (rgb: ..), got an SPD type",
            ))
        }
    };
    // Every tabulated entry, and the curve as the renderer will read it, within [0, 1].
    let table: Vec<(f64, f64)> = match &curve {
        SpectralCurve::Tabulated { lambda, value } => {
            lambda.iter().copied().zip(value.iter().copied()).collect()
        }
        SpectralCurve::Constant(c) => vec![(f64::NAN, *c)],
    };
    for &(nm, v) in &table {
        check::unit_interval(param, v, (!nm.is_nan()).then_some(nm))?;
    }
    let f = reflectance_fn(curve, &ctx.representation);
    check::reflectance_curve(param, &[], f.as_ref())?;
    Ok(Arc::new(CurveTexture::new(
        param.to_string(),
        1.0,
        Arc::new(move |l| f(l as f64) as f32),
    )))
}

/// A reflectance image texture (see [`crate::texture::image_texture`]): RGB images uplifted
/// per texel through the precomputed table (components clamped into [0, 1], with a warning
/// when some were above 1), spectral EXR images as they are (values must lie in [0, 1]).
fn image_texture(
    t: &TextureRef,
    param: &str,
    ctx: &FactoryContext,
) -> Result<Arc<dyn SpectralTexture>, FactoryError> {
    use crate::texture::image_file::{self, Encoding, LoadedImage};
    use crate::texture::image_texture::{
        Filter, RgbReflectanceTexture, SpectralImageTexture, TexelLookup, Wrap,
    };
    let err = |e: String| param_err(param, e);
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
            return Err(param_err(param, format!("`texture.{name}` must be finite")));
        }
        Ok(glam::Vec2::new(a as f32, b as f32))
    };
    let uv_scale = pair("uv_scale", t.uv_scale, 1.0)?;
    let uv_offset = pair("uv_offset", t.uv_offset, 0.0)?;
    let scale = t.scale.unwrap_or(1.0);
    check::unit_interval(param, scale, None).map_err(|_| {
        param_err(
            param,
            format!("`texture.scale` of a reflectance must lie in [0, 1], got {scale}"),
        )
    })?;
    let path = ctx.resolve(&t.file);
    let (image, report) = image_file::load(&path, encoding).map_err(err)?;
    if report.replaced > 0 {
        eprintln!(
            "warning: {}: {} pixel values were negative or not finite and were set to 0",
            path.display(),
            report.replaced
        );
    }
    let name = path.display().to_string();
    match image {
        LoadedImage::Rgb(img) => {
            let (tex, clamped) = RgbReflectanceTexture::new(
                &name,
                &img,
                filter,
                wrap,
                uv_scale,
                uv_offset,
                scale as f32,
            );
            if clamped > 0 {
                eprintln!(
                    "warning: {name}: {clamped} colour components are above 1 and were clamped \
                     to 1 (a reflectance cannot exceed 1)"
                );
            }
            Ok(Arc::new(tex))
        }
        LoadedImage::Spectral(s) => {
            let max = s.values.iter().copied().fold(0.0f32, f32::max);
            if max as f64 * scale > 1.0 {
                return Err(param_err(
                    param,
                    format!("{name}: spectral reflectance up to {max} × scale {scale} exceeds 1"),
                ));
            }
            let lookup = TexelLookup {
                width: s.width,
                height: s.height,
                filter,
                wrap,
                uv_scale,
                uv_offset,
            };
            Ok(Arc::new(SpectralImageTexture::new(
                name,
                s,
                lookup,
                scale as f32,
                true,
            )))
        }
    }
}

/// An SPD parameter: the normalised SPD and, for inline tables, their raw integral (so
/// absolute tabulated values can be reproduced as `integral · spd(λ)`). Tables (inline, CSV,
/// bundled) are read with `ctx.representation.spd_interpolation`. SPD types are looked up in
/// the context's SPD factories (the scene's registry, then the built-in table).
pub fn spd(
    value: &Spectrum,
    param: &str,
    ctx: &FactoryContext,
) -> Result<(Arc<dyn Spd>, Option<f64>), FactoryError> {
    match value {
        Spectrum::Spec(s) => {
            let spec = Spectrum::resolved_spec(s, ctx);
            match parse_spd_spec_with(&spec, ctx.representation.spd_interpolation) {
                Ok(spd) => Ok((Arc::new(spd), None)),
                // Not a spec the spectrum module knows: perhaps another factory's SPD type.
                Err(e) => match ctx.spd_factories.build_spec(s, ctx) {
                    Some(r) => Ok((r.map_err(|e| param_err(param, e))?, None)),
                    None => Err(param_err(param, e)),
                },
            }
        }
        Spectrum::File { name, nm, values } => {
            // Exactly what reading the file gave: a normalised table named by its path.
            let t = TabulatedSpd::new(name, nm, values, ctx.representation.spd_interpolation)
                .map_err(|e| param_err(param, e))?;
            Ok((Arc::new(t), None))
        }
        Spectrum::Pairs(p) => {
            let (l, v): (Vec<f64>, Vec<f64>) = p.iter().copied().unzip();
            let t = TabulatedSpd::new(
                &format!("{} {param}", ctx.item),
                &l,
                &v,
                ctx.representation.spd_interpolation,
            )
            .map_err(|e| param_err(param, e))?;
            let raw = t.raw_integral();
            Ok((Arc::new(t), Some(raw)))
        }
        Spectrum::Typed { type_name, params } => {
            // The scene's registry first (one way in: it may provide `spec` from a library),
            // then the built-in table, which every context lists last.
            let built = ctx
                .spd_factories
                .build(type_name, params, ctx)
                .unwrap_or_else(|| {
                    Err(FactoryError::UnknownType {
                        kind: "spd",
                        type_name: type_name.clone(),
                    })
                });
            Ok((built?, None))
        }
        Spectrum::Number(_) | Spectrum::Rgb(_) => Err(param_err(
            param,
            "expected a spectrum spec string, (nm, value) list or (type: .., params: ..), got a constant",
        )),
        Spectrum::Texture(_) => Err(param_err(
            param,
            "an image texture cannot be used here: this parameter is one spectrum for the whole \
             surface (expected a spec string, (nm, value) list or (type: .., params: ..))",
        )),
    }
}

/// An index of refraction (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "IorRepr", into = "IorRepr")]
pub enum Ior {
    /// A constant.
    Number(f64),
    /// A glass by name.
    Glass(String),
    /// Cauchy `n = a + b/λ²` (λ in µm).
    Cauchy(f64, f64),
    /// Sellmeier coefficients (c in µm²).
    Sellmeier {
        /// B₁..B₃.
        b: [f64; 3],
        /// C₁..C₃, µm².
        c: [f64; 3],
    },
}

/// Serde bridge: the scene forms when human readable, tagged otherwise.
#[derive(Clone)]
struct IorRepr(Ior);

impl From<IorRepr> for Ior {
    fn from(r: IorRepr) -> Ior {
        r.0
    }
}

impl From<Ior> for IorRepr {
    fn from(i: Ior) -> IorRepr {
        IorRepr(i)
    }
}

#[derive(Serialize, Deserialize)]
enum IorTagged {
    Number(f64),
    Glass(String),
    Cauchy(f64, f64),
    Sellmeier([f64; 3], [f64; 3]),
}

impl Serialize for IorRepr {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if !s.is_human_readable() {
            return match &self.0 {
                Ior::Number(x) => IorTagged::Number(*x),
                Ior::Glass(g) => IorTagged::Glass(g.clone()),
                Ior::Cauchy(a, b) => IorTagged::Cauchy(*a, *b),
                Ior::Sellmeier { b, c } => IorTagged::Sellmeier(*b, *c),
            }
            .serialize(s);
        }
        #[derive(Serialize)]
        struct Cauchy {
            cauchy: (f64, f64),
        }
        #[derive(Serialize)]
        struct SellB {
            b: [f64; 3],
            c: [f64; 3],
        }
        #[derive(Serialize)]
        struct Sell {
            sellmeier: SellB,
        }
        match &self.0 {
            Ior::Number(x) => s.serialize_f64(*x),
            Ior::Glass(g) => s.serialize_str(g),
            Ior::Cauchy(a, b) => Cauchy { cauchy: (*a, *b) }.serialize(s),
            Ior::Sellmeier { b, c } => Sell {
                sellmeier: SellB { b: *b, c: *c },
            }
            .serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for IorRepr {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        if !d.is_human_readable() {
            return Ok(IorRepr(match IorTagged::deserialize(d)? {
                IorTagged::Number(x) => Ior::Number(x),
                IorTagged::Glass(g) => Ior::Glass(g),
                IorTagged::Cauchy(a, b) => Ior::Cauchy(a, b),
                IorTagged::Sellmeier(b, c) => Ior::Sellmeier { b, c },
            }));
        }
        let v = Value::deserialize(d)?;
        ior_from_value(&v).map(IorRepr).map_err(D::Error::custom)
    }
}

fn ior_from_value(value: &Value) -> Result<Ior, String> {
    if let Some(x) = as_f64(value) {
        return Ok(Ior::Number(x));
    }
    match value {
        Value::String(s) => Ok(Ior::Glass(s.clone())),
        Value::Map(_) => {
            let p = Params::new(value);
            if let Some(c) = p.get("cauchy") {
                let l = as_f64_list(c)
                    .filter(|l| l.len() == 2)
                    .ok_or("`cauchy`: expected (a, b)")?;
                return Ok(Ior::Cauchy(l[0], l[1]));
            }
            if let Some(s) = p.get("sellmeier") {
                let sp = Params::new(s);
                let get = |k: &str| {
                    sp.get(k)
                        .and_then(as_f64_list)
                        .filter(|l| l.len() == 3)
                        .map(|l| [l[0], l[1], l[2]])
                        .ok_or_else(|| format!("`sellmeier.{k}`: expected three numbers"))
                };
                return Ok(Ior::Sellmeier {
                    b: get("b")?,
                    c: get("c")?,
                });
            }
            Err("expected (cauchy: (a, b)) or (sellmeier: (b: .., c: ..))".into())
        }
        other => Err(format!(
            "expected a number, glass name or struct, got {}",
            kind_of(other)
        )),
    }
}

impl Ior {
    /// The renderer's IOR: finite and > 0 at every whole nm of the renderer's range (a
    /// Sellmeier pole or a negative Cauchy value inside the range is refused).
    pub fn build(&self) -> Result<SpectralIor, FactoryError> {
        let finite_all = |xs: &[f64]| {
            xs.iter()
                .all(|x| x.is_finite() && x.abs() <= check::MAX_F32)
        };
        match self {
            Ior::Number(x) if !(finite_all(&[*x]) && *x > 0.0) => {
                return Err(param_err(
                    "ior",
                    format!("must be a finite number > 0, got {x}"),
                ))
            }
            Ior::Cauchy(a, b) if !finite_all(&[*a, *b]) => {
                return Err(param_err("ior", "`cauchy` coefficients must be finite"))
            }
            Ior::Sellmeier { b, c } if !finite_all(b) || !finite_all(c) => {
                return Err(param_err("ior", "`sellmeier` coefficients must be finite"))
            }
            Ior::Cauchy(a, b) => {
                // n(λ) = a + b/λ², λ in µm.
                check::ior_curve("ior", &|nm| a + b / (nm * 1e-3).powi(2))?;
            }
            Ior::Sellmeier { b, c } => {
                // n²(λ) = 1 + Σ Bᵢλ²/(λ² − Cᵢ), λ in µm; a pole or n² ≤ 0 is not a real index.
                check::ior_curve("ior", &|nm| {
                    let l2 = (nm * 1e-3).powi(2);
                    let n2 = 1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f64>();
                    if n2 > 0.0 {
                        n2.sqrt()
                    } else {
                        n2
                    }
                })?;
            }
            _ => {}
        }
        Ok(match self {
            Ior::Number(x) => SpectralIor::Constant(*x as f32),
            Ior::Glass(s) => SpectralIor::glass(s).map_err(|e| param_err("ior", e))?,
            Ior::Cauchy(a, b) => SpectralIor::Cauchy {
                a: *a as f32,
                b: *b as f32,
            },
            Ior::Sellmeier { b, c } => SpectralIor::Sellmeier {
                b: [b[0] as f32, b[1] as f32, b[2] as f32],
                c: [c[0] as f32, c[1] as f32, c[2] as f32],
            },
        })
    }
}

/// Microfacet roughness from `alpha` or `roughness` (`alpha = roughness²`), default α = 0.1.
pub fn alpha(alpha: Option<f64>, roughness: Option<f64>) -> Result<f32, FactoryError> {
    let a = match (alpha, roughness) {
        (Some(a), _) => super::finite("alpha", a)? as f32,
        (None, Some(r)) => {
            let r = super::finite("roughness", r)? as f32;
            r * r
        }
        (None, None) => 0.1,
    };
    if !(a >= 0.0 && a.is_finite()) {
        let which = if alpha.is_some() {
            "alpha"
        } else {
            "roughness"
        };
        return Err(param_err(
            which,
            format!("must give a finite GGX α ≥ 0, got α = {a}"),
        ));
    }
    Ok(a)
}
