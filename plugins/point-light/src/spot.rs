//! `smooth_spot`: a point light emitting into a cone with a smooth edge.
//!
//! | parameter           | unit        | default | meaning                                          |
//! |---------------------|-------------|---------|--------------------------------------------------|
//! | `position`          | scene units | —       | apex of the cone                                 |
//! | `direction`         | —           | —       | cone axis (any length > 0)                       |
//! | `cone_angle_deg`    | degrees     | 30      | half-angle where the intensity reaches 0, (0,90] |
//! | `falloff_start_deg` | degrees     | 25      | half-angle where the falloff begins, ≤ cone      |
//! | `power_w`           | W           | —       | total radiant flux, > 0                          |
//! | `spd`               | SPD spec    | `"e"`   | spectrum, resolved by the host                   |
//!
//! Intensity I(θ, λ) = I₀ · s(cos θ) · spd(λ), with s the smoothstep from cos(cone) to
//! cos(falloff start). The flux Φ = I₀ · 2π [(1 − cos θs) + (cos θs − cos θc)/2] fixes I₀,
//! because smoothstep integrates to half its interval.

use crate::frame::{basis, finite, incident_from_point};
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmissionSample, Flags, Host, IncidentSample, LightSource,
    ParamDoc, PluginError, PluginResult, PluginType, RandomSample, SpdHandle, SpectralValues, Vec3,
    WavelengthSample, Wavelengths,
};
use std::f64::consts::PI;

/// Parameters (and saved state) of [`SpotLight`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpotParams {
    /// Apex, scene units.
    pub position: [f64; 3],
    /// Cone axis.
    pub direction: [f64; 3],
    /// Cut-off half-angle, degrees.
    #[serde(default = "default_cone")]
    pub cone_angle_deg: f64,
    /// Falloff start half-angle, degrees.
    #[serde(default = "default_falloff")]
    pub falloff_start_deg: f64,
    /// Radiant flux, W.
    pub power_w: f64,
    /// SPD spec resolved by the host.
    #[serde(default = "default_spd")]
    pub spd: String,
}

fn default_cone() -> f64 {
    30.0
}
fn default_falloff() -> f64 {
    25.0
}
fn default_spd() -> String {
    "e".to_string()
}

/// A spot light.
pub struct SpotLight {
    params: SpotParams,
    position: Vec3,
    axis: Vec3,
    tangent: Vec3,
    bitangent: Vec3,
    cos_cone: f64,
    cos_falloff: f64,
    /// I₀, W/sr per unit of normalised SPD.
    peak_intensity: f64,
    spd: SpdHandle,
}

impl PluginType for SpotLight {
    const TYPE_NAME: &'static str = "smooth_spot";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "point light emitting into a cone with a smooth edge";
    type Params = SpotParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("position", "scene units", "apex of the cone"),
            ParamDoc::required("direction", "", "cone axis (any length > 0)"),
            ParamDoc::optional(
                "cone_angle_deg",
                "degrees",
                "30",
                "half-angle where intensity reaches 0",
            ),
            ParamDoc::optional(
                "falloff_start_deg",
                "degrees",
                "25",
                "half-angle where the falloff begins",
            ),
            ParamDoc::required("power_w", "W", "total radiant flux, > 0"),
            ParamDoc::optional("spd", "SPD spec", "\"e\"", "spectrum, resolved by the host"),
        ]
    }

    fn new(params: SpotParams, host: &Host<'_, '_>) -> PluginResult<Self> {
        let position = finite("position", params.position)?;
        let axis = finite("direction", params.direction)?;
        if axis.length() == 0.0 {
            return Err(PluginError::invalid_parameter(
                "`direction` must not be zero",
            ));
        }
        let axis = axis.normalized();
        if !(params.cone_angle_deg > 0.0 && params.cone_angle_deg <= 90.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`cone_angle_deg` must be in (0, 90], got {}",
                params.cone_angle_deg
            )));
        }
        if !(params.falloff_start_deg >= 0.0 && params.falloff_start_deg <= params.cone_angle_deg) {
            return Err(PluginError::invalid_parameter(format!(
                "`falloff_start_deg` must be in [0, cone_angle_deg = {}], got {}",
                params.cone_angle_deg, params.falloff_start_deg
            )));
        }
        if !(params.power_w.is_finite() && params.power_w > 0.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`power_w` must be a finite number > 0, got {}",
                params.power_w
            )));
        }
        let cos_cone = params.cone_angle_deg.to_radians().cos();
        let cos_falloff = params.falloff_start_deg.to_radians().cos();
        let solid_angle_weight = 2.0 * PI * ((1.0 - cos_falloff) + 0.5 * (cos_falloff - cos_cone));
        let (tangent, bitangent) = basis(axis);
        let spd = host.spd(&params.spd)?;
        Ok(Self {
            peak_intensity: params.power_w / solid_angle_weight,
            params,
            position,
            axis,
            tangent,
            bitangent,
            cos_cone,
            cos_falloff,
            spd,
        })
    }

    fn params(&self) -> &SpotParams {
        &self.params
    }
}

