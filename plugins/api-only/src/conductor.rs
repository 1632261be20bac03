//! `api_conductor`: a metal, smooth or rough: GGX microfacets with visible-normal sampling and
//! the conductor Fresnel term of a spectral complex index, written from the plugin API alone.
//! The built-in `conductor` (alias `rough_conductor`) again: same parameters, defaults, checks
//! and conventions.
//!
//! | parameter   | unit     | default       | meaning                                          |
//! |-------------|----------|---------------|--------------------------------------------------|
//! | `metal`     | —        | `"aluminium"` | a bundled metal's n, k tables ([`crate::metals`]) |
//! | `n`         | unitless | —             | `(nm, n)` pairs (with `k`, instead of `metal`)   |
//! | `k`         | unitless | —             | `(nm, k)` pairs at the same wavelengths as `n`   |
//! | `roughness` | unitless | —             | perceptual roughness r, α = r²                   |
//! | `alpha`     | unitless | `0.1`         | GGX α directly (wins over `roughness`)           |
//!
//! Two-sided, like a metal sheet: from below the shading normal the same lobe is mirrored
//! through the surface (directions with their z negated). With α < 1e-3 the
//! surface is a perfect mirror (a SPECULAR event of weight F/cos θ, density 1); otherwise a
//! GLOSSY lobe f = F(wo·m) D(m) G2(wo, wi) / (4 cos θo cos θi), m the half vector, sampled from
//! the normals visible from `wo`: pdf = D_wo(m) / (4 |wo·m|).

use crate::fresnel;
use crate::ggx::Ggx;
use crate::metals::ComplexIor;
use crate::vec::{add, length2, normalize, reflect, xyz};
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    material_flags, Flags, Host, Material, ParamDoc, PluginError, PluginResult, PluginType,
    Scatter, Surface, TransportMode, Vec4f, Wavelengths, LANES,
};

/// Largest value a parameter may take: the material computes in single precision.
const MAX_F32: f64 = f32::MAX as f64;

/// Parameters (and saved state) of [`Conductor`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorParams {
    /// Bundled metal name.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub metal: Option<String>,
    /// Real part of the index, `(nm, n)`.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub n: Option<Vec<(f64, f64)>>,
    /// Imaginary part, `(nm, k)`.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub k: Option<Vec<(f64, f64)>>,
    /// Perceptual roughness r (α = r²).
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub roughness: Option<f64>,
    /// GGX α.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub alpha: Option<f64>,
}

/// The material.
pub struct Conductor {
    params: ConductorParams,
    ior: ComplexIor,
    ggx: Ggx,
}

fn bad(name: &str, what: impl std::fmt::Display) -> PluginError {
    PluginError::invalid_parameter(format!("parameter `{name}`: {what}"))
}

/// GGX α from `alpha` or `roughness` (α = r²), 0.1 when neither is given; finite and ≥ 0.
fn alpha_of(p: &ConductorParams) -> PluginResult<f32> {
    let (name, a) = match (p.alpha, p.roughness) {
        (Some(a), _) => ("alpha", a as f32),
        (None, Some(r)) => ("roughness", (r as f32) * (r as f32)),
        (None, None) => return Ok(0.1),
    };
    if !(a >= 0.0 && a.is_finite()) {
        return Err(bad(
            name,
            format!("must give a finite GGX α ≥ 0, got α = {a}"),
        ));
    }
    Ok(a)
}

fn ior_of(p: &ConductorParams) -> PluginResult<ComplexIor> {
    let (Some(n), Some(k)) = (&p.n, &p.k) else {
        let metal = p.metal.as_deref().unwrap_or("aluminium");
        return ComplexIor::metal(metal).map_err(|e| bad("metal", e));
    };
    if n.len() != k.len() || n.iter().zip(k).any(|(a, b)| a.0 != b.0) {
        return Err(bad("k", "must use the same wavelengths as `n`"));
    }
    if let Some(&(l, v)) = n
        .iter()
        .find(|&&(_, v)| !(v.is_finite() && v > 0.0 && v <= MAX_F32))
    {
        return Err(bad(
            "n",
            format!("value {v} at {l} nm must be finite and > 0"),
        ));
    }
    if let Some(&(l, v)) = k.iter().find(|&&(_, v)| !(0.0..=MAX_F32).contains(&v)) {
        return Err(bad(
            "k",
            format!("value {v} at {l} nm must be finite and ≥ 0"),
        ));
    }
    let rows: Vec<(f32, f32, f32)> = n
        .iter()
        .zip(k)
        .map(|(&(l, n), &(_, k))| (l as f32, n as f32, k as f32))
        .collect();
    ComplexIor::from_rows(&rows).map_err(|e| bad("n", e))
}

