//! One registry maps (kind, type name) to whoever provides the type: a built-in or a loaded
//! plugin. Scenes and the CLI ask it by name and never care which. Duplicate names are refused
//! at registration, naming both providers; unknown names list what is available.

use super::loader::{load_dir, load_library, LoadError, LoadedPlugin};
use super::services::{HostServices, PluginSpds};
use crate::builtin::BuiltinType;
use crate::scene_file::type_doc::{Kind, TypeDoc};
use spectrace_plugin_api::abi::std_types::{RResult, RSlice, RStr};
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::HostRef;
use spectrace_plugin_api::{
    LightObject, MaterialObject, ObjectKind, ObserverObject, PluginError, SpdObject, TypeInfo,
};
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// Who provides a type.
#[derive(Clone, Debug)]
pub enum Provider {
    /// Compiled into the host.
    Builtin,
    /// A loaded plugin library.
    Plugin(Arc<LoadedPlugin>),
}

impl Provider {
    /// "built-in" or "plugin NAME VERSION (PATH)".
    pub fn describe(&self) -> String {
        match self {
            Provider::Builtin => "built-in".to_string(),
            Provider::Plugin(p) => format!(
                "plugin `{}` {} ({})",
                p.info.name,
                p.info.version,
                p.path.display()
            ),
        }
    }
}

/// One registered type.
#[derive(Clone, Debug)]
pub struct TypeEntry {
    /// Its metadata: kind, name, version, parameters (and, for an alias, what it stands for).
    pub info: TypeDoc,
    /// Who provides it.
    pub provider: Provider,
    /// For built-ins: the type and its constructor (`None` for the host's own `blob` types,
    /// which the registry's factory builds itself, and for types registered by information
    /// only).
    pub builtin: Option<&'static BuiltinType>,
}

/// Why a registry operation failed.
#[derive(Debug, Clone)]
pub enum RegistryError {
    /// A library could not be loaded.
    Load(LoadError),
    /// Two providers claim the same (kind, name), or two plugins the same plugin name.
    Duplicate {
        /// What is duplicated, e.g. "light type `point`".
        what: String,
        /// The provider already registered.
        existing: String,
        /// The one refused.
        refused: String,
    },
    /// No provider for this (kind, name).
    UnknownType {
        /// Kind asked for.
        kind: Kind,
        /// Name asked for.
        name: String,
        /// Names of that kind that do exist.
        known: Vec<String>,
    },
    /// The provider's constructor refused (the message names the parameter).
    Construct {
        /// Kind.
        kind: Kind,
        /// Type name.
        name: String,
        /// Provider description.
        provider: String,
        /// The plugin's error.
        error: PluginError,
    },
}

impl fmt::Display for RegistryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RegistryError::Load(e) => write!(f, "{e}"),
            RegistryError::Duplicate {
                what,
                existing,
                refused,
            } => write!(
                f,
                "duplicate {what}: already provided by {existing}; refused from {refused}"
            ),
            RegistryError::UnknownType { kind, name, known } => write!(
                f,
                "unknown {kind} type `{name}` (known {kind} types: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ),
            RegistryError::Construct {
                kind,
                name,
                provider,
                error,
            } => write!(f, "{kind} `{name}` from {provider}: {error}"),
        }
    }
}

impl std::error::Error for RegistryError {}

impl RegistryError {
    /// The message with the full loader report, for `--verbose`.
    pub fn verbose(&self) -> String {
        match self {
            RegistryError::Load(e) => e.verbose(),
            other => other.to_string(),
        }
    }
}

/// The registry of every type the host can build.
#[derive(Default, Clone)]
pub struct Registry {
    plugins: Vec<Arc<LoadedPlugin>>,
    types: BTreeMap<(Kind, String), TypeEntry>,
}

