//! What the host lends a plugin while it builds an object: SPD lookup by spec. An SPD spec is
//! either a registered SPD type with RON parameters, `name(param: value, …)` or a bare `name`
//! of a registered type (built-in or from any plugin), or a spec of the spectrum module
//! (`d65`, `blackbody:3000`, a CSV path, …). Built-in SPDs are lent through the same guarded
//! ABI wrapper plugins use, so a plugin cannot tell them apart.

use crate::spectrum::{parse_spd_spec, Spd as HostSpd};
use spectrace_plugin_api::abi::sabi_trait::TD_Opaque;
use spectrace_plugin_api::abi::std_types::{RResult, RStr};
use spectrace_plugin_api::host::{AbiHost, AbiHost_TO, HostRef};
use spectrace_plugin_api::spd::GuardedSpd;
use spectrace_plugin_api::{
    PluginError, PluginResult, Spd, SpdObject, SpectralLine, WavelengthRange, WavelengthSample,
};
use std::sync::Arc;

/// The plugin SPD types the services can build (the registry lends itself as one): passed in,
/// so that the services know nothing of the registry that lends them.
pub trait PluginSpds {
    /// A plugin provides SPD type `name`.
    fn provides_spd(&self, name: &str) -> bool;
    /// Build the plugin SPD `name` from its parameters (RON text).
    fn create_spd(&self, name: &str, params: &str) -> Result<SpdObject, String>;
}

/// The host's services, borrowing the plugin SPD types (the registry) for the duration of a
/// constructor call.
pub struct HostServices<'r> {
    registry: &'r dyn PluginSpds,
}

impl<'r> HostServices<'r> {
    /// Services backed by `registry`.
    pub fn new(registry: &'r dyn PluginSpds) -> Self {
        Self { registry }
    }

    /// The ABI view handed to plugin constructors.
    pub fn as_ref(&self) -> HostRef<'_> {
        AbiHost_TO::from_ptr(self, TD_Opaque)
    }

    /// Resolve a spec to an SPD behind the ABI.
    pub fn resolve_spd(&self, spec: &str) -> Result<SpdObject, PluginError> {
        let spec = spec.trim();
        let (name, params) = crate::spectrum::spec::split_type_spec(spec);
        if self.registry.provides_spd(name) {
            return self
                .registry
                .create_spd(name, params)
                .map_err(|e| PluginError::invalid_parameter(format!("spd `{spec}`: {e}")));
        }
        let spd = parse_spd_spec(spec)
            .map_err(|e| PluginError::invalid_parameter(format!("spd `{spec}`: {e}")))?;
        lend_spd(Arc::new(spd))
    }
}

impl AbiHost for HostServices<'_> {
    fn spd(&self, spec: RStr<'_>) -> RResult<SpdObject, PluginError> {
        self.resolve_spd(spec.as_str()).into()
    }
}

/// A host SPD seen through the plugin interface.
struct LentSpd(Arc<dyn HostSpd>);

impl Spd for LentSpd {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        let lines = self.0.delta_lines();
        let mass = crate::spectrum::spd::line_mass_at_lane(&lines, nm as f32);
        Ok(if mass > 0.0 { mass } else { self.0.value(nm) })
    }
    fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        let s = self.0.sample(u);
        Ok(WavelengthSample {
            nm: s.lambda,
            pdf: s.pdf,
        })
    }
    fn pdf(&self, nm: f64) -> PluginResult<f64> {
        Ok(self.0.pdf(nm))
    }
    fn range_nm(&self) -> WavelengthRange {
        let (min_nm, max_nm) = self.0.range();
        WavelengthRange { min_nm, max_nm }
    }
    fn lines(&self) -> Vec<SpectralLine> {
        self.0
            .delta_lines()
            .into_iter()
            .map(|l| SpectralLine {
                nm: l.lambda,
                weight: l.weight,
            })
            .collect()
    }
}

/// Wrap a host SPD so it can be handed to a plugin.
pub fn lend_spd(spd: Arc<dyn HostSpd>) -> Result<SpdObject, PluginError> {
    let lent = GuardedSpd::object(LentSpd(spd), |_| {
        Err(PluginError::unsupported(
            "a host SPD lent to a plugin is saved by its spec, not by state",
        ))
    });
    lent.into_result()
}
