//! `api_spot`: a spot light with a smooth falloff between an inner and an outer cone, written
//! from the plugin API alone. The built-in `spot` again: same parameters, defaults, checks and
//! conventions.
//!
//! | parameter     | unit        | default | meaning                                        |
//! |---------------|-------------|---------|------------------------------------------------|
//! | `position`    | scene units | —       | where the light is                             |
//! | `target`      | scene units | —       | a point on the cone's axis                     |
//! | `inner_angle` | degrees     | `20`    | half-angle of full intensity                   |
//! | `outer_angle` | degrees     | `30`    | half-angle where the intensity reaches zero    |
//! | `power`       | W           | —       | total radiant flux, ≥ 0                        |
//! | `flux_lm`     | lm          | —       | or: total luminous flux, ≥ 0                   |
//! | `intensity_cd`| cd          | —       | or: luminous intensity on the axis, ≥ 0        |
//! | `spd`         | —           | `"e"`   | emission spectrum: an SPD spec the host resolves |
//!
//! Intensity I(ω, λ) = I₀ · s(cos θ) · S(λ), θ the angle to the axis, s the smoothstep from 0 at
//! the outer half-angle to 1 at the inner one, S the normalised spectrum. s averages ½ over
//! cos θ, so the falloff's solid angle is Ω = 2π[(1 − cos θi) + (cos θi − cos θo)/2] and
//! I₀ = Φ/Ω. Exactly one of `power` (Φ in W), `flux_lm` (Φ = lm / K) and `intensity_cd`
//! (I₀ = cd / K W/sr, Φ = I₀ Ω) is given, K the spectrum's luminous efficacy
//! ([`crate::photometry`]). Emitted rays are drawn uniformly in the outer cone.
//!
//! Unlike the built-in, `spd` takes only a spec string (which covers SPD types as
//! `name(p: v, ..)`): the host's SPD service resolves specs, and an inline `(nm, value)` list
//! would need the scene's interpolation setting, which a plugin does not see; a CSV file does
//! the same.

use crate::photometry::efficacy_lm_per_w;
use crate::spectrum::EmissionSpd;
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmittedRay, Flags, Host, Incident, LightSource, ParamDoc,
    PluginError, PluginResult, PluginType, RandomSample, Receiver, RepresentedBeam, Spd, Vec3,
    Vec4f, Wavelengths, LANES,
};
use std::f32::consts::PI;

/// Largest value a parameter may take: the light computes in single precision.
const MAX_F32: f64 = f32::MAX as f64;

/// Parameters (and saved state) of [`Spot`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpotParams {
    /// Position, scene units.
    pub position: [f64; 3],
    /// A point on the axis, scene units.
    pub target: [f64; 3],
    /// Inner half-angle, degrees.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub inner_angle: Option<f64>,
    /// Outer half-angle, degrees.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub outer_angle: Option<f64>,
    /// Radiant flux, W.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub power: Option<f64>,
    /// Luminous flux, lm.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub flux_lm: Option<f64>,
    /// Luminous intensity on the axis, cd.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub intensity_cd: Option<f64>,
    /// Emission spectrum.
    #[serde(default, deserialize_with = "crate::params::bare")]
    pub spd: Option<String>,
}

/// The light.
pub struct Spot {
    params: SpotParams,
    position: Vec4f,
    /// Orthonormal frame (s, t, axis).
    s: Vec4f,
    t: Vec4f,
    axis: Vec4f,
    cos_inner: f32,
    cos_outer: f32,
    /// Radiant flux as held (f32), W.
    power: f32,
    /// Peak intensity I₀, W/sr.
    i0: f32,
    spd: EmissionSpd,
}

fn bad(name: &str, what: impl std::fmt::Display) -> PluginError {
    PluginError::invalid_parameter(format!("parameter `{name}`: {what}"))
}

fn point(name: &str, v: [f64; 3]) -> PluginResult<Vec4f> {
    if v.iter().all(|c| c.is_finite() && c.abs() <= MAX_F32) {
        Ok(Vec4f::new(v[0] as f32, v[1] as f32, v[2] as f32))
    } else {
        Err(bad(
            name,
            format!("must be three finite numbers, got {v:?}"),
        ))
    }
}

fn finite(name: &str, x: f64) -> PluginResult<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(bad(name, "must be finite"))
    }
}

/// Solid angle (sr) of the falloff of a spot with half-angles `inner_deg` ≤ `outer_deg`.
pub fn falloff_solid_angle_sr(inner_deg: f64, outer_deg: f64) -> f64 {
    let (ci, co) = (inner_deg.to_radians().cos(), outer_deg.to_radians().cos());
    2.0 * std::f64::consts::PI * ((1.0 - ci) + 0.5 * (ci - co))
}

