//! `spec` and `table`: the host's SPD types (`host/src/builtin/spd/`), same parameters, with
//! their spectral lines.

use crate::wrap::{context, params_doc, plugin_error, HostParams, HostSpd};
use spectrace::builtin::spd::{spec, table};
use spectrace_plugin_api::{
    Host, ParamDoc, PluginResult, PluginType, Spd, SpectralLine, WavelengthRange, WavelengthSample,
};

macro_rules! spd_type {
    ($ty:ident, $module:ident, $params:ty) => {
        /// The host's SPD type of the same name.
        pub struct $ty {
            params: HostParams<$params>,
            spd: HostSpd,
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
                Ok(Self {
                    params,
                    spd: HostSpd(spd),
                })
            }

            fn params(&self) -> &Self::Params {
                &self.params
            }
        }

        impl Spd for $ty {
            fn value(&self, nm: f64) -> PluginResult<f64> {
                self.spd.value(nm)
            }
            fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
                self.spd.sample(u)
            }
            fn pdf(&self, nm: f64) -> PluginResult<f64> {
                self.spd.pdf(nm)
            }
            fn range_nm(&self) -> WavelengthRange {
                self.spd.range_nm()
            }
            fn lines(&self) -> Vec<SpectralLine> {
                self.spd.lines()
            }
        }
    };
}

spd_type!(SpecSpd, spec, spec::SpecParams);
spd_type!(TableSpd, table, table::TableParams);
