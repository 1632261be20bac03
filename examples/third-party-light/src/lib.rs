//! An RGB spot light from a third party: a point in millimetres, in left-handed axes (x right,
//! y up, +z away from the viewer), emitting uniformly into a hard-edged cone around an axis
//! given by two angles, with an RGB colour instead of a spectrum. Its beams are written in that
//! same language (origin in mm, direction as polar/azimuth angles, colour as RGB); the type
//! declares it through `BEAM_REPRESENTATION` and the host converts each beam.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    BeamRepresentation, ColourEncoding, DirectionEncoding, Flags, Handedness, Host, LightSource,
    ParamDoc, PluginError, PluginResult, PluginType, RandomSample, RepresentedBeam, Vec3,
};
use std::f64::consts::PI;

/// Parameters, e.g. `(position_mm: (0, 2500, -1000), axis_polar_deg: 150,
/// axis_azimuth_deg: 90, cone_deg: 30, rgb: (1, 0.6, 0.25), power_w: 100)`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RgbSpotParams {
    /// Position, mm, left-handed.
    pub position_mm: [f64; 3],
    /// Angle of the cone axis from +y (up), degrees.
    pub axis_polar_deg: f64,
    /// Azimuth of the cone axis from +x towards +z (left-handed), degrees.
    pub axis_azimuth_deg: f64,
    /// Half-angle of the cone, degrees, in (0, 180).
    pub cone_deg: f64,
    /// Linear sRGB colour (chromaticity only; components ≥ 0, not all 0).
    pub rgb: [f64; 3],
    /// Emitted flux, W.
    pub power_w: f64,
}

/// The light.
pub struct RgbSpot {
    params: RgbSpotParams,
    axis: Vec3,
    tangent: Vec3,
    bitangent: Vec3,
    cos_cone: f64,
}

/// Unit vector of polar angle `theta` from +y and azimuth `phi` from +x towards +z (radians).
fn from_angles(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.cos(),
        theta.sin() * phi.sin(),
    )
}

impl PluginType for RgbSpot {
    const TYPE_NAME: &'static str = "rgb_spot";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str =
        "hard-edged RGB spot light in millimetres and left-handed axes (third-party example)";
    const BEAM_REPRESENTATION: BeamRepresentation = BeamRepresentation {
        metres_per_unit: 0.001,
        handedness: Handedness::Left,
        direction: DirectionEncoding::Angles,
        colour: ColourEncoding::LinearSrgb,
    };
    type Params = RgbSpotParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("position_mm", "mm", "position, left-handed axes"),
            ParamDoc::required("axis_polar_deg", "deg", "cone axis: angle from +y"),
            ParamDoc::required(
                "axis_azimuth_deg",
                "deg",
                "cone axis: azimuth from +x to +z",
            ),
            ParamDoc::required("cone_deg", "deg", "cone half-angle"),
            ParamDoc::required("rgb", "", "linear sRGB colour (chromaticity)"),
            ParamDoc::required("power_w", "W", "emitted flux"),
        ]
    }

    fn new(params: RgbSpotParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        let p = &params;
        if !p.position_mm.iter().all(|v| v.is_finite()) {
            return Err(PluginError::invalid_parameter(
                "`position_mm` must be finite",
            ));
        }
        if !(p.axis_polar_deg.is_finite() && p.axis_azimuth_deg.is_finite()) {
            return Err(PluginError::invalid_parameter("axis angles must be finite"));
        }
        if !(p.cone_deg > 0.0 && p.cone_deg < 180.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`cone_deg` must lie in (0, 180), got {}",
                p.cone_deg
            )));
        }
        if !(p.rgb.iter().all(|&c| c.is_finite() && c >= 0.0) && p.rgb.iter().any(|&c| c > 0.0)) {
            return Err(PluginError::invalid_parameter(
                "`rgb` components must be finite and ≥ 0, not all 0",
            ));
        }
        if !(p.power_w.is_finite() && p.power_w > 0.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`power_w` must be finite and > 0, got {}",
                p.power_w
            )));
        }
        let axis = from_angles(
            p.axis_polar_deg.to_radians(),
            p.axis_azimuth_deg.to_radians(),
        );
        // Any two unit vectors perpendicular to the axis and to each other.
        let helper = if axis.x.abs() < 0.9 {
            Vec3::new(1.0, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 1.0, 0.0)
        };
        let tangent = helper.cross(axis).normalized();
        let bitangent = axis.cross(tangent);
        Ok(Self {
            cos_cone: p.cone_deg.to_radians().cos(),
            params,
            axis,
            tangent,
            bitangent,
        })
    }

    fn params(&self) -> &RgbSpotParams {
        &self.params
    }
}

impl LightSource for RgbSpot {
    fn flags(&self) -> Flags {
        // Beams only: the host traces what `next_beam` hands out.
        Flags::NONE
    }

    /// Uniform in solid angle within the cone (u[0], u[1]), in the declared representation.
    /// The intensity is uniform too, so every beam carries the whole flux: `power_w` is the
    /// one-sample estimate of it.
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        let cos_t = 1.0 - sample.u[0] * (1.0 - self.cos_cone);
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = 2.0 * PI * sample.u[1];
        let d = self.tangent * (sin_t * phi.cos())
            + self.bitangent * (sin_t * phi.sin())
            + self.axis * cos_t;
        let [x, y, z] = self.params.position_mm;
        Ok(RepresentedBeam {
            origin: Vec3::new(x, y, z),
            direction: [d.y.clamp(-1.0, 1.0).acos(), d.z.atan2(d.x), 0.0],
            colour: self.params.rgb,
            power_w: self.params.power_w,
        })
    }

    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.params.power_w)
    }
}

spectrace_plugin_api::export_plugin! {
    name: "third-party-light",
    version: env!("CARGO_PKG_VERSION"),
    lights: [RgbSpot],
    spds: [],
    observers: [],
    materials: [],
}
