//! Building materials, lights and SPDs from a scene item's `type` and `params`.
//!
//! [`ObjectFactory`] is the extension point: the [`BuiltinFactory`] knows the built-in types and
//! the plugin registry implements the same trait for plugin types. The scene builder asks each
//! factory in turn; [`FactoryError::UnknownType`] means "not mine, ask the next one".

use super::params::{as_f64, as_f64_list, kind_of, ParamError, Params};
use super::representation::{reflectance_fn, RepresentationOptions};
use crate::color::uplift_srgb;
use crate::light::{
    ConstantEnvironment, DirectionalLight, EnvironmentLight, Light, PointLight, SpotLight,
};
use crate::material::metals::ComplexIorTable;
use crate::material::{
    ConstantTexture, CurveTexture, Emissive, Lambertian, Material, Mirror, RoughConductor,
    RoughDielectric, SmoothDielectric, SpectralIor, SpectralTexture,
};
use crate::spectrum::spec::parse_spd_spec_with;
use crate::spectrum::{parse_spd_spec, Spd, SpectralCurve, TabulatedSpd};
use ron::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an item is being built: for relative paths and messages.
#[derive(Clone, Debug, PartialEq)]
pub struct FactoryContext {
    /// Directory of the scene file; relative paths resolve against it.
    pub base_dir: PathBuf,
    /// The item being built, e.g. `material "red"`.
    pub item: String,
    /// How spectral data are represented (defaults: as written).
    pub representation: RepresentationOptions,
    /// The scene's other factories that build SPD types, asked when the item's own factory does
    /// not know an SPD type: how a built-in light or material takes a plugin's spectrum.
    pub spd_factories: SpdFactories,
}

/// Factories asked for SPD types an item's own factory does not know (see
/// [`FactoryContext::spd_factories`]); compared by identity.
#[derive(Clone, Default)]
pub struct SpdFactories(pub Vec<Arc<dyn ObjectFactory>>);

impl std::fmt::Debug for SpdFactories {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.0.iter().map(|x| x.name()).collect();
        write!(f, "SpdFactories({names:?})")
    }
}

impl PartialEq for SpdFactories {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len() && self.0.iter().zip(&other.0).all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

impl SpdFactories {
    /// The first factory that knows SPD type `type_name` builds it; `None` when none does.
    fn build(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Option<Result<Arc<dyn Spd>, FactoryError>> {
        self.0
            .iter()
            .find_map(|f| match f.spd(type_name, params, ctx) {
                Err(FactoryError::UnknownType { .. }) => None,
                other => Some(other),
            })
    }

    /// A spec string `name(param: value, …)` or `name` naming an SPD type of one of these
    /// factories (the syntax plugins use with host services); `None` when it names none.
    fn build_spec(
        &self,
        spec: &str,
        ctx: &FactoryContext,
    ) -> Option<Result<Arc<dyn Spd>, FactoryError>> {
        if self.0.is_empty() {
            return None;
        }
        let (name, params) = crate::spectrum::spec::split_type_spec(spec);
        let params: Value = ron::from_str(params).ok()?;
        self.build(name, &params, ctx)
    }
}

impl FactoryContext {
    /// `path` resolved against the scene directory.
    pub fn resolve(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base_dir.join(p)
        }
    }
}

/// Why a factory could not build an item.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FactoryError {
    /// This factory does not know the type (the builder then asks the next factory).
    #[error("unknown {kind} type `{type_name}`")]
    UnknownType {
        /// `material`, `light` or `spd`.
        kind: &'static str,
        /// The type name.
        type_name: String,
    },
    /// A parameter is missing or invalid.
    #[error("{0}")]
    Param(String),
}

impl From<ParamError> for FactoryError {
    fn from(e: ParamError) -> Self {
        FactoryError::Param(e.to_string())
    }
}

fn param_err(param: &str, message: impl std::fmt::Display) -> FactoryError {
    FactoryError::Param(format!("parameter `{param}`: {message}"))
}

/// Builds scene items from their type name and parameters. Object safe.
pub trait ObjectFactory: Send + Sync {
    /// A short name for messages (`builtin`, a plugin's name).
    fn name(&self) -> &str;

