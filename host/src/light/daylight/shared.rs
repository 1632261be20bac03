//! What the sun and the sky share: CIE daylight spectra by correlated colour temperature, the default temperatures, the sky's frame and directions in it.

use crate::spectrum::{Interpolation, Spd, TabulatedSpd};
use std::sync::Arc;

/// Lowest and highest CCT the CIE daylight locus is defined for (CIE 15:2004 §3.1), K.
pub const DAYLIGHT_CCT_RANGE: (f64, f64) = (4000.0, 25_000.0);

/// The CIE D-series spectrum at `cct` kelvin (CIE 15:2004: S0 + M1 S1 + M2 S2), normalised,
/// tabulated every 5 nm on 300–830 nm (the components' own grid). An error outside
/// 4000–25 000 K, where the daylight locus is not defined.
pub fn daylight_spd(cct: f64) -> Result<Arc<dyn Spd>, String> {
    let (lo, hi) = DAYLIGHT_CCT_RANGE;
    if !(cct.is_finite() && (lo..=hi).contains(&cct)) {
        return Err(format!(
            "CCT {cct} K is outside the CIE daylight locus ({lo}–{hi} K)"
        ));
    }
    let f = crate::color::daylight::daylight_spd(cct);
    let lambda: Vec<f64> = (0..=106).map(|i| 300.0 + 5.0 * i as f64).collect();
    let values: Vec<f64> = lambda.iter().map(|&l| f(l).max(0.0)).collect();
    let t = TabulatedSpd::new(
        &format!("CIE daylight {cct} K"),
        &lambda,
        &values,
        Interpolation::Linear,
    )
    .map_err(|e| e.to_string())?;
    Ok(Arc::new(t))
}

/// Default CCT of the sky light (documented in `docs/daylight.md`): 6500 K for the overcast
/// types 1–5 (CIE D65, "average daylight"), 8000 K for the partly cloudy types 6–10 and
/// 10 000 K for the clear types 11–15, whose diffuse light is bluer. A convention, not a
/// model of the atmosphere: give `cct` for measured conditions.
pub fn default_sky_cct(sky_type: u8) -> f64 {
    match sky_type {
        1..=5 => 6500.0,
        6..=10 => 8000.0,
        _ => 10_000.0,
    }
}

/// Default CCT of the sun's direct beam (documented in `docs/daylight.md`): 5500 K (D55) at
/// altitudes of 30° and more, falling linearly in sin(altitude) to 4000 K (the lowest CCT the
/// daylight locus has) at the horizon, as the beam reddens through more air mass. A
/// convention, not a model: give `cct` or `spd` for measured conditions.
pub fn default_sun_cct(altitude_deg: f64) -> f64 {
    let s = (altitude_deg.to_radians().sin() / 0.5).clamp(0.0, 1.0);
    4000.0 + 1500.0 * s
}

/// The unit frame of the sky: `up`, `north`, and `east = north × up` (scene directions).
pub fn sky_frame(up: [f64; 3], north: [f64; 3]) -> Result<[glam::DVec3; 3], String> {
    let up = glam::DVec3::from_array(up);
    let north = glam::DVec3::from_array(north);
    if !(up.is_finite() && up.length() > 0.0) {
        return Err("`up` must be a finite non-zero direction".into());
    }
    let up = up.normalize();
    let n = north - up * north.dot(up);
    if !(n.is_finite() && n.length() > 1e-6 * north.length().max(1e-300)) || north.length() == 0.0 {
        return Err("`north` must be a finite direction not parallel to `up`".into());
    }
    let n = n.normalize();
    Ok([up, n, n.cross(up)])
}

/// The unit direction towards zenith angle `z` and azimuth `az` (radians, from north through
/// east) in the frame `[up, north, east]`.
pub fn direction(frame: &[glam::DVec3; 3], z: f64, az: f64) -> glam::DVec3 {
    frame[0] * z.cos() + (frame[1] * az.cos() + frame[2] * az.sin()) * z.sin()
}
