//! The CIE observers (`host/src/builtin/observer/cie.rs`), no parameters; each declares the
//! host's 1 nm table it evaluates, so the host evaluates its own copy.

use crate::wrap::{plugin_error, HostParams};
use spectrace::builtin::observer::cie::{self, CieParams};
use spectrace::color::Observer as HostObserver;
use spectrace_plugin_api::{
    ColorObserver, Host, ObserverTable, ParamDoc, PluginResult, PluginType, WavelengthRange, Xyz,
};
use std::sync::Arc;

macro_rules! cie_type {
    ($ty:ident, $konst:ident, $kind:ident) => {
        /// The host's CIE observer of the same name.
        pub struct $ty {
            params: HostParams<CieParams>,
            observer: Arc<dyn HostObserver>,
        }

        impl PluginType for $ty {
            const TYPE_NAME: &'static str = cie::$konst.name;
            const TYPE_VERSION: u32 = cie::$konst.version;
            const DESCRIPTION: &'static str = cie::$konst.description;
            type Params = HostParams<CieParams>;

            fn params_doc() -> Vec<ParamDoc> {
                Vec::new()
            }

            fn new(params: Self::Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
                let spectrace::builtin::Build::Observer(build) = cie::$konst.build else {
                    return Err(plugin_error("not an observer"));
                };
                let observer = build(&ron::Value::Unit, &crate::wrap::context(Self::TYPE_NAME))
                    .map_err(plugin_error)?;
                Ok(Self { params, observer })
            }

            fn params(&self) -> &Self::Params {
                &self.params
            }
        }

        impl ColorObserver for $ty {
            fn xyz_bar(&self, nm: f64) -> PluginResult<Xyz> {
                let [x, y, z] = self.observer.xyz_bar(nm);
                Ok(Xyz { x, y, z })
            }
            fn name(&self) -> String {
                self.observer.name().to_string()
            }
            fn range_nm(&self) -> WavelengthRange {
                let (min_nm, max_nm) = self.observer.range();
                WavelengthRange { min_nm, max_nm }
            }
            /// The host's 1 nm table, which `xyz_bar` interpolates.
            fn table(&self) -> Option<ObserverTable> {
                let (start_nm, table) = spectrace::color::CieObserverKind::$kind.get().grid();
                Some(ObserverTable {
                    start_nm,
                    xyz: table.iter().map(|&[x, y, z]| Xyz { x, y, z }).collect(),
                })
            }
        }
    };
}

cie_type!(Cie1931_2, CIE1931_2, Cie1931_2);
cie_type!(Cie1964_10, CIE1964_10, Cie1964_10);
cie_type!(Cie2015_2, CIE2015_2, Cie2015_2);
cie_type!(Cie2015_10, CIE2015_10, Cie2015_10);
