//! `gaussian_sensor`: a three-channel camera sensor whose spectral sensitivities are Gaussians,
//! used as a colour observer (its channels take the place of x̄, ȳ, z̄).
//!
//! | parameter     | unit | default              | meaning                                   |
//! |---------------|------|----------------------|-------------------------------------------|
//! | `name`        | —    | `"gaussian-sensor"`  | name shown in outputs                     |
//! | `peaks_nm`    | nm   | `(600, 540, 450)`    | peak wavelength of channels 1, 2, 3       |
//! | `widths_nm`   | nm   | `(40, 40, 30)`       | standard deviation of each channel        |
//! | `gains`       | —    | `(1, 1, 1)`          | peak sensitivity of each channel          |
//! | `min_nm`      | nm   | 360                  | range start                               |
//! | `max_nm`      | nm   | 830                  | range end                                 |
//!
//! Channel 2 plays the role of ȳ (the host normalises by its integral).

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    ColorObserver, Host, ParamDoc, PluginError, PluginResult, PluginType, WavelengthRange, Xyz,
};

/// Parameters of [`GaussianSensor`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SensorParams {
    /// Display name.
    #[serde(default = "default_name")]
    pub name: String,
    /// Peak wavelengths, nm.
    #[serde(default = "default_peaks")]
    pub peaks_nm: [f64; 3],
    /// Standard deviations, nm.
    #[serde(default = "default_widths")]
    pub widths_nm: [f64; 3],
    /// Peak sensitivities.
    #[serde(default = "default_gains")]
    pub gains: [f64; 3],
    /// Range start, nm.
    #[serde(default = "default_min")]
    pub min_nm: f64,
    /// Range end, nm.
    #[serde(default = "default_max")]
    pub max_nm: f64,
}

fn default_name() -> String {
    "gaussian-sensor".into()
}
fn default_peaks() -> [f64; 3] {
    [600.0, 540.0, 450.0]
}
fn default_widths() -> [f64; 3] {
    [40.0, 40.0, 30.0]
}
fn default_gains() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}
fn default_min() -> f64 {
    360.0
}
fn default_max() -> f64 {
    830.0
}

/// A Gaussian three-channel sensor.
pub struct GaussianSensor {
    params: SensorParams,
}

impl PluginType for GaussianSensor {
    const TYPE_NAME: &'static str = "gaussian_sensor";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "three-channel camera sensor with Gaussian sensitivities";
    type Params = SensorParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional("name", "", "\"gaussian-sensor\"", "name shown in outputs"),
            ParamDoc::optional("peaks_nm", "nm", "(600, 540, 450)", "channel peaks"),
            ParamDoc::optional(
                "widths_nm",
                "nm",
                "(40, 40, 30)",
                "channel standard deviations",
            ),
            ParamDoc::optional("gains", "", "(1, 1, 1)", "channel peak sensitivities"),
            ParamDoc::optional("min_nm", "nm", "360", "range start"),
            ParamDoc::optional("max_nm", "nm", "830", "range end"),
        ]
    }

    fn new(params: SensorParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        for (i, w) in params.widths_nm.iter().enumerate() {
            if !(w.is_finite() && *w > 0.0) {
                return Err(PluginError::invalid_parameter(format!(
                    "`widths_nm[{i}]` must be a finite number > 0, got {w}"
                )));
            }
        }
        if params
            .gains
            .iter()
            .chain(&params.peaks_nm)
            .any(|v| !v.is_finite())
            || params.gains.iter().any(|g| *g < 0.0)
        {
            return Err(PluginError::invalid_parameter(
                "`peaks_nm` must be finite and `gains` finite and ≥ 0",
            ));
        }
        if !(params.min_nm < params.max_nm) {
            return Err(PluginError::invalid_parameter(
                "`min_nm` must be below `max_nm`",
            ));
        }
        Ok(Self { params })
    }

    fn params(&self) -> &SensorParams {
        &self.params
    }
}

impl ColorObserver for GaussianSensor {
    fn xyz_bar(&self, nm: f64) -> PluginResult<Xyz> {
        if nm < self.params.min_nm || nm > self.params.max_nm {
            return Ok(Xyz::default());
        }
        let ch = |i: usize| {
            let t = (nm - self.params.peaks_nm[i]) / self.params.widths_nm[i];
            self.params.gains[i] * (-0.5 * t * t).exp()
        };
        Ok(Xyz {
            x: ch(0),
            y: ch(1),
            z: ch(2),
        })
    }

    fn name(&self) -> String {
        self.params.name.clone()
    }

    fn range_nm(&self) -> WavelengthRange {
        WavelengthRange {
            min_nm: self.params.min_nm,
            max_nm: self.params.max_nm,
        }
    }
}