/// The radiant flux (W) the parameters ask for, from whichever of W, lm, cd was given.
fn flux_w(p: &SpotParams, inner: f64, outer: f64, spd: &dyn Spd) -> PluginResult<f64> {
    let given = [
        ("power", p.power),
        ("flux_lm", p.flux_lm),
        ("intensity_cd", p.intensity_cd),
    ];
    let present: Vec<usize> = (0..3).filter(|&i| given[i].1.is_some()).collect();
    let [i] = present[..] else {
        return Err(PluginError::invalid_parameter(format!(
            "give exactly one of `power`, `flux_lm`, `intensity_cd` ({} given)",
            present.len()
        )));
    };
    let (name, value) = (given[i].0, given[i].1.unwrap_or(0.0));
    if i == 0 {
        return Ok(value);
    }
    if !(value.is_finite() && value >= 0.0) {
        return Err(bad(name, format!("must be finite and ≥ 0, got {value}")));
    }
    let k = efficacy_lm_per_w(spd)?;
    if !(k > 0.0) {
        return Err(bad(
            name,
            "the light's spectrum has no visible part (luminous efficacy 0 lm/W), so a \
             photometric value cannot set its power; give `power` in W",
        ));
    }
    Ok(if i == 1 {
        value / k
    } else {
        value / k * falloff_solid_angle_sr(inner, outer)
    })
}

/// An orthonormal frame (s, t) around the unit `n` (Duff et al. 2017, "Building an orthonormal
/// basis, revisited": no branch on the sign of `n.z`), as the built-in lights orient theirs.
fn frame(n: Vec4f) -> (Vec4f, Vec4f) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec4f::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec4f::new(b, sign + n.y * n.y * a, -n.y),
    )
}

impl PluginType for Spot {
    const TYPE_NAME: &'static str = "api_spot";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str =
        "spot light with a smooth falloff between two cones, from the plugin API alone";
    type Params = SpotParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("position", "scene units", "where the light is, (x, y, z)"),
            ParamDoc::required("target", "scene units", "a point on the cone axis"),
            ParamDoc::optional(
                "inner_angle",
                "degrees",
                "20",
                "half-angle of full intensity",
            ),
            ParamDoc::optional(
                "outer_angle",
                "degrees",
                "30",
                "half-angle where the intensity reaches zero",
            ),
            ParamDoc::optional(
                "power",
                "W",
                "—",
                "total radiant flux, ≥ 0; exactly one of `power`, `flux_lm`, `intensity_cd`",
            ),
            ParamDoc::optional(
                "flux_lm",
                "lm",
                "—",
                "or: total luminous flux, ≥ 0 (CIE 1931 V(λ), 683.002 lm/W)",
            ),
            ParamDoc::optional(
                "intensity_cd",
                "cd",
                "—",
                "or: luminous intensity on the axis (inside the inner cone), ≥ 0",
            ),
            ParamDoc::optional(
                "spd",
                "",
                "\"e\"",
                "emission spectrum: an SPD spec the host resolves (a bundled name, blackbody:T, \
                 a CSV path, an SPD type `name(p: v, ..)`)",
            ),
        ]
    }

    fn new(params: SpotParams, host: &Host<'_, '_>) -> PluginResult<Self> {
        let position = point("position", params.position)?;
        let target = point("target", params.target)?;
        let d = Vec4f::new(
            target.x - position.x,
            target.y - position.y,
            target.z - position.z,
        );
        let len = d.dot(d).sqrt();
        if !(len > 0.0) {
            return Err(bad(
                "target",
                format!(
                    "must differ from `position`, both are {:?}",
                    params.position
                ),
            ));
        }
        let inner = finite("inner_angle", params.inner_angle.unwrap_or(20.0))?;
        let outer = finite("outer_angle", params.outer_angle.unwrap_or(30.0))?;
        if !(outer > 0.0 && outer < 180.0) {
            return Err(bad(
                "outer_angle",
                format!("{outer}° is outside (0, 180) degrees"),
            ));
        }
        if !(inner >= 0.0 && inner <= outer) {
            return Err(bad(
                "inner_angle",
                format!("{inner}° is outside [0, outer_angle = {outer}] degrees"),
            ));
        }
        let handle = host
            .spd(params.spd.as_deref().unwrap_or("e"))
            .map_err(|e| bad("spd", e))?;
        let flux = flux_w(&params, inner, outer, &handle)?;
        if !(0.0..=MAX_F32).contains(&flux) {
            return Err(bad(
                "power",
                format!("{flux} W must be finite, ≥ 0 and at most {MAX_F32:e} W"),
            ));
        }
        let power = flux as f32;
        // As the built-in normalises (glam: times the reciprocal of the length).
        let inv = 1.0 / len;
        let axis = Vec4f::new(d.x * inv, d.y * inv, d.z * inv);
        let (s, t) = frame(axis);
        let cos_inner = (inner as f32).to_radians().cos();
        let cos_outer = (outer as f32).to_radians().cos();
        let solid = 2.0 * PI * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_outer));
        Ok(Self {
            spd: EmissionSpd::new(handle)?,
            params,
            position,
            s,
            t,
            axis,
            cos_inner,
            cos_outer,
            power,
            i0: power / solid,
        })
    }

    fn params(&self) -> &SpotParams {
        &self.params
    }
}

