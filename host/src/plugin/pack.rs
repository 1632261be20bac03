//! Packing a scene item, or a type and its parameters, into a [`Blob`], and building the object
//! a blob holds (through [`RegistryFactory::build_blob`]).

use super::adapter::PluginFaults;
use super::blob::{Blob, BUILTIN_PLUGIN};
use super::factory::{Built, RegistryFactory, Source, BLOB_LIGHT};
use super::host_registry::builtin_registry;
use super::registry::Registry;
use spectrace_plugin_api::ObjectKind;
use std::path::Path;

impl Blob {
    /// Save an object of `kind` (type and scene parameters, files relative to `base_dir`) as
    /// a self-contained blob. The object is built once first, so a blob with bad parameters is
    /// never written. Built-in types store their parameter struct as bincode with every file
    /// they read embedded; plugin types store their plugin's state.
    pub fn pack_item(
        factory: &RegistryFactory,
        kind: ObjectKind,
        type_name: &str,
        params: &ron::Value,
        base_dir: &Path,
    ) -> Result<Blob, String> {
        let registry = factory.registry();
        let entry = registry
            .lookup(kind, type_name)
            .map_err(|e| e.to_string())?;
        let Some(ty) = entry.builtin else {
            if type_name == BLOB_LIGHT {
                return Err("a blob cannot be packed into a blob; copy the file instead".into());
            }
            let text = ron::to_string(params).map_err(|e| e.to_string())?;
            return Self::pack_plugin(registry, kind, type_name, &text).map_err(|e| e.to_string());
        };
        let ctx = factory.context(base_dir, format!("{kind} `{type_name}`"));
        factory
            .build(kind.into(), type_name, Source::Params(params), &ctx)
            .map_err(|e| format!("built-in {kind} `{type_name}`: {e}"))?;
        let state = ty
            .state
            .ok_or_else(|| format!("a {kind} `{type_name}` cannot be a blob"))?;
        let payload = (state.save)(params, &ctx)
            .map_err(|e| format!("built-in {kind} `{type_name}`: {e}"))?;
        Ok(Blob {
            kind,
            plugin: BUILTIN_PLUGIN.to_string(),
            plugin_version: env!("CARGO_PKG_VERSION").to_string(),
            type_name: ty.name.to_string(),
            type_version: ty.version,
            payload,
        })
    }

    /// Save a built-in light (type and RON parameters) as a blob; relative files resolve
    /// against the working directory.
    pub fn pack_builtin_light(type_name: &str, params: &ron::Value) -> Result<Blob, String> {
        let factory =
            RegistryFactory::new(std::sync::Arc::new(builtin_registry()), PluginFaults::new());
        Self::pack_item(
            &factory,
            ObjectKind::Light,
            type_name,
            params,
            Path::new("."),
        )
    }

