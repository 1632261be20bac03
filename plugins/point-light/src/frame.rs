//! Small vector helpers shared by the lights.

use spectrace_plugin_api::{Vec3, Vec4f};
use std::f64::consts::PI;

/// Uniform direction on the unit sphere from two numbers in [0,1); density 1/(4π) sr⁻¹.
pub fn uniform_sphere(u0: f64, u1: f64) -> Vec3 {
    let z = 1.0 - 2.0 * u0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u1;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// An orthonormal basis (t, b, n) around unit `n` (Duff et al. 2017, branch-free and robust).
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Check a vector parameter is finite, naming it otherwise.
pub fn finite(name: &str, v: [f64; 3]) -> Result<Vec3, spectrace_plugin_api::PluginError> {
    let v = Vec3::new(v[0], v[1], v[2]);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(spectrace_plugin_api::PluginError::invalid_parameter(
            format!("`{name}` must be finite, got {v:?}"),
        ))
    }
}

/// Light from a point source at `position` arriving at `receiver`, written into `out`: the
/// direction and the intensity toward the receiver (given the unit direction of travel from the
/// source) divided by d², with pdf 1 as for every delta light. `Ok(false)` when the receiver sits
/// on the source.
pub fn incident_from_point(
    position: Vec3,
    receiver: &spectrace_plugin_api::Receiver,
    intensity: impl FnOnce(Vec3) -> spectrace_plugin_api::PluginResult<[f64; 4]>,
    out: &mut spectrace_plugin_api::Incident,
) -> spectrace_plugin_api::PluginResult<bool> {
    let to_light = position - receiver.p.to_f64();
    let d2 = to_light.dot(to_light);
    if !(d2 > 0.0) {
        return Ok(false);
    }
    let direction = to_light * (1.0 / d2.sqrt());
    let value = intensity(-direction)?;
    *out = spectrace_plugin_api::Incident {
        value: value.map(|v| (v / d2) as f32),
        direction: Vec4f::from_f64(direction),
        pdf: 1.0,
        point: Vec4f::from_f64(position),
        point_error: Vec4f::default(),
        normal: Vec4f::default(),
    };
    Ok(true)
}

/// The emission of a point source at `position` along `direction`, written into `out`.
pub fn emitted_from_point(
    position: Vec3,
    direction: Vec3,
    value: [f64; 4],
    pdf_direction: f64,
    out: &mut spectrace_plugin_api::EmittedRay,
) {
    *out = spectrace_plugin_api::EmittedRay {
        origin: Vec4f::from_f64(position),
        direction: Vec4f::from_f64(direction),
        value: value.map(|v| v as f32),
        pdf_position: 1.0,
        pdf_direction: pdf_direction as f32,
        normal: Vec4f::default(),
    };
}
