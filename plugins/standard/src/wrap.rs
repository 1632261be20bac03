//! Shared pieces: the host's parameter structs as plugin parameters, and the host's param docs
//! as the plugin API's.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use spectrace::builtin::BuiltinType;
use spectrace::scene::FactoryContext;
use spectrace_plugin_api::{
    ParamDoc, PluginError, PluginResult, Spd, SpectralLine, WavelengthRange, WavelengthSample,
};
use std::sync::Arc;

/// A host parameter struct read the way the host reads scene parameters (bare numbers for
/// optional fields, `()` for all defaults, errors naming the parameter); bincode as is.
#[derive(Clone, Debug, PartialEq)]
pub struct HostParams<P>(pub P);

impl<P: Serialize> Serialize for HostParams<P> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de, P: serde::de::DeserializeOwned> Deserialize<'de> for HostParams<P> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        if d.is_human_readable() {
            let v = ron::Value::deserialize(d)?;
            spectrace::builtin::from_value(&v)
                .map(HostParams)
                .map_err(D::Error::custom)
        } else {
            P::deserialize(d).map(HostParams)
        }
    }
}

/// The parameter table of a built-in type in the plugin API's form.
pub fn params_doc(ty: &BuiltinType) -> Vec<ParamDoc> {
    ty.params
        .iter()
        .map(|p| match p.default {
            Some(d) => ParamDoc::optional(p.name, p.unit, d, p.description),
            None => ParamDoc::required(p.name, p.unit, p.description),
        })
        .collect()
}

/// The context the host's constructors run in: relative paths against the working directory
/// (plugin parameters do not carry the scene's folder); SPD types nested in a spectrum are
/// the built-in ones.
pub fn context(item: &str) -> FactoryContext {
    FactoryContext {
        base_dir: ".".into(),
        item: item.to_string(),
        representation: Default::default(),
        spd_factories: spectrace::scene::SpdFactories(vec![Arc::new(
            spectrace::builtin::BuiltinFactory,
        )]),
    }
}

/// A host error as a plugin error.
pub fn plugin_error(e: impl std::fmt::Display) -> PluginError {
    PluginError::invalid_parameter(e.to_string())
}

/// A host SPD as a plugin SPD: the same value, sampling, density, range and lines, in f64
/// unchanged, so the host rebuilds an SPD that evaluates and samples bit for bit like this one.
/// What the library's lights and materials hand over as their emission spectrum.
#[derive(Clone, Debug)]
pub struct HostSpd(pub Arc<dyn spectrace::spectrum::Spd>);

impl Spd for HostSpd {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        Ok(self.0.value(nm))
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
