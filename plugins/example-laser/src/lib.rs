//! A laser: one wavelength, one direction, a beam of given radius. It implements only the seed's
//! two calls (`next_beam`, and `number_of_beams` which the API counts for it), so the host traces
//! its beams; nothing else is needed to render it.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    Beam, Flags, Host, LightSource, ParamDoc, PluginError, PluginResult, PluginType, RandomSample,
    RepresentedBeam, Vec3,
};

/// Parameters, written in a scene as `(origin: (0, 1, 0), direction: (0, 0, -1), ...)`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaserParams {
    /// Centre of the exit aperture, scene units.
    pub origin: [f64; 3],
    /// Beam direction (any length > 0).
    pub direction: [f64; 3],
    /// Beam radius at the aperture, scene units.
    #[serde(default)]
    pub radius: f64,
    /// Wavelength, nm.
    pub wavelength_nm: f64,
    /// Output power, W.
    pub power_w: f64,
}

/// The laser.
pub struct Laser {
    params: LaserParams,
    origin: Vec3,
    axis: Vec3,
    tangent: Vec3,
    bitangent: Vec3,
}

impl PluginType for Laser {
    const TYPE_NAME: &'static str = "laser";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "monochromatic collimated beam (beams only)";
    type Params = LaserParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("origin", "scene units", "centre of the aperture"),
            ParamDoc::required("direction", "", "beam direction"),
            ParamDoc::optional("radius", "scene units", "0", "beam radius"),
            ParamDoc::required("wavelength_nm", "nm", "wavelength"),
            ParamDoc::required("power_w", "W", "output power"),
        ]
    }

    fn new(params: LaserParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        let [x, y, z] = params.direction;
        let axis = Vec3::new(x, y, z);
        if !(axis.is_finite() && axis.length() > 0.0) {
            return Err(PluginError::invalid_parameter(
                "`direction` must be finite and non-zero",
            ));
        }
        if !(300.0..=1000.0).contains(&params.wavelength_nm) {
            return Err(PluginError::invalid_parameter(format!(
                "`wavelength_nm` must be in [300, 1000] nm, got {}",
                params.wavelength_nm
            )));
        }
        if !(params.power_w > 0.0 && params.power_w.is_finite() && params.radius >= 0.0) {
            return Err(PluginError::invalid_parameter(
                "`power_w` must be > 0 and `radius` ≥ 0",
            ));
        }
        let axis = axis.normalized();
        let helper = if axis.x.abs() < 0.9 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let tangent = axis.cross(helper).normalized();
        let [ox, oy, oz] = params.origin;
        Ok(Self {
            origin: Vec3::new(ox, oy, oz),
            bitangent: axis.cross(tangent),
            tangent,
            axis,
            params,
        })
    }

    fn params(&self) -> &LaserParams {
        &self.params
    }
}

impl LightSource for Laser {
    fn flags(&self) -> Flags {
        // Beams only: the host traces what `next_beam` hands out.
        Flags::NONE
    }

    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        // Uniform over the aperture disk: r = R·sqrt(u0), φ = 2π·u1.
        let r = self.params.radius * sample.u[0].sqrt();
        let phi = std::f64::consts::TAU * sample.u[1];
        Ok(Beam {
            origin: self.origin + self.tangent * (r * phi.cos()) + self.bitangent * (r * phi.sin()),
            direction: self.axis,
            wavelength_nm: self.params.wavelength_nm,
            power_w: self.params.power_w,
            source_id: 0,
        }
        .into())
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.params.power_w)
    }
}

spectrace_plugin_api::export_plugin! {
    name: "example-laser",
    version: env!("CARGO_PKG_VERSION"),
    lights: [Laser],
    spds: [],
    observers: [],
    materials: [],
}