impl SpotLight {
    /// Angular profile s(cos θ) in [0, 1].
    fn falloff(&self, cos_theta: f64) -> f64 {
        if cos_theta >= self.cos_falloff {
            return 1.0;
        }
        if cos_theta <= self.cos_cone {
            return 0.0;
        }
        let t = (cos_theta - self.cos_cone) / (self.cos_falloff - self.cos_cone);
        t * t * (3.0 - 2.0 * t)
    }

    /// Density of cone sampling, 1/sr (uniform over the cut-off cone).
    fn direction_pdf(&self) -> f64 {
        1.0 / (2.0 * PI * (1.0 - self.cos_cone))
    }

    fn sample_direction(&self, u0: f64, u1: f64) -> (Vec3, f64) {
        let cos_theta = 1.0 - u0 * (1.0 - self.cos_cone);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u1;
        let d = self.tangent * (sin_theta * phi.cos())
            + self.bitangent * (sin_theta * phi.sin())
            + self.axis * cos_theta;
        (d, cos_theta)
    }

    fn intensity(&self, cos_theta: f64, lambda: &Wavelengths) -> PluginResult<SpectralValues> {
        let s = self.peak_intensity * self.falloff(cos_theta);
        let mut v = SpectralValues::ZERO;
        for (out, &nm) in v.v.iter_mut().zip(&lambda.nm) {
            *out = s * self.spd.value(nm)?;
        }
        Ok(v)
    }
}

impl LightSource for SpotLight {
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<Beam> {
        let lambda = self.spd.sample(sample.u[4])?;
        let (direction, cos_theta) = self.sample_direction(sample.u[2], sample.u[3]);
        Ok(Beam {
            origin: self.position,
            direction,
            wavelength_nm: lambda.nm,
            // I(ω)/pdf(ω), with the wavelength drawn from the SPD itself.
            power_w: self.peak_intensity * self.falloff(cos_theta) / self.direction_pdf(),
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
        let (direction, cos_theta) = self.sample_direction(sample.u[2], sample.u[3]);
        Ok(EmissionSample {
            origin: self.position,
            direction,
            normal: Vec3::default(),
            value: self.intensity(cos_theta, lambda)?,
            pdf_position: 1.0,
            pdf_direction: self.direction_pdf(),
        })
    }

    fn emission_pdf(&self, _origin: Vec3, direction: Vec3) -> PluginResult<EmissionPdf> {
        let inside = direction.normalized().dot(self.axis) > self.cos_cone;
        Ok(EmissionPdf {
            position: 1.0,
            direction: if inside { self.direction_pdf() } else { 0.0 },
        })
    }

    fn sample_toward(
        &self,
        receiver: Vec3,
        _sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> PluginResult<IncidentSample> {
        incident_from_point(self.position, receiver, |w| {
            self.intensity(w.dot(self.axis), lambda)
        })
    }
}
