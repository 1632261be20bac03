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

use crate::frame::{basis, emitted_from_point, finite, incident_from_point};
use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmittedRay, Flags, Host, Incident, LightSource, ParamDoc,
    PluginError, PluginResult, PluginType, RandomSample, Receiver, RepresentedBeam, Spd, SpdHandle,
    Vec3, Vec4f, Wavelengths,
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

    fn intensity(&self, cos_theta: f64, lambda: &Wavelengths) -> PluginResult<[f64; 4]> {
        let s = self.peak_intensity * self.falloff(cos_theta);
        let mut v = [0.0; 4];
        for (out, &nm) in v.iter_mut().zip(&lambda.nm) {
            *out = s * self.spd.value(nm as f64)?;
        }
        Ok(v)
    }
}

impl LightSource for SpotLight {
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        let lambda = self.spd.sample(sample.u[4])?;
        let (direction, cos_theta) = self.sample_direction(sample.u[2], sample.u[3]);
        Ok(Beam {
            origin: self.position,
            direction,
            wavelength_nm: lambda.nm,
            // I(ω)/pdf(ω), with the wavelength drawn from the SPD itself.
            power_w: self.peak_intensity * self.falloff(cos_theta) / self.direction_pdf(),
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
        let (direction, cos_theta) = self.sample_direction(u[2] as f64, u[3] as f64);
        let value = self.intensity(cos_theta, lambda)?;
        emitted_from_point(self.position, direction, value, self.direction_pdf(), out);
        Ok(true)
    }

    fn emission_pdf(&self, _origin: &Vec4f, direction: &Vec4f) -> PluginResult<EmissionPdf> {
        let inside = direction.to_f64().normalized().dot(self.axis) > self.cos_cone;
        Ok(EmissionPdf {
            position: 1.0,
            direction: if inside {
                self.direction_pdf() as f32
            } else {
                0.0
            },
        })
    }

    fn sample_toward(
        &self,
        receiver: &Receiver,
        _u: [f32; 2],
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> PluginResult<bool> {
        incident_from_point(
            self.position,
            receiver,
            |w| self.intensity(w.dot(self.axis), lambda),
            out,
        )
    }
}
