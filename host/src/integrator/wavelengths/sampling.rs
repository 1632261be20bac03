//! How camera paths draw their wavelengths: the `--wavelengths` setting.

/// How camera paths draw their wavelengths (each lane's pdf is kept, so all are unbiased).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WavelengthSampling {
    /// Importance-sampled for the observer and the scene's emission together (the default):
    /// ¾ of the density is the visible-importance shape times the square root of the lights'
    /// emission, ¼ the visible-importance density alone, one tabulated density (see
    /// [`super::wavelengths::groups`]). Fewer lanes land where the lights emit little; the
    /// visible quarter keeps every visible wavelength possible. Falls back to `Visible` where it
    /// cannot apply (no evaluable light, fluorescence) and to the render plan's mixture where
    /// the plan draws from the lights' spectra.
    #[default]
    Product,
    /// Importance-sampled for the observer's luminance response (pbrt-v4's sech² fit):
    /// fewer wavelengths wasted where x̄ȳz̄ are near zero.
    Visible,
    /// Uniform over 360–830 nm: the plain baseline, more colour noise per sample.
    Uniform,
    /// Importance-sampled from the scene's emission: the power-weighted mixture of the
    /// evaluable lights' SPDs (continuous parts; see [`super::wavelengths::groups`] for delta lines
    /// and scenes without such lights). Unbiased for path tracing without fluorescence: where
    /// no light emits, every contribution is 0, so a zero density there loses nothing.
    LightSpd,
}

impl std::str::FromStr for WavelengthSampling {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "product" | "visible-emission" => Ok(Self::Product),
            "visible" => Ok(Self::Visible),
            "uniform" => Ok(Self::Uniform),
            "light" | "light-spd" | "lightspd" => Ok(Self::LightSpd),
            other => Err(format!(
                "unknown wavelength sampling {other:?}: expected product, visible, uniform or light"
            )),
        }
    }
}

impl std::fmt::Display for WavelengthSampling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Product => "product",
            Self::Visible => "visible",
            Self::Uniform => "uniform",
            Self::LightSpd => "light",
        })
    }
}