    /// Type names this factory builds, for "unknown type" messages: `(kind, type)`.
    fn known_types(&self) -> Vec<(&'static str, String)>;

    /// A material of type `type_name`.
    fn material(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError>;

    /// A (non-area) light of type `type_name`.
    fn light(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError>;

    /// A normalised SPD of type `type_name` (used where a params block gives
    /// `spd: (type: "...", params: (...))`).
    fn spd(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError>;

    /// This factory as a shared object for [`FactoryContext::spd_factories`], if it builds SPD
    /// types other factories' items may use (plugins do; the built-in types are already
    /// everywhere).
    fn shared_spd_factory(&self) -> Option<Arc<dyn ObjectFactory>> {
        None
    }

    /// A colour observer of type `type_name`, for a scene's `observer` that is not one of the
    /// built-in CIE names (plugins can ship, say, a camera's sensor curves).
    fn observer(
        &self,
        type_name: &str,
        _params: &Value,
        _ctx: &FactoryContext,
    ) -> Result<Arc<dyn crate::color::Observer>, FactoryError> {
        Err(FactoryError::UnknownType {
            kind: "observer",
            type_name: type_name.to_string(),
        })
    }
}

/// The built-in materials, lights and SPDs.
///
/// Materials: `lambertian` (`reflectance`), `mirror` (`reflectance`, default 1), `dielectric`
/// (`ior`), `rough_dielectric` (`ior`, `roughness` or `alpha`), `conductor` (`metal` or `n`+`k`
/// tables, `roughness` or `alpha`), `emissive` (`radiance`, `scale`, `two_sided`).
/// Lights: `point` (`position`, `power` W, `spd`), `spot` (`position`, `target`, `inner_angle`,
/// `outer_angle` half-angles in degrees, `power` W, `spd`), `directional` (`direction`,
/// `irradiance` W/m², `spd`), `environment` (`scale` W/(m²·sr), `radiance` SPD, default `"e"`).
/// SPD types: `spec` (`spec` string), `table` (`values` pairs).
///
/// Spectral values (`reflectance`): a number, a spec string (curve name, `colorchecker:N`, CSV
/// path), a list of `(nm, value)` pairs, or `(rgb: (r, g, b))` uplifted from linear sRGB.
/// SPDs (`spd`, `radiance`): a spec string (`d65`, `blackbody:2856`, CSV path, …; see
/// `spectrum::spec`), a list of `(nm, value)` pairs, or `(type: "...", params: (...))`.
/// IOR: a number, a glass name (`N-BK7`, `N-SF11`, `F2`, `fused-silica`), `(cauchy: (a, b))` or
/// `(sellmeier: (b: (..), c: (..)))`. Roughness: `alpha = roughness²`.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuiltinFactory;

/// Interpret a spectral reflectance-like parameter. Tables and curves follow
/// `ctx.representation` (step reading, RGB uplift); `(rgb: ..)` values are uplifts already.
pub fn spectral_texture(
    value: &Value,
    param: &str,
    ctx: &FactoryContext,
) -> Result<Arc<dyn SpectralTexture>, FactoryError> {
    if let Some(x) = as_f64(value) {
        return Ok(Arc::new(ConstantTexture(x as f32)));
    }
    let curve = match value {
        Value::String(s) => {
            let resolved = ctx.resolve(s);
            let spec = if resolved.is_file() {
                resolved.to_string_lossy().into_owned()
            } else {
                s.clone()
            };
            SpectralCurve::parse(&spec).map_err(|e| param_err(param, e))?
        }
        Value::Seq(_) => {
            let (l, v) = pairs(value, param)?;
            SpectralCurve::tabulated(l, v).map_err(|e| param_err(param, e))?
        }
        Value::Map(_) => {
            let p = Params::new(value);
            let rgb = p.get("rgb").and_then(as_f64_list).filter(|l| l.len() == 3);
            let Some(rgb) = rgb else {
                return Err(param_err(param, "expected (rgb: (r, g, b))"));
            };
            if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(param_err(param, "rgb components must lie in [0, 1]"));
            }
            let poly = uplift_srgb([rgb[0], rgb[1], rgb[2]]);
            return Ok(Arc::new(CurveTexture::new(
                format!("rgb {rgb:?}"),
                1.0,
                Arc::new(move |l| poly.value(l as f64) as f32),
            )));
        }
        other => {
            return Err(param_err(
                param,
                format!(
                    "expected a number, spec string, (nm, value) list or (rgb: ..), got {}",
                    kind_of(other)
                ),
            ))
        }
    };
    let f = reflectance_fn(curve, &ctx.representation);
    Ok(Arc::new(CurveTexture::new(
        param.to_string(),
        1.0,
        Arc::new(move |l| f(l as f64) as f32),
    )))
}

/// `(nm, value)` pairs from a list.
fn pairs(value: &Value, param: &str) -> Result<(Vec<f64>, Vec<f64>), FactoryError> {
    let Value::Seq(items) = value else {
        return Err(param_err(param, "expected a list of (nm, value) pairs"));
    };
    let mut l = Vec::with_capacity(items.len());
    let mut v = Vec::with_capacity(items.len());
    for (i, it) in items.iter().enumerate() {
        match as_f64_list(it).filter(|p| p.len() == 2) {
            Some(p) => {
                l.push(p[0]);
                v.push(p[1]);
            }
            None => {
                return Err(param_err(
                    param,
                    format!("entry {i} is not a (nm, value) pair"),
                ))
            }
        }
    }
    Ok((l, v))
}

/// An SPD parameter: the normalised SPD and, for tables, their raw integral (so absolute
/// tabulated values can be reproduced as `integral · spd(λ)`). Tables (inline, CSV, bundled) are
/// read with `ctx.representation.spd_interpolation`.
pub fn spd_param(
    factory: &dyn ObjectFactory,
    value: &Value,
    param: &str,
    ctx: &FactoryContext,
) -> Result<(Arc<dyn Spd>, Option<f64>), FactoryError> {
    match value {
        Value::String(s) => {
            let resolved = ctx.resolve(s);
            let spec = if resolved.is_file() {
                resolved.to_string_lossy().into_owned()
            } else {
                s.clone()
            };
            match parse_spd_spec_with(&spec, ctx.representation.spd_interpolation) {
                Ok(spd) => Ok((Arc::new(spd), None)),
                // Not a spec the spectrum module knows: perhaps another factory's SPD type.
                Err(e) => match ctx.spd_factories.build_spec(s, ctx) {
                    Some(r) => Ok((r.map_err(|e| param_err(param, e))?, None)),
                    None => Err(param_err(param, e)),
                },
            }
        }
        Value::Seq(_) => {
            let (l, v) = pairs(value, param)?;
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
        Value::Map(_) => {
            let p = Params::new(value);
            let type_name = p.string("type").map_err(|e| param_err(param, e))?;
            let inner = p.get("params").cloned().unwrap_or(Value::Unit);
            match factory.spd(type_name, &inner, ctx) {
                Err(unknown @ FactoryError::UnknownType { .. }) => {
                    match ctx.spd_factories.build(type_name, &inner, ctx) {
                        Some(r) => Ok((r?, None)),
                        None => Err(unknown),
                    }
                }
                other => Ok((other?, None)),
            }
        }
        other => Err(param_err(
            param,
            format!("expected a spectrum spec string, (nm, value) list or (type: .., params: ..), got {}", kind_of(other)),
        )),
    }
}

fn ior_param(value: Option<&Value>, default: f32) -> Result<SpectralIor, FactoryError> {
    let Some(value) = value else {
        return Ok(SpectralIor::Constant(default));
    };
    if let Some(x) = as_f64(value) {
        if !(x > 0.0) {
            return Err(param_err("ior", "must be positive"));
        }
        return Ok(SpectralIor::Constant(x as f32));
    }
    match value {
        Value::String(s) => SpectralIor::glass(s).map_err(|e| param_err("ior", e)),
        Value::Map(_) => {
            let p = Params::new(value);
            if let Some(c) = p.get("cauchy") {
                let l = as_f64_list(c)
                    .filter(|l| l.len() == 2)
                    .ok_or_else(|| param_err("ior.cauchy", "expected (a, b)"))?;
                return Ok(SpectralIor::Cauchy {
                    a: l[0] as f32,
                    b: l[1] as f32,
                });
            }
            if let Some(s) = p.get("sellmeier") {
                let sp = Params::new(s);
                let get = |k: &str| {
                    sp.get(k)
                        .and_then(as_f64_list)
                        .filter(|l| l.len() == 3)
                        .ok_or_else(|| {
                            param_err(&format!("ior.sellmeier.{k}"), "expected three numbers")
                        })
                };
                let (b, c) = (get("b")?, get("c")?);
                return Ok(SpectralIor::Sellmeier {
                    b: [b[0] as f32, b[1] as f32, b[2] as f32],
                    c: [c[0] as f32, c[1] as f32, c[2] as f32],
                });
            }
            Err(param_err(
                "ior",
                "expected (cauchy: (a, b)) or (sellmeier: (b: .., c: ..))",
            ))
        }
        other => Err(param_err(
            "ior",
            format!(
                "expected a number, glass name or struct, got {}",
                kind_of(other)
            ),
        )),
    }
}

fn alpha_param(p: &Params<'_>) -> Result<f32, FactoryError> {
    let a = match (p.get("alpha"), p.get("roughness")) {
        (Some(_), _) => p.f32("alpha")?,
        (None, Some(_)) => {
            let r = p.f32("roughness")?;
            r * r
        }
        (None, None) => 0.1,
    };
    if !(a >= 0.0) {
        return Err(param_err("roughness", "must be ≥ 0"));
    }
    Ok(a)
}

impl ObjectFactory for BuiltinFactory {
    fn name(&self) -> &str {
        "builtin"
    }

    fn known_types(&self) -> Vec<(&'static str, String)> {
        let m = [
            "lambertian",
            "mirror",
            "dielectric",
            "rough_dielectric",
            "conductor",
            "emissive",
        ];
        let l = ["point", "spot", "directional", "environment"];
        let s = ["spec", "table"];
        m.iter()
            .map(|t| ("material", t.to_string()))
            .chain(l.iter().map(|t| ("light", t.to_string())))
            .chain(s.iter().map(|t| ("spd", t.to_string())))
            .collect()
    }

    fn material(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError> {
        let p = Params::new(params);
        match type_name {
            "lambertian" | "diffuse" => {
                p.expect_only(&["reflectance"])?;
                let r = match p.get("reflectance") {
                    Some(v) => spectral_texture(v, "reflectance", ctx)?,
                    None => Arc::new(ConstantTexture(0.5)),
                };
                Ok(Arc::new(Lambertian::new(r)))
            }
            "mirror" => {
                p.expect_only(&["reflectance"])?;
                let r = match p.get("reflectance") {
                    Some(v) => spectral_texture(v, "reflectance", ctx)?,
                    None => Arc::new(ConstantTexture(1.0)),
                };
                Ok(Arc::new(Mirror::new(r)))
            }
            "dielectric" => {
                p.expect_only(&["ior"])?;
                Ok(Arc::new(SmoothDielectric::new(ior_param(
                    p.get("ior"),
                    1.5,
                )?)))
            }
            "rough_dielectric" => {
                p.expect_only(&["ior", "roughness", "alpha"])?;
                Ok(Arc::new(RoughDielectric::new(
                    ior_param(p.get("ior"), 1.5)?,
                    alpha_param(&p)?,
                )))
            }
            "conductor" | "rough_conductor" => {
                p.expect_only(&["metal", "n", "k", "roughness", "alpha"])?;
                let table = match (p.get("n"), p.get("k")) {
                    (Some(n), Some(k)) => {
                        let (ln, vn) = pairs(n, "n")?;
                        let (lk, vk) = pairs(k, "k")?;
                        if ln != lk {
                            return Err(param_err("k", "must use the same wavelengths as `n`"));
                        }
                        let rows: Vec<(f32, f32, f32)> = ln
                            .iter()
                            .zip(vn.iter().zip(vk.iter()))
                            .map(|(&l, (&n, &k))| (l as f32, n as f32, k as f32))
                            .collect();
                        ComplexIorTable::from_rows(&rows).map_err(|e| param_err("n", e))?
                    }
                    _ => ComplexIorTable::builtin(p.string_opt("metal")?.unwrap_or("aluminium"))
                        .map_err(|e| param_err("metal", e))?,
                };
                Ok(Arc::new(RoughConductor::new(table, alpha_param(&p)?)))
            }
            "emissive" | "area_light" => {
                p.expect_only(&["radiance", "scale", "two_sided"])?;
                let v = p
                    .get("radiance")
                    .ok_or_else(|| param_err("radiance", "missing"))?;
                let (spd, raw) = spd_param(self, v, "radiance", ctx)?;
                // Tables are absolute spectral radiance (× optional scale); named SPDs are
                // normalised and need `scale` = integrated radiance in W/(m²·sr).
                let scale = match raw {
                    Some(integral) => integral * p.f64_or("scale", 1.0)?,
                    None => p.f64("scale").map_err(|_| {
                        param_err(
                            "scale",
                            "required with a named SPD: integrated radiance in W/(m²·sr)",
                        )
                    })?,
                };
                if !(scale >= 0.0) {
                    return Err(param_err("scale", "must be ≥ 0"));
                }
                Ok(Arc::new(Emissive::new(
                    spd,
                    scale as f32,
                    p.bool_or("two_sided", false)?,
                )))
            }
            _ => Err(FactoryError::UnknownType {
                kind: "material",
                type_name: type_name.to_string(),
            }),
        }
    }

    fn light(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError> {
        let p = Params::new(params);
        let spd = |p: &Params<'_>| -> Result<Arc<dyn Spd>, FactoryError> {
            match p.get("spd") {
                Some(v) => Ok(spd_param(self, v, "spd", ctx)?.0),
                None => Ok(Arc::new(
                    parse_spd_spec("e").map_err(|e| param_err("spd", e))?,
                )),
            }
        };
        let positive = |name: &str| -> Result<f32, FactoryError> {
            let v = p.f32(name)?;
            if !(v >= 0.0) {
                return Err(param_err(name, "must be ≥ 0"));
            }
            Ok(v)
        };
        match type_name {
            "point" => {
                p.expect_only(&["position", "power", "spd"])?;
                Ok(Arc::new(PointLight::new(
                    p.vec3("position")?,
                    spd(&p)?,
                    positive("power")?,
                )))
            }
            "spot" => {
                p.expect_only(&[
                    "position",
                    "target",
                    "inner_angle",
                    "outer_angle",
                    "power",
                    "spd",
                ])?;
                let s = SpotLight::new(
                    p.vec3("position")?,
                    p.vec3("target")?,
                    p.f32_or("inner_angle", 20.0)?,
                    p.f32_or("outer_angle", 30.0)?,
                    spd(&p)?,
                    positive("power")?,
                )
                .map_err(FactoryError::Param)?;
                Ok(Arc::new(s))
            }
            "directional" => {
                p.expect_only(&["direction", "irradiance", "spd"])?;
                let d =
                    DirectionalLight::new(p.vec3("direction")?, spd(&p)?, positive("irradiance")?)
                        .map_err(|e| param_err("direction", e))?;
                Ok(Arc::new(d))
            }
            "environment" => {
                p.expect_only(&["radiance", "scale"])?;
                // As for `emissive`: a table is absolute spectral radiance (× optional
                // `scale`); a named SPD is normalised and `scale` is the integrated radiance.
                let (spd, raw) = match p.get("radiance") {
                    Some(v) => spd_param(self, v, "radiance", ctx)?,
                    None => (
                        Arc::new(parse_spd_spec("e").map_err(|e| param_err("radiance", e))?)
                            as Arc<dyn Spd>,
                        None,
                    ),
                };
                let scale = match raw {
                    Some(integral) => integral as f32 * p.f32_or("scale", 1.0)?,
                    None => positive("scale")?,
                };
                let source =
                    ConstantEnvironment::new(spd, scale).map_err(|e| param_err("scale", e))?;
                Ok(Arc::new(EnvironmentLight::new(Arc::new(source))))
            }
            _ => Err(FactoryError::UnknownType {
                kind: "light",
                type_name: type_name.to_string(),
            }),
        }
    }

    fn spd(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError> {
        let p = Params::new(params);
        match type_name {
            "spec" => {
                p.expect_only(&["spec"])?;
                let v = p.get("spec").ok_or_else(|| param_err("spec", "missing"))?;
                Ok(spd_param(self, v, "spec", ctx)?.0)
            }
            "table" => {
                p.expect_only(&["values"])?;
                let v = p
                    .get("values")
                    .ok_or_else(|| param_err("values", "missing"))?;
                Ok(spd_param(self, v, "values", ctx)?.0)
            }
            _ => Err(FactoryError::UnknownType {
                kind: "spd",
                type_name: type_name.to_string(),
            }),
        }
    }
}
