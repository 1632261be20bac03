//! `lorentzian`: an emission line with a Lorentzian (Cauchy) profile, truncated to a range.
//!
//! | parameter   | unit | default | meaning                                    |
//! |-------------|------|---------|--------------------------------------------|
//! | `centre_nm` | nm   | —       | line centre                                |
//! | `fwhm_nm`   | nm   | —       | full width at half maximum, > 0            |
//! | `min_nm`    | nm   | 360     | lower end of the range                     |
//! | `max_nm`    | nm   | 830     | upper end of the range                     |
//!
//! Value p(λ) = (γ/π) / ((λ−c)² + γ²) / Z with γ = FWHM/2 and Z the mass inside the range,
//! so ∫ p dλ = 1. Sampling inverts the CDF exactly (arctan form), so `pdf` equals `value`.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    Host, ParamDoc, PluginError, PluginResult, PluginType, Spd, WavelengthRange, WavelengthSample,
};

/// Parameters of [`Lorentzian`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LorentzianParams {
    /// Centre, nm.
    pub centre_nm: f64,
    /// Full width at half maximum, nm.
    pub fwhm_nm: f64,
    /// Range start, nm.
    #[serde(default = "default_min")]
    pub min_nm: f64,
    /// Range end, nm.
    #[serde(default = "default_max")]
    pub max_nm: f64,
}

fn default_min() -> f64 {
    360.0
}
fn default_max() -> f64 {
    830.0
}

/// A truncated Lorentzian line.
pub struct Lorentzian {
    params: LorentzianParams,
    gamma: f64,
    /// arctan((min − c)/γ) and arctan((max − c)/γ): the CDF's ends in angle space.
    a_lo: f64,
    a_hi: f64,
}

impl PluginType for Lorentzian {
    const TYPE_NAME: &'static str = "lorentzian";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "Lorentzian emission line, normalised over a range";
    type Params = LorentzianParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::required("centre_nm", "nm", "line centre"),
            ParamDoc::required("fwhm_nm", "nm", "full width at half maximum, > 0"),
            ParamDoc::optional("min_nm", "nm", "360", "lower end of the range"),
            ParamDoc::optional("max_nm", "nm", "830", "upper end of the range"),
        ]
    }

    fn new(params: LorentzianParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        if !(params.fwhm_nm.is_finite() && params.fwhm_nm > 0.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`fwhm_nm` must be a finite number > 0, got {}",
                params.fwhm_nm
            )));
        }
        if !(params.centre_nm.is_finite()
            && params.min_nm.is_finite()
            && params.max_nm.is_finite()
            && params.min_nm < params.max_nm)
        {
            return Err(PluginError::invalid_parameter(
                "`centre_nm`, `min_nm`, `max_nm` must be finite with min_nm < max_nm",
            ));
        }
        let gamma = 0.5 * params.fwhm_nm;
        let a_lo = ((params.min_nm - params.centre_nm) / gamma).atan();
        let a_hi = ((params.max_nm - params.centre_nm) / gamma).atan();
        Ok(Self {
            params,
            gamma,
            a_lo,
            a_hi,
        })
    }

    fn params(&self) -> &LorentzianParams {
        &self.params
    }
}

impl Spd for Lorentzian {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        if nm < self.params.min_nm || nm > self.params.max_nm {
            return Ok(0.0);
        }
        let d = nm - self.params.centre_nm;
        // Unnormalised Cauchy density, divided by its mass inside the range ((a_hi − a_lo)/π).
        Ok(self.gamma / (d * d + self.gamma * self.gamma) / (self.a_hi - self.a_lo))
    }

    fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        let angle = self.a_lo + u * (self.a_hi - self.a_lo);
        let nm = (self.params.centre_nm + self.gamma * angle.tan())
            .clamp(self.params.min_nm, self.params.max_nm);
        Ok(WavelengthSample {
            nm,
            pdf: self.value(nm)?,
        })
    }

    fn pdf(&self, nm: f64) -> PluginResult<f64> {
        self.value(nm)
    }

    fn range_nm(&self) -> WavelengthRange {
        WavelengthRange {
            min_nm: self.params.min_nm,
            max_nm: self.params.max_nm,
        }
    }
}