    /// Save the item `name` of `kind` of a scene file as a blob (built-in or plugin type). For
    /// an observer, `name` is the scene's `observer` type name.
    pub fn pack_scene_item(
        registry: &Registry,
        scene: &Path,
        kind: ObjectKind,
        name: &str,
    ) -> Result<Blob, String> {
        let text = std::fs::read_to_string(scene)
            .map_err(|e| format!("{}: cannot read: {e}", scene.display()))?;
        let desc = crate::scene::parse_scene_str(&text, scene).map_err(|e| e.to_string())?;
        let (type_name, params) = match kind {
            ObjectKind::Observer => {
                let (obs, params) = desc
                    .observer
                    .as_ref()
                    .map(|o| o.type_and_params())
                    .unwrap_or(("cie1931-2", ron::Value::Unit));
                if obs != name {
                    return Err(format!(
                        "{}: the scene's observer is `{obs}`, not `{name}`",
                        scene.display()
                    ));
                }
                (obs.to_string(), params)
            }
            _ => {
                let items = match kind {
                    ObjectKind::Light => &desc.lights,
                    ObjectKind::Material => &desc.materials,
                    _ => &Vec::new(),
                };
                let found = if kind == ObjectKind::Spd {
                    find_scene_spd(&desc, name)
                } else {
                    items
                        .iter()
                        .find(|l| l.name == name)
                        .map(|i| (i.type_name.clone(), i.params.clone()))
                };
                found.ok_or_else(|| {
                    let names: Vec<String> = if kind == ObjectKind::Spd {
                        scene_spd_names(&desc)
                    } else {
                        items.iter().map(|l| l.name.clone()).collect()
                    };
                    format!(
                        "{}: no {kind} named `{name}` ({kind}s: {})",
                        scene.display(),
                        names.join(", ")
                    )
                })?
            }
        };
        let factory =
            RegistryFactory::new(std::sync::Arc::new(registry.clone()), PluginFaults::new());
        // A blob's lengths are metres: a light's parameters in the scene's unit are converted
        // as the scene builder converts them.
        let params = if kind == ObjectKind::Light {
            let unit = crate::scene_file::LengthUnit::parse(desc.units.as_deref().unwrap_or("m"))
                .map_err(|e| format!("{}: units: {e}", scene.display()))?;
            match crate::scene_file::ObjectFactory::param_docs(&factory, "light", &type_name) {
                Some(docs) => {
                    crate::scene_file::units::params_in_metres(&params, &docs, unit.metres())
                }
                None => params,
            }
        } else {
            params
        };
        let base = scene.parent().unwrap_or(Path::new("."));
        Self::pack_item(&factory, kind, &type_name, &params, base)
            .map_err(|e| format!("{}: {kind} `{name}`: {e}", scene.display()))
    }

    /// Save the light named `light` of a scene file as a blob (built-in or plugin type).
    pub fn pack_scene_light(
        registry: &Registry,
        scene: &Path,
        light: &str,
    ) -> Result<Blob, String> {
        Self::pack_scene_item(registry, scene, ObjectKind::Light, light)
    }

    /// Rebuild the object this blob holds, built-in or from its plugin, through `factory`
    /// (see [`RegistryFactory::build_blob`]).
    pub fn instantiate(&self, factory: &RegistryFactory) -> Result<Built, String> {
        factory.build_blob(self)
    }
}

/// SPDs of a scene that can be packed by name: `LIGHT.spd` or `MATERIAL.radiance` (the
/// spectral parameter of a light or emissive material), as `(type: "spec", params: (spec: ..))`
/// or the item's own `(type: .., params: ..)`.
fn find_scene_spd(
    desc: &crate::scene_file::SceneDescription,
    name: &str,
) -> Option<(String, ron::Value)> {
    let (item, param) = name.split_once('.')?;
    let owner = desc
        .lights
        .iter()
        .chain(desc.materials.iter())
        .find(|i| i.name == item)?;
    let value = crate::scene_file::params::Params::new(&owner.params)
        .get(param)?
        .clone();
    let p = crate::scene_file::params::Params::new(&value);
    if let (Some(ron::Value::String(t)), true) =
        (p.get("type"), matches!(value, ron::Value::Map(_)))
    {
        return Some((
            t.clone(),
            p.get("params").cloned().unwrap_or(ron::Value::Unit),
        ));
    }
    let key = if matches!(value, ron::Value::Seq(_)) {
        "values"
    } else {
        "spec"
    };
    let mut m = ron::Map::new();
    m.insert(ron::Value::String(key.into()), value);
    Some((
        if key == "values" { "table" } else { "spec" }.to_string(),
        ron::Value::Map(m),
    ))
}

fn scene_spd_names(desc: &crate::scene_file::SceneDescription) -> Vec<String> {
    let mut out = Vec::new();
    for (items, param) in [(&desc.lights, "spd"), (&desc.materials, "radiance")] {
        for i in items {
            if crate::scene_file::params::Params::new(&i.params)
                .get(param)
                .is_some()
            {
                out.push(format!("{}.{param}", i.name));
            }
        }
    }
    out
}
