//! `isotropic_point`: an isotropic point light.
//!
//! | parameter  | unit        | default | meaning                                        |
//! |------------|-------------|---------|------------------------------------------------|
//! | `position` | scene units | —       | where the light is                             |
//! | `power_w`  | W           | —       | total radiant flux, > 0                        |
//! | `spd`      | SPD spec    | `"e"`   | spectrum, resolved by the host (∫ = 1)         |
//!
//! Radiant intensity I(λ) = Φ · spd(λ) / 4π  W/(sr·nm) in every direction.

use crate::frame::{finite, incident_from_point, uniform_sphere};
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmissionSample, Flags, Host, IncidentSample, LightSource,
    ParamDoc, PluginError, PluginResult, PluginType, RandomSample, SpdHandle, SpectralValues, Vec3,
    WavelengthSample, Wavelengths,
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
    fn intensity(&self, lambda: &Wavelengths) -> PluginResult<SpectralValues> {
        let mut v = SpectralValues::ZERO;
        for (out, &nm) in v.v.iter_mut().zip(&lambda.nm) {
            *out = self.params.power_w * self.spd.value(nm)? / (4.0 * PI);
        }
        Ok(v)
    }
}

impl LightSource for PointLight {
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<Beam> {
        let lambda = self.spd.sample(sample.u[4])?;
        Ok(Beam {
            origin: self.position,
            direction: uniform_sphere(sample.u[2], sample.u[3]),
            wavelength_nm: lambda.nm,
            // Direction and wavelength are drawn in proportion to emission: each beam carries Φ.
            power_w: self.params.power_w,
            source_id: 0,
        })
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.params.power_w)
    }

    fn capabilities(&self) -> Flags {
        light_flags::DELTA_POSITION | light_flags::CONNECTABLE
    }

    fn sample_wavelength(&self, u: f64) -> PluginResult<WavelengthSample> {
        self.spd.sample(u)
    }

    fn wavelength_pdf(&self, nm: f64) -> PluginResult<f64> {
        self.spd.pdf(nm)
    }

    fn sample_emission(
        &self,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> PluginResult<EmissionSample> {
        Ok(EmissionSample {
            origin: self.position,
            direction: uniform_sphere(sample.u[2], sample.u[3]),
            normal: Vec3::default(),
            value: self.intensity(lambda)?,
            pdf_position: 1.0,
            pdf_direction: 1.0 / (4.0 * PI),
        })
    }

    fn emission_pdf(&self, _origin: Vec3, _direction: Vec3) -> PluginResult<EmissionPdf> {
        Ok(EmissionPdf {
            position: 1.0,
            direction: 1.0 / (4.0 * PI),
        })
    }

    fn sample_toward(
        &self,
        receiver: Vec3,
        _sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> PluginResult<IncidentSample> {
        incident_from_point(self.position, receiver, |_| self.intensity(lambda))
    }
}
