//! The registry as the scene's factory: one [`ObjectFactory`] that builds every registered type
//! through the same call, whoever provides it — a built-in (its constructor in
//! [`crate::builtin`]), a loaded plugin (through the ABI, wrapped by the adapters), or a blob
//! file (`type: "blob"`, any blob kind). Since the registry refuses a second provider for any
//! name, there is exactly one way to build each `(kind, type)`.

use super::adapter::{
    Origin, PluginFaults, PluginLight, PluginMaterial, PluginObserver, PluginSpd,
};
use super::blob::{Blob, BUILTIN_PLUGIN};
use super::loader::LoadedPlugin;
use super::registry::{Provider, Registry, RegistryError};
use crate::builtin::{Build, BuiltinType};
use crate::camera::{Filter, PerspectiveCamera};
use crate::geometry::Shape;
use crate::light::Light;
use crate::material::Material;
use crate::scene_file::type_doc::{Kind, TypeDoc};
use crate::scene_file::{FactoryContext, FactoryError, ObjectFactory};
use crate::spectrum::Spd;
use spectrace_plugin_api::abi::std_types::{ROption, RStr};
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::ObjectKind;
use std::path::Path;
use std::sync::Arc;

/// The type name that loads a blob file, for each blob kind:
/// `(type: "blob", params: (file: "lamp.blob"))`.
pub const BLOB_LIGHT: &str = "blob";

/// Kinds that can be saved as blobs.
pub const BLOB_KINDS: [Kind; 4] = [Kind::Material, Kind::Light, Kind::Spd, Kind::Observer];

/// The type information of the `blob` type of `kind`.
pub fn blob_type_doc(kind: Kind) -> TypeDoc {
    TypeDoc {
        kind,
        name: BLOB_LIGHT.to_string(),
        version: 1,
        description: format!(
            "a {kind} saved with `spectrace blob pack` (self-contained; plugin types need their plugin loaded)"
        ),
        params: vec![crate::scene_file::type_doc::ParamDoc {
            name: "file".into(),
            unit: String::new(),
            default: None,
            description: "the blob file, relative to the scene file".into(),
        }],
        alias_of: None,
    }
}

/// One object of any blob kind.
#[derive(Clone)]
pub enum Built {
    /// A material.
    Material(Arc<dyn Material>),
    /// A light.
    Light(Arc<dyn Light>),
    /// An SPD.
    Spd(Arc<dyn Spd>),
    /// An observer.
    Observer(Arc<dyn crate::color::Observer>),
}

impl std::fmt::Debug for Built {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let k = match self {
            Built::Material(_) => "material",
            Built::Light(_) => "light",
            Built::Spd(_) => "spd",
            Built::Observer(_) => "observer",
        };
        write!(f, "Built::{k}")
    }
}

/// Where a constructor takes its values from.
pub enum Source<'a> {
    /// Scene parameters.
    Params(&'a ron::Value),
    /// A blob's saved state.
    State {
        /// State schema version.
        type_version: u32,
        /// The bytes.
        bytes: &'a [u8],
    },
}

/// Builds every registered type (built-in, plugin or blob) for scenes.
pub struct PluginFactory {
    registry: Arc<Registry>,
    faults: Arc<PluginFaults>,
}

/// The registry's factory under the name that says what it is.
pub type RegistryFactory = PluginFactory;

