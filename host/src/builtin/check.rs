//! Construction-time checks shared by the built-in types: reflectances in [0, 1] at every
//! wavelength, radiometric quantities finite, ≥ 0 and representable in the `f32` the renderer
//! carries them in, indices of refraction finite and > 0 over the whole wavelength range.
//! Every error names the parameter (the scene builder adds the item), so a bad value is refused
//! before it can turn into a silently black or missing light.

use crate::scene_file::FactoryError;
use crate::spectrum::wavelength_sampling::VISIBLE_RANGE;

/// Largest radiometric value (W, W/m², W/(m²·sr)) the renderer can hold: lights and emitters
/// keep their power in `f32`, and anything above `f32::MAX` becomes infinity there.
pub const MAX_F32: f64 = f32::MAX as f64;

/// Wavelengths (nm) at which spectral values are checked: every whole nm of the renderer's
/// range (360–830 nm), which is where paths draw their wavelengths.
pub fn check_wavelengths() -> impl Iterator<Item = f64> {
    (VISIBLE_RANGE.0 as i32..=VISIBLE_RANGE.1 as i32).map(f64::from)
}

/// `v` for messages: plain when moderate, in exponent form when very large or small (so
/// 1e300 is not printed as 301 digits).
pub fn show(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A reflectance value `v` (at `nm`, or at every wavelength for a constant) within [0, 1].
pub fn unit_interval(param: &str, v: f64, nm: Option<f64>) -> Result<(), FactoryError> {
    if (0.0..=1.0).contains(&v) {
        return Ok(());
    }
    let at = match nm {
        Some(nm) => format!("at {nm} nm"),
        None => "at every wavelength".to_string(),
    };
    Err(param_err(
        param,
        format!(
            "value {} {at} is outside [0, 1] (a reflectance cannot be negative or create energy)",
            show(v)
        ),
    ))
}

/// Every entry of a table and the curve `f` as the renderer reads it (interpolated, step or
/// uplifted) at every whole nm of the range within [0, 1].
pub fn reflectance_curve(
    param: &str,
    table: &[(f64, f64)],
    f: &dyn Fn(f64) -> f64,
) -> Result<(), FactoryError> {
    for &(nm, v) in table {
        unit_interval(param, v, Some(nm))?;
    }
    for nm in check_wavelengths() {
        unit_interval(param, f(nm), Some(nm))?;
    }
    Ok(())
}

/// A radiometric quantity (`unit` names it for the message): finite, ≥ 0 and at most
/// [`MAX_F32`], as the `f32` the renderer stores it in.
pub fn radiometric(param: &str, value: f64, unit: &str) -> Result<f32, FactoryError> {
    if !value.is_finite() {
        return Err(param_err(
            param,
            format!("must be a finite number of {unit}, got {}", show(value)),
        ));
    }
    if !(value >= 0.0) {
        return Err(param_err(
            param,
            format!("must be ≥ 0 {unit}, got {}", show(value)),
        ));
    }
    if value > MAX_F32 {
        return Err(param_err(
            param,
            format!(
                "{value:e} {unit} is above the largest value the renderer can hold \
                 ({MAX_F32:e} {unit}, the 32-bit float limit); it would become infinite"
            ),
        ));
    }
    Ok(value as f32)
}

/// A scene coordinate or direction component list: finite and within the `f32` range the
/// geometry uses.
pub fn position(param: &str, v: [f64; 3]) -> Result<glam::Vec3A, FactoryError> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= MAX_F32) {
        Ok(glam::Vec3A::new(v[0] as f32, v[1] as f32, v[2] as f32))
    } else {
        Err(param_err(
            param,
            format!("expected three finite numbers (x, y, z) within ±{MAX_F32:e}, got {v:?}"),
        ))
    }
}

/// A direction: finite and non-zero.
pub fn direction(param: &str, v: [f64; 3]) -> Result<glam::Vec3A, FactoryError> {
    let d = position(param, v)?;
    if !(d.length() > 0.0 && d.length().is_finite()) {
        return Err(param_err(
            param,
            format!("a direction must be non-zero, got {v:?}"),
        ));
    }
    Ok(d)
}

/// An index of refraction evaluated by `eta` at every whole nm of the range: finite and > 0.
pub fn ior_curve(param: &str, eta: &dyn Fn(f64) -> f64) -> Result<(), FactoryError> {
    for nm in check_wavelengths() {
        let n = eta(nm);
        if !(n.is_finite() && n > 0.0) {
            return Err(param_err(
                param,
                format!("index of refraction {n} at {nm} nm must be finite and > 0"),
            ));
        }
    }
    Ok(())
}

/// A parameter error in the form every built-in uses.
pub fn param_err(param: &str, message: impl std::fmt::Display) -> FactoryError {
    FactoryError::Param(format!("parameter `{param}`: {message}"))
}

/// `v` if every component is finite and within the `f32` range the geometry uses, else an
/// error naming `param`.
pub fn finite3(param: &str, v: [f64; 3]) -> Result<glam::Vec3A, FactoryError> {
    position(param, v)
}

/// `x` if finite, else an error naming `param`.
pub fn finite(param: &str, x: f64) -> Result<f64, FactoryError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(param_err(param, "must be finite"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_interval_names_value_and_wavelength() {
        let e = unit_interval("reflectance", 2.0, Some(550.0)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "parameter `reflectance`: value 2 at 550 nm is outside [0, 1] (a reflectance \
             cannot be negative or create energy)"
        );
        assert!(unit_interval("r", f64::NAN, None).is_err());
        assert!(unit_interval("r", 0.0, None).is_ok());
        assert!(unit_interval("r", 1.0, None).is_ok());
    }

    #[test]
    fn radiometric_limits() {
        assert_eq!(radiometric("power", 3.0, "W").unwrap(), 3.0);
        for bad in [f64::NAN, f64::INFINITY, -1.0, 1e300, 3.5e38] {
            assert!(radiometric("power", bad, "W").is_err(), "{bad}");
        }
        // f32::MAX itself is representable.
        assert!(radiometric("power", MAX_F32, "W").unwrap().is_finite());
    }
}
