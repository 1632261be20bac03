//! Building materials, lights and SPDs from a scene item's `type` and `params`.
//!
//! [`ObjectFactory`] is the extension point: the [`crate::builtin::BuiltinFactory`] knows the built-in types and
//! the plugin registry implements the same trait for plugin types. The scene builder asks each
//! factory in turn; [`FactoryError::UnknownType`] means "not mine, ask the next one".

use super::params::ParamError;
use super::representation::RepresentationOptions;
use crate::camera::{Filter, PerspectiveCamera};
use crate::geometry::Shape;
use crate::light::Light;
use crate::material::Material;
use crate::spectrum::Spd;
use ron::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an item is being built: for relative paths and messages.
#[derive(Clone, Debug, PartialEq)]
pub struct FactoryContext {
    /// Directory of the scene file; relative paths resolve against it.
    pub base_dir: PathBuf,
    /// The item being built, e.g. `material "red"`.
    pub item: String,
    /// How spectral data are represented (defaults: as written).
    pub representation: RepresentationOptions,
    /// The scene's other factories that build SPD types, asked when the item's own factory does
    /// not know an SPD type: how a built-in light or material takes a plugin's spectrum.
    pub spd_factories: SpdFactories,
}

/// Factories asked for SPD types an item's own factory does not know (see
/// [`FactoryContext::spd_factories`]); compared by identity.
#[derive(Clone, Default)]
pub struct SpdFactories(pub Vec<Arc<dyn ObjectFactory>>);

impl std::fmt::Debug for SpdFactories {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.0.iter().map(|x| x.name()).collect();
        write!(f, "SpdFactories({names:?})")
    }
}

impl PartialEq for SpdFactories {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len() && self.0.iter().zip(&other.0).all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

impl SpdFactories {
    /// The first factory that knows SPD type `type_name` builds it; `None` when none does.
    pub fn build(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Option<Result<Arc<dyn Spd>, FactoryError>> {
        self.0
            .iter()
            .find_map(|f| match f.spd(type_name, params, ctx) {
                Err(FactoryError::UnknownType { .. }) => None,
                other => Some(other),
            })
    }

    /// A spec string `name(param: value, …)` or `name` naming an SPD type of one of these
    /// factories (the syntax plugins use with host services); `None` when it names none.
    pub fn build_spec(
        &self,
        spec: &str,
        ctx: &FactoryContext,
    ) -> Option<Result<Arc<dyn Spd>, FactoryError>> {
        if self.0.is_empty() {
            return None;
        }
        let (name, params) = crate::spectrum::spec::split_type_spec(spec);
        let params: Value = ron::from_str(params).ok()?;
        self.build(name, &params, ctx)
    }
}

impl FactoryContext {
    /// `path` resolved against the scene directory.
    pub fn resolve(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base_dir.join(p)
        }
    }
}

/// Why a factory could not build an item.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FactoryError {
    /// This factory does not know the type (the builder then asks the next factory).
    #[error("unknown {kind} type `{type_name}`")]
    UnknownType {
        /// `material`, `light` or `spd`.
        kind: &'static str,
        /// The type name.
        type_name: String,
    },
    /// A parameter is missing or invalid.
    #[error("{0}")]
    Param(String),
}

impl From<ParamError> for FactoryError {
    fn from(e: ParamError) -> Self {
        FactoryError::Param(e.to_string())
    }
}

/// Builds scene items from their type name and parameters. Object safe.
pub trait ObjectFactory: Send + Sync {
    /// A short name for messages (`builtin`, a plugin's name).
    fn name(&self) -> &str;

    /// Type names this factory builds, for "unknown type" messages: `(kind, type)`.
    fn known_types(&self) -> Vec<(&'static str, String)>;

    /// A material of type `type_name`.
    fn material(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError>;

    /// A (non-area) light of type `type_name`.
    fn light(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError>;

    /// A normalised SPD of type `type_name` (used where a params block gives
    /// `spd: (type: "...", params: (...))`).
    fn spd(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError>;

    /// This factory as a shared object for [`FactoryContext::spd_factories`], if it builds SPD
    /// types other factories' items may use (plugins do; the built-in types are already
    /// everywhere).
    fn shared_spd_factory(&self) -> Option<Arc<dyn ObjectFactory>> {
        None
    }

    /// The parameter table of `(kind, type_name)` when this factory builds it: the scene
    /// builder converts the parameters documented in `scene units` to metres (see
    /// [`super::units`]). `None` when the type is not this factory's.
    fn param_docs(
        &self,
        _kind: &'static str,
        _type_name: &str,
    ) -> Option<Vec<super::type_doc::ParamDoc>> {
        None
    }

    /// A colour observer of type `type_name`, for a scene's `observer` that is not one of the
    /// built-in CIE names (plugins can ship, say, a camera's sensor curves).
    fn observer(
        &self,
        type_name: &str,
        _params: &Value,
        _ctx: &FactoryContext,
    ) -> Result<Arc<dyn crate::color::Observer>, FactoryError> {
        Err(FactoryError::UnknownType {
            kind: "observer",
            type_name: type_name.to_string(),
        })
    }

    /// A shape (object space) of type `type_name`.
    fn shape(
        &self,
        type_name: &str,
        _params: &Value,
        _ctx: &FactoryContext,
    ) -> Result<Shape, FactoryError> {
        Err(FactoryError::UnknownType {
            kind: "shape",
            type_name: type_name.to_string(),
        })
    }

    /// A camera and its pixel filter, of type `type_name`.
    fn camera(
        &self,
        type_name: &str,
        _params: &Value,
        _ctx: &FactoryContext,
    ) -> Result<(PerspectiveCamera, Filter), FactoryError> {
        Err(FactoryError::UnknownType {
            kind: "camera",
            type_name: type_name.to_string(),
        })
    }
}