fn construct_error(e: RegistryError) -> FactoryError {
    match e {
        RegistryError::Construct {
            error, provider, ..
        } => FactoryError::Param(format!("{} (from {provider})", error.message)),
        other => FactoryError::Param(other.to_string()),
    }
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

    /// The registry.
    pub fn registry(&self) -> &Arc<Registry> {
        &self.registry
    }

    /// A context whose SPD lookups go through this factory's registry, then the built-in
    /// types (for items built outside a scene, such as blobs).
    pub fn context(&self, base_dir: &std::path::Path, item: String) -> FactoryContext {
        let builtin: Arc<dyn ObjectFactory> = Arc::new(crate::builtin::BuiltinFactory);
        FactoryContext {
            base_dir: base_dir.to_path_buf(),
            item,
            representation: Default::default(),
            spd_factories: crate::scene_file::SpdFactories(
                self.shared_spd_factory()
                    .into_iter()
                    .chain([builtin])
                    .collect(),
            ),
        }
    }

    /// Build `(kind, type_name)` from parameters or saved state, whoever provides it.
    pub fn build(
        &self,
        kind: Kind,
        type_name: &str,
        source: Source<'_>,
        ctx: &FactoryContext,
    ) -> Result<Built, FactoryError> {
        let entry = self
            .registry
            .lookup(kind, type_name)
            .map_err(|_| unknown(kind, type_name))?;
        if let Some(ty) = entry.builtin {
            return builtin_from_source(ty, kind, type_name, source, ctx);
        }
        if type_name == BLOB_LIGHT && matches!(entry.provider, Provider::Builtin) {
            let Source::Params(params) = source else {
                return Err(FactoryError::Param("a blob cannot hold a blob".into()));
            };
            return self.blob(kind, params, ctx);
        }
        let Provider::Plugin(plugin) = &entry.provider else {
            return Err(unknown(kind, type_name));
        };
        self.build_plugin(plugin, kind, type_name, source, ctx)
    }

    /// Build `(kind, type_name)` with the plugin library that provides it.
    fn build_plugin(
        &self,
        plugin: &LoadedPlugin,
        kind: Kind,
        type_name: &str,
        source: Source<'_>,
        ctx: &FactoryContext,
    ) -> Result<Built, FactoryError> {
        let text;
        let object_source = match source {
            Source::Params(v) => {
                text = ron::to_string(v).map_err(|e| {
                    FactoryError::Param(format!("cannot pass parameters to the plugin: {e}"))
                })?;
                ObjectSource::Params(RStr::from_str(&text))
            }
            Source::State {
                type_version,
                bytes,
            } => ObjectSource::State {
                type_version,
                bytes: spectrace_plugin_api::abi::std_types::RSlice::from_slice(bytes),
            },
        };
        let origin = Origin {
            label: format!(
                "{kind} `{type_name}` (plugin {} {})",
                plugin.info.name, plugin.info.version
            ),
            faults: self.faults.clone(),
        };
        let r = &self.registry;
        let take_error = plugin.module.take_error();
        Ok(match kind {
            Kind::Material => {
                let m = r
                    .create_plugin_material(type_name, object_source)
                    .map_err(construct_error)?;
                Built::Material(Arc::new(
                    PluginMaterial::new(m, take_error, origin, &ctx.item)
                        .map_err(FactoryError::Param)?,
                ))
            }
            Kind::Light => {
                let l = r
                    .create_plugin_light(type_name, object_source)
                    .map_err(construct_error)?;
                let representation = plugin
                    .info
                    .types
                    .iter()
                    .find(|t| t.kind == ObjectKind::Light && t.name.as_str() == type_name)
                    .map(|t| t.beams)
                    .unwrap_or_default();
                Built::Light(Arc::new(
                    PluginLight::new(l, representation, take_error, origin, &ctx.item)
                        .map_err(FactoryError::Param)?,
                ))
            }
            Kind::Spd => {
                let s = r
                    .create_plugin_spd(type_name, object_source)
                    .map_err(construct_error)?;
                Built::Spd(Arc::new(PluginSpd::new(s, origin)))
            }
            Kind::Observer => {
                let o = r
                    .create_plugin_observer(type_name, object_source)
                    .map_err(construct_error)?;
                match &o.table {
                    ROption::RSome(table) => Built::Observer(Arc::new(
                        super::observer_table::host_copy(&o, table).map_err(|e| {
                            FactoryError::Param(format!(
                                "{} declares its colour-matching functions as a 1 nm table \
                                 (ColorObserver::table), but {e}",
                                origin.label
                            ))
                        })?,
                    )),
                    ROption::RNone => Built::Observer(Arc::new(PluginObserver::new(o, origin))),
                }
            }
            _ => return Err(unknown(kind, type_name)),
        })
    }

    fn blob(
        &self,
        kind: Kind,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Built, FactoryError> {
        let p = crate::scene_file::params::Params::new(params);
        p.expect_only(&["file"])?;
        let file = ctx.resolve(p.string("file")?);
        let blob = Blob::read_file(&file).map_err(|e| FactoryError::Param(e.to_string()))?;
        if Kind::from(blob.kind) != kind {
            return Err(FactoryError::Param(format!(
                "{}: holds a {}, not a {kind}",
                file.display(),
                blob.kind
            )));
        }
        blob.instantiate(self)
            .map_err(|e| FactoryError::Param(format!("{}: {e}", file.display())))
    }
}

macro_rules! unwrap_built {
    ($self:ident, $kind:ident, $type_name:ident, $params:ident, $ctx:ident) => {
        match $self.build(Kind::$kind, $type_name, Source::Params($params), $ctx)? {
            Built::$kind(x) => Ok(x),
            _ => Err(FactoryError::UnknownType {
                kind: Kind::$kind.as_str(),
                type_name: $type_name.to_string(),
            }),
        }
    };
}

impl ObjectFactory for PluginFactory {
    fn name(&self) -> &str {
        "registry"
    }

    fn known_types(&self) -> Vec<(&'static str, String)> {
        self.registry
            .types()
            .map(|t| (t.info.kind.as_str(), t.info.name.clone()))
            .collect()
    }

    fn param_docs(
        &self,
        kind: &'static str,
        type_name: &str,
    ) -> Option<Vec<crate::scene_file::type_doc::ParamDoc>> {
        let kind = Kind::parse(kind)?;
        // A light type with its own declared beam representation converts its own lengths.
        let own_units = |p: &super::LoadedPlugin| {
            p.info.types.iter().any(|t| {
                t.kind == ObjectKind::Light && t.name.as_str() == type_name && !t.beams.is_native()
            })
        };
        if kind == Kind::Light
            && matches!(
                self.registry.plugin_for(ObjectKind::Light, type_name),
                Ok(Some(p)) if own_units(&p)
            )
        {
            return Some(Vec::new());
        }
        Some(
            self.registry
                .lookup(kind, type_name)
                .ok()?
                .info
                .params
                .clone(),
        )
    }

    fn material(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError> {
        unwrap_built!(self, Material, type_name, params, ctx)
    }

    fn light(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError> {
        unwrap_built!(self, Light, type_name, params, ctx)
    }

    fn spd(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError> {
        unwrap_built!(self, Spd, type_name, params, ctx)
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
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn crate::color::Observer>, FactoryError> {
        unwrap_built!(self, Observer, type_name, params, ctx)
    }

    fn shape(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<Shape, FactoryError> {
        match self.registry.lookup(Kind::Shape, type_name) {
            Ok(super::registry::TypeEntry {
                builtin: Some(ty), ..
            }) => match ty.build {
                Build::Shape(f) => f(params, ctx),
                _ => Err(FactoryError::Param(format!("`{type_name}` is not a shape"))),
            },
            _ => Err(FactoryError::UnknownType {
                kind: "shape",
                type_name: type_name.to_string(),
            }),
        }
    }

    fn camera(
        &self,
        type_name: &str,
        params: &ron::Value,
        ctx: &FactoryContext,
    ) -> Result<(PerspectiveCamera, Filter), FactoryError> {
        match self.registry.lookup(Kind::Camera, type_name) {
            Ok(super::registry::TypeEntry {
                builtin: Some(ty), ..
            }) => match ty.build {
                Build::Camera(f) => f(params, ctx),
                _ => Err(FactoryError::Param(format!(
                    "`{type_name}` is not a camera"
                ))),
            },
            _ => Err(FactoryError::UnknownType {
                kind: "camera",
                type_name: type_name.to_string(),
            }),
        }
    }
}

impl RegistryFactory {
    /// Rebuild the object `blob` holds, built-in or from its plugin.
    pub fn build_blob(&self, blob: &Blob) -> Result<Built, String> {
        let kind = Kind::from(blob.kind);
        let ctx = self.context(
            Path::new("."),
            format!("{kind} `{}` (blob)", blob.type_name),
        );
        if blob.plugin == BUILTIN_PLUGIN {
            let ty = blob.builtin_type()?;
            // A built-in's state is built by the built-in itself, even in a registry where a
            // library provides the same name.
            let text = blob.builtin_params()?;
            let params: ron::Value =
                ron::from_str(&text).map_err(|e| format!("bad saved state: {e}"))?;
            return build_builtin(ty, &params, &ctx).map_err(|e| e.to_string());
        }
        blob.check_plugin(self.registry())
            .map_err(|e| e.to_string())?;
        let source = Source::State {
            type_version: blob.type_version,
            bytes: &blob.payload,
        };
        self.build(kind, &blob.type_name, source, &ctx)
            .map_err(|e| e.to_string())
    }
}

/// A built-in type's object from its parameters (a built-in blob's state).
fn build_builtin(
    ty: &crate::builtin::BuiltinType,
    params: &ron::Value,
    ctx: &FactoryContext,
) -> Result<Built, FactoryError> {
    Ok(match ty.build {
        Build::Material(f) => Built::Material(f(params, ctx)?),
        Build::Light(f) => Built::Light(f(params, ctx)?),
        Build::Spd(f) => Built::Spd(f(params, ctx)?),
        Build::Observer(f) => Built::Observer(f(params, ctx)?),
        Build::Shape(_) | Build::Camera(_) => {
            return Err(FactoryError::Param(
                "shapes and cameras are not blobs".into(),
            ))
        }
    })
}

/// The error of a type nobody provides.
fn unknown(kind: Kind, type_name: &str) -> FactoryError {
    FactoryError::UnknownType {
        kind: kind.as_str(),
        type_name: type_name.to_string(),
    }
}

/// Build the built-in type `ty` from parameters or from its saved state (shapes and cameras
/// are not built here: this factory does not know them).
fn builtin_from_source(
    ty: &BuiltinType,
    kind: Kind,
    type_name: &str,
    source: Source<'_>,
    ctx: &FactoryContext,
) -> Result<Built, FactoryError> {
    let owned;
    let params = match source {
        Source::Params(v) => v,
        Source::State { bytes, .. } => {
            let state = ty.state.ok_or_else(|| {
                FactoryError::Param(format!("a {kind} `{type_name}` cannot be a blob"))
            })?;
            let text = (state.load)(bytes)?;
            owned = ron::from_str::<ron::Value>(&text)
                .map_err(|e| FactoryError::Param(format!("bad saved state: {e}")))?;
            &owned
        }
    };
    if matches!(ty.build, Build::Shape(_) | Build::Camera(_)) {
        return Err(unknown(kind, type_name));
    }
    build_builtin(ty, params, ctx)
}
