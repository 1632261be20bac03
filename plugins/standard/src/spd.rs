//! `spec` and `table`: the host's SPD types (`host/src/builtin/spd/`), same parameters.

use crate::wrap::{context, params_doc, plugin_error, HostParams};
use spectrace::builtin::spd::{spec, table};
use spectrace::spectrum::Spd as HostSpd;
use spectrace_plugin_api::{
    spd_flags, Flags, Host, ParamDoc, PluginResult, PluginType, Spd, WavelengthRange,
    WavelengthSample,
};
use std::sync::Arc;

macro_rules! spd_type {
    ($ty:ident, $module:ident, $params:ty) => {
        /// The host's SPD type of the same name.
        pub struct $ty {
            params: HostParams<$params>,
            spd: Arc<dyn HostSpd>,
        }

        impl PluginType for $ty {
            const TYPE_NAME: &'static str = $module::TYPE.name;
            const TYPE_VERSION: u32 = $module::TYPE.version;
            const DESCRIPTION: &'static str = $module::TYPE.description;
            type Params = HostParams<$params>;

            fn params_doc() -> Vec<ParamDoc> {
                params_doc(&$module::TYPE)
            }

            fn new(params: Self::Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
                let spd =
                    $module::build(&params.0, &context(Self::TYPE_NAME)).map_err(plugin_error)?;
                Ok(Self { params, spd })
            }

            fn params(&self) -> &Self::Params {
                &self.params
            }
        }

        impl Spd for $ty {
            fn value(&self, nm: f64) -> PluginResult<f64> {
                Ok(self.spd.value(nm))
            }
            fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
                let s = self.spd.sample(u);
                Ok(WavelengthSample {
                    nm: s.lambda,
                    pdf: s.pdf,
                })
            }
            fn pdf(&self, nm: f64) -> PluginResult<f64> {
                Ok(self.spd.pdf(nm))
            }
            fn range_nm(&self) -> WavelengthRange {
                let (min_nm, max_nm) = self.spd.range();
                WavelengthRange { min_nm, max_nm }
            }
            fn capabilities(&self) -> Flags {
                if self.spd.is_delta() {
                    spd_flags::HAS_LINES
                } else {
                    Flags::NONE
                }
            }
        }
    };
}

spd_type!(SpecSpd, spec, spec::SpecParams);
spd_type!(TableSpd, table, table::TableParams);
