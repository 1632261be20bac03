//! Plugin types in scenes: an [`ObjectFactory`] backed by the registry. The scene builder asks the
//! built-in factory and this one in turn; since the registry refuses a plugin type whose name a
//! built-in (or another plugin) already has, at most one of them knows any name.

use super::adapter::{
    Origin, PluginFaults, PluginLight, PluginMaterial, PluginObserver, PluginSpd,
};
use super::registry::{Registry, RegistryError};
use crate::light::Light;
use crate::material::Material;
use crate::scene::{FactoryContext, FactoryError, ObjectFactory};
use crate::spectrum::Spd;
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::ObjectKind;
use std::sync::Arc;

/// Builds scene items whose type comes from a loaded plugin.
pub struct PluginFactory {
    registry: Arc<Registry>,
    faults: Arc<PluginFaults>,
}

impl PluginFactory {
    /// A factory over `registry`; errors from plugin calls during rendering go to `faults`.
    pub fn new(registry: Arc<Registry>, faults: Arc<PluginFaults>) -> Self {
        Self { registry, faults }
    }

    /// The fault collector shared by every object this factory built.
    pub fn faults(&self) -> &Arc<PluginFaults> {
        &self.faults
    }

    fn prepare(
        &self,
        kind: ObjectKind,
        kind_name: &'static str,
        type_name: &str,
        params: &ron::Value,
    ) -> Result<(String, Origin), FactoryError> {
        match self.registry.plugin_for(kind, type_name) {
            Ok(Some(plugin)) => {
                let text = ron::to_string(params).map_err(|e| {
                    FactoryError::Param(format!("cannot pass parameters to the plugin: {e}"))
                })?;
                let origin = Origin {
                    label: format!(
                        "{kind_name} `{type_name}` (plugin {} {})",
                        plugin.info.name, plugin.info.version
                    ),
                    faults: self.faults.clone(),
                };
                Ok((text, origin))
            }
            _ => Err(FactoryError::UnknownType {
                kind: kind_name,
                type_name: type_name.to_string(),
            }),
        }
    }
}

fn construct_error(e: RegistryError) -> FactoryError {
    match e {
        RegistryError::Construct {
            error, provider, ..
        } => FactoryError::Param(format!("{} (from {provider})", error.message)),
        other => FactoryError::Param(other.to_string()),
    }
}

fn kind_name(kind: ObjectKind) -> &'static str {
    match kind {
        ObjectKind::Material => "material",
        ObjectKind::Light => "light",
        ObjectKind::Spd => "spd",
        ObjectKind::Observer => "observer",
    }
}

/// The light type that loads a blob file: `(type: "blob", params: (file: "lamp.blob"))`.
pub const BLOB_LIGHT: &str = "blob";

impl PluginFactory {
    fn blob_light(
        &self,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError> {
        let p = crate::scene::params::Params::new(params);
        p.expect_only(&["file"])?;
        let file = ctx.resolve(p.string("file")?);
        let blob =
            super::blob::Blob::read_file(&file).map_err(|e| FactoryError::Param(e.to_string()))?;
        blob.instantiate_light(&self.registry, &self.faults)
            .map_err(|e| FactoryError::Param(format!("{}: {e}", file.display())))
    }
}

impl ObjectFactory for PluginFactory {
    fn name(&self) -> &str {
        "plugins"
    }

    fn known_types(&self) -> Vec<(&'static str, String)> {
        std::iter::once(("light", BLOB_LIGHT.to_string()))
            .chain(
                self.registry
                    .plugins()
                    .iter()
                    .flat_map(|p| p.info.types.iter())
                    .map(|t| (kind_name(t.kind), t.name.to_string())),
            )
            .collect()
    }

    fn material(
        &self,
        type_name: &str,
        params: &ron::Value,
        _ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError> {
        let (text, origin) = self.prepare(ObjectKind::Material, "material", type_name, params)?;
        let m = self
            .registry
            .create_plugin_material(type_name, ObjectSource::Params(RStr::from_str(&text)))
            .map_err(construct_error)?;
        Ok(Arc::new(PluginMaterial::new(m, origin)))
    }

    fn light(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError> {
        if type_name == BLOB_LIGHT {
            return self.blob_light(params, ctx);
        }
        let (text, origin) = self.prepare(ObjectKind::Light, "light", type_name, params)?;
        let source = ObjectSource::Params(RStr::from_str(&text));
        let l = self
            .registry
            .create_plugin_light(type_name, source)
            .map_err(construct_error)?;
        // A type whose beams are in another representation is wrapped in its adapters.
        let light = super::representation::wrap_light(
            &self.registry,
            type_name,
            source,
            PluginLight::new(l, origin),
        )
        .map_err(FactoryError::Param)?;
        Ok(Arc::new(light))
    }

    fn spd(
        &self,
        type_name: &str,
        params: &ron::Value,
        _ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError> {
        let (text, origin) = self.prepare(ObjectKind::Spd, "spd", type_name, params)?;
        let s = self
            .registry
            .create_plugin_spd(type_name, ObjectSource::Params(RStr::from_str(&text)))
            .map_err(construct_error)?;
        Ok(Arc::new(PluginSpd::new(s, origin)))
    }

    fn shared_spd_factory(&self) -> Option<Arc<dyn ObjectFactory>> {
        Some(Arc::new(PluginFactory {
            registry: self.registry.clone(),
            faults: self.faults.clone(),
        }))
    }

    fn observer(
        &self,
        type_name: &str,
        params: &ron::Value,
        _ctx: &FactoryContext,
    ) -> Result<Arc<dyn crate::color::Observer>, FactoryError> {
        let (text, origin) = self.prepare(ObjectKind::Observer, "observer", type_name, params)?;
        let o = self
            .registry
            .create_plugin_observer(type_name, ObjectSource::Params(RStr::from_str(&text)))
            .map_err(construct_error)?;
        Ok(Arc::new(PluginObserver::new(o, origin)))
    }
}
