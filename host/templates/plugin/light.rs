//! `__TYPE__`: an isotropic point light (a spectrace plugin written by `spectrace plugins new`).
//!
//! | parameter  | unit        | default       | meaning                                  |
//! |------------|-------------|---------------|------------------------------------------|
//! | `position` | scene units | `(0, 0, 0)`   | where the light is                       |
//! | `power_w`  | W           | `100`         | total radiant flux, > 0                  |
//! | `spd`      | SPD spec    | `"e"`         | spectrum, resolved by the host (∫ = 1)   |
//!
//! Radiant intensity I(λ) = Φ · spd(λ) / 4π W/(sr·nm) in every direction.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmittedRay, Flags, Host, Incident, LightSource, ParamDoc,
    PluginError, PluginResult, PluginType, RandomSample, Receiver, RepresentedBeam, Spd,
    SpdHandle, Vec3, Vec4f, Wavelengths,
};
use std::f64::consts::PI;

/// Parameters (and saved state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Position, scene units.
    pub position: [f64; 3],
    /// Radiant flux, W.
    pub power_w: f64,
    /// SPD spec resolved by the host (`"e"`, `"d65"`, `"blackbody:3000"`, …).
    pub spd: String,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            power_w: 100.0,
            spd: "e".into(),
        }
    }
}

/// The light.
pub struct PointLight {
    params: Params,
    position: Vec3,
    spd: SpdHandle,
}

impl PluginType for PointLight {
    const TYPE_NAME: &'static str = "__TYPE__";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "isotropic point light with a given flux and spectrum";
    type Params = Params;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional("position", "scene units", "(0, 0, 0)", "where the light is"),
            ParamDoc::optional("power_w", "W", "100", "total radiant flux, > 0"),
            ParamDoc::optional("spd", "SPD spec", "\"e\"", "spectrum, resolved by the host"),
        ]
    }

    fn new(params: Params, host: &Host<'_, '_>) -> PluginResult<Self> {
        let [x, y, z] = params.position;
        let position = Vec3::new(x, y, z);
        if !position.is_finite() {
            return Err(PluginError::invalid_parameter("`position` must be finite"));
        }
        if !(params.power_w.is_finite() && params.power_w > 0.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`power_w` must be a finite number > 0, got {}",
                params.power_w
            )));
        }
        let spd = host.spd(&params.spd)?;
        Ok(Self {
            params,
            position,
            spd,
        })
    }

    fn params(&self) -> &Params {
        &self.params
    }
}

/// Uniform direction on the unit sphere; density 1/(4π) sr⁻¹.
fn uniform_sphere(u0: f64, u1: f64) -> Vec3 {
    let z = 1.0 - 2.0 * u0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u1;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

impl PointLight {
    /// I(λ) per lane, W/(sr·nm).
    fn intensity(&self, lambda: &Wavelengths) -> PluginResult<[f32; 4]> {
        let mut v = [0.0; 4];
        for (out, &nm) in v.iter_mut().zip(&lambda.nm) {
            *out = (self.params.power_w * self.spd.value(nm as f64)? / (4.0 * PI)) as f32;
        }
        Ok(v)
    }
}

impl LightSource for PointLight {
    fn flags(&self) -> Flags {
        light_flags::DELTA_POSITION | light_flags::CONNECTABLE
    }

    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(Some(Box::new(self.spd.clone())))
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.params.power_w)
    }

    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        // Direction and wavelength drawn in proportion to emission: each beam carries Φ.
        let lambda = self.spd.sample(sample.u[4])?;
        Ok(Beam {
            origin: self.position,
            direction: uniform_sphere(sample.u[2], sample.u[3]),
            wavelength_nm: lambda.nm,
            power_w: self.params.power_w,
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
        let to_light = self.position - receiver.p.to_f64();
        let d2 = to_light.dot(to_light);
        if !(d2 > 0.0) {
            return Ok(false);
        }
        let intensity = self.intensity(lambda)?;
        *out = Incident {
            value: intensity.map(|i| (i as f64 / d2) as f32),
            direction: Vec4f::from_f64(to_light * (1.0 / d2.sqrt())),
            pdf: 1.0,
            point: Vec4f::from_f64(self.position),
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
        *out = EmittedRay {
            origin: Vec4f::from_f64(self.position),
            direction: Vec4f::from_f64(uniform_sphere(u[2] as f64, u[3] as f64)),
            value: self.intensity(lambda)?,
            pdf_position: 1.0,
            pdf_direction: (1.0 / (4.0 * PI)) as f32,
            normal: Vec4f::default(),
        };
        Ok(true)
    }

    fn emission_pdf(&self, _origin: &Vec4f, _direction: &Vec4f) -> PluginResult<EmissionPdf> {
        Ok(EmissionPdf {
            position: 1.0,
            direction: (1.0 / (4.0 * PI)) as f32,
        })
    }
}

spectrace_plugin_api::export_plugin! {
    name: "__NAME__",
    version: env!("CARGO_PKG_VERSION"),
    lights: [PointLight],
    spds: [],
    observers: [],
    materials: [],
}