impl Spot {
    /// The falloff s(cos θ) in [0, 1].
    #[inline]
    fn falloff(&self, cos: f32) -> f32 {
        if cos >= self.cos_inner {
            return 1.0;
        }
        if cos <= self.cos_outer {
            return 0.0;
        }
        let x = (cos - self.cos_outer) / (self.cos_inner - self.cos_outer);
        x * x * (3.0 - 2.0 * x)
    }

    /// Intensity per lane (W/(sr·nm)) along the unit direction `w` leaving the light.
    #[inline]
    fn intensity(&self, w: Vec4f, lambda: &Wavelengths) -> PluginResult<[f32; LANES]> {
        let s = self.i0 * self.falloff(w.dot(self.axis));
        Ok(self.spd.lanes(&lambda.nm)?.map(|v| v * s))
    }

    /// Density of the emitted directions, uniform in the outer cone, 1/sr.
    fn direction_pdf(&self) -> f32 {
        1.0 / (2.0 * PI * (1.0 - self.cos_outer))
    }

    /// A direction uniform in the outer cone from `u` in [0, 1)².
    fn cone_direction(&self, u: [f32; 2]) -> Vec4f {
        let cos = 1.0 - u[0] * (1.0 - self.cos_outer);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let (x, y) = (sin * phi.cos(), sin * phi.sin());
        Vec4f::new(
            self.s.x * x + self.t.x * y + self.axis.x * cos,
            self.s.y * x + self.t.y * y + self.axis.y * cos,
            self.s.z * x + self.t.z * y + self.axis.z * cos,
        )
    }
}

impl LightSource for Spot {
    fn flags(&self) -> Flags {
        light_flags::DELTA_POSITION | light_flags::CONNECTABLE
    }

    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(Some(Box::new(self.spd.handle().clone())))
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.power as f64)
    }

    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        let lambda = self.spd.handle().sample(sample.u[4])?;
        let w = self.cone_direction([sample.u[2] as f32, sample.u[3] as f32]);
        let p = self.position;
        Ok(Beam {
            origin: Vec3::new(p.x as f64, p.y as f64, p.z as f64),
            direction: Vec3::new(w.x as f64, w.y as f64, w.z as f64),
            wavelength_nm: lambda.nm,
            // I(ω)/pdf(ω): the wavelength is drawn from the normalised spectrum itself.
            power_w: (self.i0 * self.falloff(w.dot(self.axis)) / self.direction_pdf()) as f64,
            source_id: 0,
        }
        .into())
    }

    fn sample_toward(
        &self,
        receiver: &Receiver,
        _u: [f32; 2],
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> PluginResult<bool> {
        let d = Vec4f::new(
            self.position.x - receiver.p.x,
            self.position.y - receiver.p.y,
            self.position.z - receiver.p.z,
        );
        let dist2 = d.dot(d);
        if !(dist2 > 0.0) {
            return Ok(false);
        }
        let dist = dist2.sqrt();
        let wi = Vec4f::new(d.x / dist, d.y / dist, d.z / dist);
        let i = self.intensity(Vec4f::new(-wi.x, -wi.y, -wi.z), lambda)?;
        if i.iter().all(|&v| v == 0.0) {
            return Ok(false);
        }
        *out = Incident {
            value: i.map(|v| v / dist2),
            direction: wi,
            pdf: 1.0,
            point: self.position,
            point_error: Vec4f::default(),
            normal: Vec4f::default(),
        };
        Ok(true)
    }

    fn sample_emission(
        &self,
        u: [f32; 4],
        lambda: &Wavelengths,
        out: &mut EmittedRay,
    ) -> PluginResult<bool> {
        let w = self.cone_direction([u[2], u[3]]);
        *out = EmittedRay {
            origin: self.position,
            direction: w,
            value: self.intensity(w, lambda)?,
            pdf_position: 1.0,
            pdf_direction: self.direction_pdf(),
            normal: Vec4f::default(),
        };
        Ok(true)
    }

    fn emission_pdf(&self, _origin: &Vec4f, direction: &Vec4f) -> PluginResult<EmissionPdf> {
        let inv = 1.0 / direction.dot(*direction).sqrt();
        let cos =
            Vec4f::new(direction.x * inv, direction.y * inv, direction.z * inv).dot(self.axis);
        Ok(EmissionPdf {
            position: 1.0,
            direction: if cos >= self.cos_outer {
                self.direction_pdf()
            } else {
                0.0
            },
        })
    }
}