impl fmt::Debug for Registry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Registry")
            .field("plugins", &self.plugins.len())
            .field("types", &self.types.len())
            .finish()
    }
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Register a type by its information only (no constructor); same duplicate rule as for
    /// plugins. Used for names the host reserves and builds itself.
    pub fn register_builtin(&mut self, info: TypeInfo) -> Result<(), RegistryError> {
        self.register_doc(TypeDoc::from(&info))
    }

    /// [`Registry::register_builtin`] with the host's own type information (any kind).
    pub fn register_doc(&mut self, info: TypeDoc) -> Result<(), RegistryError> {
        self.insert(TypeEntry {
            info,
            provider: Provider::Builtin,
            builtin: None,
        })
    }

    /// Register a built-in type and each of its aliases (as entries of their own, so a plugin
    /// type of an alias's name is refused too).
    pub fn register_builtin_type(&mut self, ty: &'static BuiltinType) -> Result<(), RegistryError> {
        for name in std::iter::once(ty.name).chain(ty.aliases.iter().copied()) {
            self.insert(TypeEntry {
                info: ty.doc(name),
                provider: Provider::Builtin,
                builtin: Some(ty),
            })?;
        }
        Ok(())
    }

    fn insert(&mut self, entry: TypeEntry) -> Result<(), RegistryError> {
        let key = (entry.info.kind, entry.info.name.clone());
        if let Some(existing) = self.types.get(&key) {
            return Err(RegistryError::Duplicate {
                what: format!("{} type `{}`", key.0, key.1),
                existing: existing.provider.describe(),
                refused: entry.provider.describe(),
            });
        }
        self.types.insert(key, entry);
        Ok(())
    }

    /// Add a loaded plugin and all its types. All or nothing: on a duplicate nothing of the
    /// plugin is registered.
    pub fn add_plugin(&mut self, plugin: LoadedPlugin) -> Result<(), RegistryError> {
        let plugin = Arc::new(plugin);
        let provider = Provider::Plugin(plugin.clone());
        if let Some(other) = self
            .plugins
            .iter()
            .find(|p| p.info.name == plugin.info.name)
        {
            return Err(RegistryError::Duplicate {
                what: format!("plugin name `{}`", plugin.info.name),
                existing: Provider::Plugin(other.clone()).describe(),
                refused: provider.describe(),
            });
        }
        let mut seen = std::collections::BTreeSet::new();
        for t in plugin.info.types.iter() {
            let key = (Kind::from(t.kind), t.name.to_string());
            if let Some(existing) = self.types.get(&key) {
                return Err(RegistryError::Duplicate {
                    what: format!("{} type `{}`", t.kind, t.name),
                    existing: existing.provider.describe(),
                    refused: provider.describe(),
                });
            }
            if !seen.insert(key) {
                return Err(RegistryError::Duplicate {
                    what: format!("{} type `{}`", t.kind, t.name),
                    existing: provider.describe(),
                    refused: format!("{} (it lists the type twice)", provider.describe()),
                });
            }
        }
        for t in plugin.info.types.iter() {
            self.types.insert(
                (t.kind.into(), t.name.to_string()),
                TypeEntry {
                    info: TypeDoc::from(t),
                    provider: provider.clone(),
                    builtin: None,
                },
            );
        }
        self.plugins.push(plugin);
        Ok(())
    }

    /// Load a library and add it.
    pub fn load_plugin(&mut self, path: &Path) -> Result<(), RegistryError> {
        let plugin = load_library(path).map_err(RegistryError::Load)?;
        self.add_plugin(plugin)
    }

    /// Load a library only if its file's SHA-256 is `sha256` (a mismatch is refused naming both
    /// hashes, see [`super::pin`]), and add it.
    pub fn load_plugin_pinned(&mut self, path: &Path, sha256: &str) -> Result<(), RegistryError> {
        let plugin =
            super::loader::load_library_pinned(path, Some(sha256)).map_err(RegistryError::Load)?;
        self.add_plugin(plugin)
    }

    /// Load the libraries a scene file lists in its `plugins` field (paths relative to the
    /// scene file; pinned ones checked), skipping a library already loaded from the same file.
    /// A scene without the field loads nothing. Errors name the scene file.
    pub fn load_scene_plugins(&mut self, scene: &Path) -> Result<(), String> {
        let list = crate::scene_file::pin::scene_plugins(scene)?;
        let base = scene.parent().unwrap_or(Path::new("."));
        for item in list {
            let path = item.resolve(base);
            let canonical = std::fs::canonicalize(&path).ok();
            let already = self
                .plugins
                .iter()
                .find(|p| canonical.is_some() && std::fs::canonicalize(&p.path).ok() == canonical);
            if let Some(p) = already {
                if let (Some(want), Some(have)) = (item.sha256(), &p.sha256) {
                    crate::scene_file::pin::check(want, have).map_err(|e| {
                        format!("{}: plugins: {}: {e}", scene.display(), path.display())
                    })?;
                }
                continue;
            }
            let r = match item.sha256() {
                Some(sha) => self.load_plugin_pinned(&path, sha),
                None => self.load_plugin(&path),
            };
            r.map_err(|e| format!("{}: plugins: {e}", scene.display()))?;
        }
        Ok(())
    }

    /// Load a library whose types replace the built-in types of the same kind and name (with
    /// those types' aliases) instead of clashing with them: how the standard set from a library
    /// (`plugins/standard`) is used in place of the built-ins (`--replace-builtins`). Clashes
    /// with other plugins and with the host's `blob` types are still refused; all or nothing.
    pub fn load_plugin_replacing_builtins(&mut self, path: &Path) -> Result<(), RegistryError> {
        let plugin = load_library(path).map_err(RegistryError::Load)?;
        let mut next = self.clone();
        for t in plugin.info.types.iter() {
            let kind = Kind::from(t.kind);
            let Some(entry) = next.types.get(&(kind, t.name.to_string())) else {
                continue;
            };
            if entry.builtin.is_none() {
                continue;
            }
            let canonical = entry
                .info
                .alias_of
                .clone()
                .unwrap_or_else(|| t.name.to_string());
            next.types.retain(|(k, n), e| {
                !(*k == kind
                    && e.builtin.is_some()
                    && (*n == canonical || e.info.alias_of.as_deref() == Some(&canonical)))
            });
        }
        next.add_plugin(plugin)?;
        *self = next;
        Ok(())
    }

    /// Load every library of a directory; the errors of those refused are returned, the rest
    /// are registered.
    pub fn load_plugin_dir(&mut self, dir: &Path) -> Vec<RegistryError> {
        match load_dir(dir) {
            Err(e) => vec![RegistryError::Load(e)],
            Ok((loaded, mut errors)) => {
                let mut out: Vec<RegistryError> =
                    errors.drain(..).map(RegistryError::Load).collect();
                for p in loaded {
                    if let Err(e) = self.add_plugin(p) {
                        out.push(e);
                    }
                }
                out
            }
        }
    }

    /// Loaded plugins, in load order.
    pub fn plugins(&self) -> &[Arc<LoadedPlugin>] {
        &self.plugins
    }

    /// Every registered type, sorted by kind then name.
    pub fn types(&self) -> impl Iterator<Item = &TypeEntry> {
        self.types.values()
    }

    /// Is (kind, name) registered?
    pub fn contains(&self, kind: impl Into<Kind>, name: &str) -> bool {
        self.types.contains_key(&(kind.into(), name.to_string()))
    }

    /// Find (kind, name), or say what exists.
    pub fn lookup(&self, kind: impl Into<Kind>, name: &str) -> Result<&TypeEntry, RegistryError> {
        let kind = kind.into();
        self.types
            .get(&(kind, name.to_string()))
            .ok_or_else(|| RegistryError::UnknownType {
                kind,
                name: name.to_string(),
                known: self
                    .types
                    .keys()
                    .filter(|(k, _)| *k == kind)
                    .map(|(_, n)| n.clone())
                    .collect(),
            })
    }

    /// The plugin that provides (kind, name); `None` for built-ins.
    pub fn plugin_for(
        &self,
        kind: impl Into<Kind>,
        name: &str,
    ) -> Result<Option<Arc<LoadedPlugin>>, RegistryError> {
        Ok(match &self.lookup(kind, name)?.provider {
            Provider::Builtin => None,
            Provider::Plugin(p) => Some(p.clone()),
        })
    }

    fn plugin_entry(
        &self,
        kind: ObjectKind,
        name: &str,
    ) -> Result<(Arc<LoadedPlugin>, String), RegistryError> {
        let entry = self.lookup(kind, name)?;
        match &entry.provider {
            Provider::Plugin(p) => Ok((p.clone(), entry.provider.describe())),
            Provider::Builtin => Err(RegistryError::Construct {
                kind: kind.into(),
                name: name.to_string(),
                provider: "built-in".to_string(),
                error: PluginError::unsupported(
                    "built-in types are built by the host directly, not through the plugin ABI",
                ),
            }),
        }
    }

    /// Call `construct` on the root module of the plugin that provides (kind, name), with the
    /// host's services lent for the call; the plugin's error is wrapped with type and provider.
    fn call_plugin<T>(
        &self,
        kind: ObjectKind,
        name: &str,
        construct: impl FnOnce(&LoadedPlugin, HostRef<'_>) -> RResult<T, PluginError>,
    ) -> Result<T, RegistryError> {
        let (plugin, provider) = self.plugin_entry(kind, name)?;
        let services = HostServices::new(self);
        construct(&plugin, services.as_ref())
            .into_result()
            .map_err(|error| construct_error(kind.into(), name, provider, error))
    }

    /// Build a plugin light from parameters (RON text) or saved state.
    pub fn create_plugin_light(
        &self,
        name: &str,
        source: ObjectSource<'_>,
    ) -> Result<LightObject, RegistryError> {
        self.call_plugin(ObjectKind::Light, name, |p, host| {
            (p.module.create_light())(RStr::from_str(name), source, host)
        })
    }

    /// Build a plugin SPD.
    pub fn create_plugin_spd(
        &self,
        name: &str,
        source: ObjectSource<'_>,
    ) -> Result<SpdObject, RegistryError> {
        self.call_plugin(ObjectKind::Spd, name, |p, host| {
            (p.module.create_spd())(RStr::from_str(name), source, host)
        })
    }

    /// Build a plugin observer.
    pub fn create_plugin_observer(
        &self,
        name: &str,
        source: ObjectSource<'_>,
    ) -> Result<ObserverObject, RegistryError> {
        self.call_plugin(ObjectKind::Observer, name, |p, host| {
            (p.module.create_observer())(RStr::from_str(name), source, host)
        })
    }

    /// Build a plugin material.
    pub fn create_plugin_material(
        &self,
        name: &str,
        source: ObjectSource<'_>,
    ) -> Result<MaterialObject, RegistryError> {
        self.call_plugin(ObjectKind::Material, name, |p, host| {
            (p.module.create_material())(RStr::from_str(name), source, host)
        })
    }

    /// Decode a plugin type's saved state into RON parameters.
    pub fn describe_plugin_state(
        &self,
        kind: ObjectKind,
        name: &str,
        type_version: u32,
        bytes: &[u8],
    ) -> Result<String, RegistryError> {
        self.call_plugin(kind, name, |p, _| {
            (p.module.describe_state())(
                kind,
                RStr::from_str(name),
                type_version,
                RSlice::from_slice(bytes),
            )
        })
        .map(|s| s.into_string())
    }
}

