//! `__TYPE__`: a triangular emission band (a spectrace plugin written by
//! `spectrace plugins new`).
//!
//! | parameter       | unit | default | meaning                              |
//! |-----------------|------|---------|--------------------------------------|
//! | `centre_nm`     | nm   | `550`   | peak wavelength                      |
//! | `half_width_nm` | nm   | `50`    | half the base width, > 0             |
//!
//! s(λ) = (w − |λ − c|)/w² on [c − w, c + w], which integrates to 1; sampled exactly by
//! inverting its distribution function.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    Host, ParamDoc, PluginError, PluginResult, PluginType, Spd, WavelengthRange, WavelengthSample,
};

/// Parameters (and saved state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Peak, nm.
    pub centre_nm: f64,
    /// Half the base width, nm.
    pub half_width_nm: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            centre_nm: 550.0,
            half_width_nm: 50.0,
        }
    }
}

/// The SPD.
pub struct Triangle {
    params: Params,
}

impl PluginType for Triangle {
    const TYPE_NAME: &'static str = "__TYPE__";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "triangular emission band, normalised";
    type Params = Params;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional("centre_nm", "nm", "550", "peak wavelength"),
            ParamDoc::optional("half_width_nm", "nm", "50", "half the base width, > 0"),
        ]
    }

    fn new(params: Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
        let (c, w) = (params.centre_nm, params.half_width_nm);
        if !(c.is_finite() && w.is_finite() && w > 0.0 && c - w > 0.0) {
            return Err(PluginError::invalid_parameter(format!(
                "`centre_nm` {c} and `half_width_nm` {w} must be finite with 0 < w < c"
            )));
        }
        Ok(Self { params })
    }

    fn params(&self) -> &Params {
        &self.params
    }
}

impl Spd for Triangle {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        let (c, w) = (self.params.centre_nm, self.params.half_width_nm);
        Ok(((w - (nm - c).abs()) / (w * w)).max(0.0))
    }

    fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        let (c, w) = (self.params.centre_nm, self.params.half_width_nm);
        let nm = if u < 0.5 {
            c - w + w * (2.0 * u).sqrt()
        } else {
            c + w - w * (2.0 * (1.0 - u)).sqrt()
        };
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
            min_nm: self.params.centre_nm - self.params.half_width_nm,
            max_nm: self.params.centre_nm + self.params.half_width_nm,
        }
    }
}

spectrace_plugin_api::export_plugin! {
    name: "__NAME__",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [Triangle],
    observers: [],
    materials: [],
}
