//! `__TYPE__`: a three-channel camera sensor with Gaussian sensitivities (a spectrace plugin
//! written by `spectrace plugins new`).
//!
//! | parameter  | unit | default             | meaning                                  |
//! |------------|------|---------------------|------------------------------------------|
//! | `peaks_nm` | nm   | `(600, 540, 450)`   | peak of the X, Y and Z channels          |
//! | `sigma_nm` | nm   | `40`                | standard deviation of every channel, > 0 |
//!
//! Defined on 380–780 nm and 0 outside; each channel peaks at 1.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    ColorObserver, Host, ParamDoc, PluginError, PluginResult, PluginType, WavelengthRange, Xyz,
};

/// Parameters (and saved state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Channel peaks, nm.
    pub peaks_nm: [f64; 3],
    /// Standard deviation, nm.
    pub sigma_nm: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            peaks_nm: [600.0, 540.0, 450.0],
            sigma_nm: 40.0,
        }
    }
}

const MIN_NM: f64 = 380.0;
const MAX_NM: f64 = 780.0;

/// The observer.
pub struct GaussianSensor {
    params: Params,
}

impl PluginType for GaussianSensor {
    const TYPE_NAME: &'static str = "__TYPE__";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "three-channel sensor with Gaussian sensitivities";
    type Params = Params;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional("peaks_nm", "nm", "(600, 540, 450)", "channel peaks"),
            ParamDoc::optional("sigma_nm", "nm", "40", "standard deviation, > 0"),
        ]
    }

    fn new(params: Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
        if !(params.sigma_nm.is_finite() && params.sigma_nm > 0.0)
            || params.peaks_nm.iter().any(|p| !p.is_finite())
        {
            return Err(PluginError::invalid_parameter(
                "`peaks_nm` must be finite and `sigma_nm` finite and > 0",
            ));
        }
        Ok(Self { params })
    }

    fn params(&self) -> &Params {
        &self.params
    }
}

impl ColorObserver for GaussianSensor {
    fn xyz_bar(&self, nm: f64) -> PluginResult<Xyz> {
        if !(MIN_NM..=MAX_NM).contains(&nm) {
            return Ok(Xyz::default());
        }
        let g = |peak: f64| {
            let t = (nm - peak) / self.params.sigma_nm;
            (-0.5 * t * t).exp()
        };
        let [x, y, z] = self.params.peaks_nm;
        Ok(Xyz {
            x: g(x),
            y: g(y),
            z: g(z),
        })
    }

    fn name(&self) -> String {
        "__TYPE__".into()
    }

    fn range_nm(&self) -> WavelengthRange {
        WavelengthRange {
            min_nm: MIN_NM,
            max_nm: MAX_NM,
        }
    }
}

spectrace_plugin_api::export_plugin! {
    name: "__NAME__",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [],
    observers: [GaussianSensor],
    materials: [],
}
