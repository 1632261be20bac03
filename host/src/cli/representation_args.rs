//! The spectral representation switches on the command line (`spectrace render`), so the
//! representations the accuracy benchmark compares can also be rendered and looked at.

use crate::scene_file::{ReflectanceSource, RepresentationOptions};
use crate::spectrum::Interpolation;

/// `--spd-interpolation`, `--reflectance`, `--observer-step`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RepresentationArgs {
    /// How tabulated spectra (reflectance and emission tables, CSV and bundled spectra) are read
    /// between entries: linear (default) or step (piecewise constant, seed §5).
    #[arg(long = "spd-interpolation", value_name = "linear|step")]
    pub spd_interpolation: Option<String>,
    /// Spectral reflectances as given (measured, default) or replaced by the uplift of their
    /// linear sRGB colour under D65 (rgb), as an RGB-authored scene would store them.
    #[arg(long = "reflectance", value_name = "measured|rgb")]
    pub reflectance: Option<String>,
    /// Colour-matching functions known every NM nm and interpolated linearly in between
    /// (1 = the 1 nm CIE table, default; 5 and 10 are common coarser tables).
    #[arg(long = "observer-step", value_name = "NM")]
    pub observer_step: Option<u32>,
}

impl RepresentationArgs {
    /// The options, or an error naming the bad flag and its accepted values.
    pub fn options(&self) -> Result<RepresentationOptions, String> {
        let mut o = RepresentationOptions::default();
        if let Some(s) = &self.spd_interpolation {
            o.spd_interpolation = match s.trim().to_ascii_lowercase().as_str() {
                "linear" => Interpolation::Linear,
                "step" | "constant" | "piecewise-constant" => Interpolation::Step,
                other => {
                    return Err(format!(
                        "--spd-interpolation: unknown value {other:?}; expected linear or step"
                    ))
                }
            };
        }
        if let Some(s) = &self.reflectance {
            o.reflectance = match s.trim().to_ascii_lowercase().as_str() {
                "measured" | "spectral" => ReflectanceSource::Measured,
                "rgb" | "rgb-uplift" => ReflectanceSource::RgbUplift,
                other => {
                    return Err(format!(
                        "--reflectance: unknown value {other:?}; expected measured or rgb"
                    ))
                }
            };
        }
        if let Some(k) = self.observer_step {
            if !(1..=100).contains(&k) {
                return Err(format!(
                    "--observer-step: {k} nm is outside 1..100 nm (the CIE tables are 1 nm data)"
                ));
            }
            o.observer_step_nm = k;
        }
        Ok(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No flags are the defaults; each flag sets its switch; bad values are errors naming the
    /// flag (structural checks).
    #[test]
    fn parses_flags() {
        assert!(RepresentationArgs::default()
            .options()
            .unwrap()
            .is_default());
        let a = RepresentationArgs {
            spd_interpolation: Some("step".into()),
            reflectance: Some("rgb".into()),
            observer_step: Some(5),
        };
        let o = a.options().unwrap();
        assert_eq!(o.spd_interpolation, Interpolation::Step);
        assert_eq!(o.reflectance, ReflectanceSource::RgbUplift);
        assert_eq!(o.observer_step_nm, 5);
        for bad in [
            RepresentationArgs {
                spd_interpolation: Some("cubic".into()),
                ..Default::default()
            },
            RepresentationArgs {
                reflectance: Some("xyz".into()),
                ..Default::default()
            },
            RepresentationArgs {
                observer_step: Some(0),
                ..Default::default()
            },
        ] {
            let e = bad.options().unwrap_err();
            assert!(e.starts_with("--"), "{e}");
        }
    }
}