impl PluginType for Conductor {
    const TYPE_NAME: &'static str = "api_conductor";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str =
        "metal with a spectral complex IOR, smooth or rough (GGX), from the plugin API alone";
    type Params = ConductorParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional(
                "metal",
                "",
                "\"aluminium\"",
                "bundled metal: aluminium, gold, silver, copper (or al, au, ag, cu)",
            ),
            ParamDoc::optional("n", "", "—", "(nm, n) pairs; with `k` instead of `metal`"),
            ParamDoc::optional("k", "", "—", "(nm, k) pairs at the wavelengths of `n`"),
            ParamDoc::optional("roughness", "", "—", "perceptual roughness r ≥ 0; α = r²"),
            ParamDoc::optional("alpha", "", "0.1", "GGX α directly (wins over `roughness`)"),
        ]
    }

    fn new(params: ConductorParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        let ggx = Ggx::new(alpha_of(&params)?);
        let ior = ior_of(&params)?;
        Ok(Self { params, ior, ggx })
    }

    fn params(&self) -> &ConductorParams {
        &self.params
    }
}

impl Conductor {
    /// Fresnel reflectance per lane at the cosine `cos` (its absolute value).
    #[inline]
    fn fresnel(&self, cos: f32, lambda: &Wavelengths) -> [f32; LANES] {
        lambda.nm.map(|l| {
            let (n, k) = self.ior.at(l);
            fresnel::conductor(cos.abs(), n, k)
        })
    }

    /// The glossy lobe's value for `wo`, `wi` above the surface and their unit half vector `m`.
    #[inline]
    fn glossy(&self, wo: Vec4f, wi: Vec4f, m: Vec4f, lambda: &Wavelengths) -> [f32; LANES] {
        let s = self.ggx.d(m) * self.ggx.g(wo, wi) / (4.0 * wo.z * wi.z);
        self.fresnel(wo.dot(m), lambda).map(|f| f * s)
    }

    /// `wo` and `wi` turned to the side `wo` is on (z negated for both when `wo` is below).
    #[inline]
    fn to_upper(wo: Vec4f, wi: Vec4f) -> (Vec4f, Vec4f) {
        if wo.z < 0.0 {
            (flip_z(wo), flip_z(wi))
        } else {
            (wo, wi)
        }
    }

    /// The unit half vector of `wo` and `wi` when both are above the surface on a rough lobe.
    #[inline]
    fn half(&self, wo: Vec4f, wi: Vec4f) -> Option<Vec4f> {
        if self.ggx.smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let m = add(wo, wi);
        if length2(m) == 0.0 {
            return None;
        }
        Some(normalize(m))
    }
}

impl Material for Conductor {
    fn flags(&self) -> Flags {
        let lobe = if self.ggx.smooth() {
            material_flags::SPECULAR
        } else {
            material_flags::GLOSSY
        };
        // GGX with height-correlated masking and Fresnel of the half vector is symmetric in
        // wo and wi.
        lobe | material_flags::RECIPROCAL
    }

    fn sample(
        &self,
        wo: &Vec4f,
        _surface: &Surface,
        lambda: &Wavelengths,
        u: [f32; 3],
        _mode: TransportMode,
        out: &mut Scatter,
    ) -> PluginResult<bool> {
        let wo = xyz(wo);
        if wo.z == 0.0 {
            return Ok(false);
        }
        if self.ggx.smooth() {
            let wi = Vec4f::new(-wo.x, -wo.y, wo.z);
            *out = Scatter {
                wi,
                value: self.fresnel(wi.z, lambda).map(|f| f / wi.z.abs()),
                pdf: 1.0,
                flags: material_flags::SPECULAR,
                eta: 1.0,
            };
            return Ok(true);
        }
        let below = wo.z < 0.0;
        let wo = if below { flip_z(wo) } else { wo };
        let m = self.ggx.sample_visible(wo, [u[1], u[2]]);
        let wi = reflect(wo, m);
        if !(wo.z * wi.z > 0.0) {
            return Ok(false);
        }
        let cos_om = wo.dot(m);
        let pdf = self.ggx.d_visible(wo, m) / (4.0 * cos_om.abs());
        if !(pdf > 0.0) {
            return Ok(false);
        }
        *out = Scatter {
            wi: if below { flip_z(wi) } else { wi },
            value: self.glossy(wo, wi, m, lambda),
            pdf,
            flags: material_flags::GLOSSY,
            eta: 1.0,
        };
        Ok(true)
    }

    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<[f32; LANES]> {
        let (wo, wi) = Self::to_upper(xyz(wo), xyz(wi));
        Ok(match self.half(wo, wi) {
            Some(m) => self.glossy(wo, wi, m, lambda),
            None => [0.0; LANES],
        })
    }

    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<f32> {
        let (wo, wi) = Self::to_upper(xyz(wo), xyz(wi));
        Ok(match self.half(wo, wi) {
            Some(m) => self.ggx.d_visible(wo, m) / (4.0 * wo.dot(m).abs()),
            None => 0.0,
        })
    }
}

/// `w` mirrored through the surface (z negated).
#[inline]
fn flip_z(w: Vec4f) -> Vec4f {
    Vec4f::new(w.x, w.y, -w.z)
}