fn construct_error(kind: Kind, name: &str, provider: String, error: PluginError) -> RegistryError {
    RegistryError::Construct {
        kind,
        name: name.to_string(),
        provider,
        error,
    }
}

/// The services lent to plugin constructors build plugin SPDs through the registry.
impl PluginSpds for Registry {
    fn provides_spd(&self, name: &str) -> bool {
        matches!(self.plugin_for(ObjectKind::Spd, name), Ok(Some(_)))
    }

    fn create_spd(&self, name: &str, params: &str) -> Result<SpdObject, String> {
        self.create_plugin_spd(name, ObjectSource::Params(RStr::from_str(params)))
            .map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every built-in name and alias registers without a clash (names are unique), and a type
    /// of another provider under an alias's name is refused naming both providers.
    #[test]
    fn builtin_names_are_unique_and_aliases_are_reserved() {
        let mut r = Registry::new();
        for ty in crate::builtin::all() {
            r.register_builtin_type(ty).unwrap();
        }
        for (kind, alias, target) in [
            (Kind::Material, "diffuse", "lambertian"),
            (Kind::Material, "rough_conductor", "conductor"),
            (Kind::Material, "area_light", "emissive"),
            (Kind::Camera, "thin_lens", "perspective"),
        ] {
            let e = r.lookup(kind, alias).unwrap();
            assert_eq!(e.info.alias_of.as_deref(), Some(target));
            let err = r
                .register_doc(TypeDoc {
                    kind,
                    name: alias.into(),
                    version: 1,
                    description: "another".into(),
                    params: Vec::new(),
                    alias_of: None,
                })
                .unwrap_err()
                .to_string();
            assert!(
                err.contains(&format!("duplicate {kind} type `{alias}`"))
                    && err.contains("already provided by built-in"),
                "{err}"
            );
        }
    }
}
