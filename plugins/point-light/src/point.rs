//! `isotropic_point`: an isotropic point light.
//!
//! | parameter  | unit        | default | meaning                                        |
//! |------------|-------------|---------|------------------------------------------------|
//! | `position` | scene units | —       | where the light is                             |
//! | `power_w`  | W           | —       | total radiant flux, > 0                        |
//! | `spd`      | SPD spec    | `"e"`   | spectrum, resolved by the host (∫ = 1)         |
//!
//! Radiant intensity I(λ) = Φ · spd(λ) / 4π  W/(sr·nm) in every direction.

use crate::frame::{emitted_from_point, finite, incident_from_point, uniform_sphere};
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmittedRay, Flags, Host, Incident, LightSource, ParamDoc,
    PluginError, PluginResult, PluginType, RandomSample, Receiver, RepresentedBeam, Spd, SpdHandle,
    Vec3, Vec4f, Wavelengths,
};
use std::f64::consts::PI;

/// Parameters (and saved state) of [`PointLight`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PointParams {
    /// Position, scene units.
    pub position: [f64; 3],
    /// Radiant flux, W.
    pub power_w: f64,
    /// SPD spec resolved by the host.
    #[serde(default = "default_spd")]
    pub spd: String,
}

fn default_spd() -> String {
    "e".to_string()
}

/// An isotropic point light.
pub struct PointLight {
    params: PointParams,
    position: Vec3,
    spd: SpdHandle,
}

impl PluginType for PointLight {
    const TYPE_NAME: &'static str = "isotropic_point";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "isotropic point light with a given flux and spectrum";
    type Params = PointParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("position", "scene units", "where the light is"),
            ParamDoc::required("power_w", "W", "total radiant flux, > 0"),
            ParamDoc::optional("spd", "SPD spec", "\"e\"", "spectrum, resolved by the host"),
        ]
    }

    fn new(params: PointParams, host: &Host<'_, '_>) -> PluginResult<Self> {
        let position = finite("position", params.position)?;
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

    fn params(&self) -> &PointParams {
        &self.params
    }
}

impl PointLight {
    fn intensity(&self, lambda: &Wavelengths) -> PluginResult<[f64; 4]> {
        let mut v = [0.0; 4];
        for (out, &nm) in v.iter_mut().zip(&lambda.nm) {
            *out = self.params.power_w * self.spd.value(nm as f64)? / (4.0 * PI);
        }
        Ok(v)
    }
}

impl LightSource for PointLight {
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        let lambda = self.spd.sample(sample.u[4])?;
        Ok(Beam {
            origin: self.position,
            direction: uniform_sphere(sample.u[2], sample.u[3]),
            wavelength_nm: lambda.nm,
            // Direction and wavelength are drawn in proportion to emission: each beam carries Φ.
            power_w: self.params.power_w,
            source_id: 0,
        }
        .into())
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.params.power_w)
    }

    fn flags(&self) -> Flags {
        light_flags::DELTA_POSITION | light_flags::CONNECTABLE
    }

    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(Some(Box::new(self.spd.clone())))
    }

    fn sample_emission(
        &self,
        u: [f32; 4],
        lambda: &Wavelengths,
        out: &mut EmittedRay,
    ) -> PluginResult<bool> {
        let direction = uniform_sphere(u[2] as f64, u[3] as f64);
        let value = self.intensity(lambda)?;
        emitted_from_point(self.position, direction, value, 1.0 / (4.0 * PI), out);
        Ok(true)
    }

    fn emission_pdf(&self, _origin: &Vec4f, _direction: &Vec4f) -> PluginResult<EmissionPdf> {
        Ok(EmissionPdf {
            position: 1.0,
            direction: (1.0 / (4.0 * PI)) as f32,
        })
    }

    fn sample_toward(
        &self,
        receiver: &Receiver,
        _u: [f32; 2],
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> PluginResult<bool> {
        incident_from_point(self.position, receiver, |_| self.intensity(lambda), out)
    }
}
