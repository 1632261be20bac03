//! What a built-in type is ([`BuiltinType`]): its name, parameter table and constructor by
//! kind ([`Build`]), and how its parameter struct is saved into a blob and read back
//! ([`StateFns`], [`Embed`]).

use super::params_de::from_value;
use crate::camera::{Filter, PerspectiveCamera};
use crate::color::Observer;
use crate::geometry::Shape;
use crate::light::Light;
use crate::material::Material;
use crate::scene_file::type_doc::{Kind, Param, TypeDoc};
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::Spd;
use ron::Value;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::sync::Arc;

/// Build a material from its params.
pub type MaterialFn = fn(&Value, &FactoryContext) -> Result<Arc<dyn Material>, FactoryError>;
/// Build a light from its params.
pub type LightFn = fn(&Value, &FactoryContext) -> Result<Arc<dyn Light>, FactoryError>;
/// Build an SPD from its params.
pub type SpdFn = fn(&Value, &FactoryContext) -> Result<Arc<dyn Spd>, FactoryError>;
/// Build an observer from its params.
pub type ObserverFn = fn(&Value, &FactoryContext) -> Result<Arc<dyn Observer>, FactoryError>;
/// Build a shape (object space) from its params.
pub type ShapeFn = fn(&Value, &FactoryContext) -> Result<Shape, FactoryError>;
/// Build a camera and its pixel filter from its params.
pub type CameraFn =
    fn(&Value, &FactoryContext) -> Result<(PerspectiveCamera, Filter), FactoryError>;

/// A built-in type's constructor, by kind.
#[derive(Clone, Copy)]
pub enum Build {
    /// A material.
    Material(MaterialFn),
    /// A light.
    Light(LightFn),
    /// An SPD.
    Spd(SpdFn),
    /// An observer.
    Observer(ObserverFn),
    /// A shape.
    Shape(ShapeFn),
    /// A camera.
    Camera(CameraFn),
}

impl Build {
    /// The kind this constructor builds.
    pub fn kind(&self) -> Kind {
        match self {
            Build::Material(_) => Kind::Material,
            Build::Light(_) => Kind::Light,
            Build::Spd(_) => Kind::Spd,
            Build::Observer(_) => Kind::Observer,
            Build::Shape(_) => Kind::Shape,
            Build::Camera(_) => Kind::Camera,
        }
    }
}

/// Saving and restoring a built-in's parameters (blobs).
#[derive(Clone, Copy)]
pub struct StateFns {
    /// Params (scene syntax) → self-contained bincode state (files embedded).
    pub save: fn(&Value, &FactoryContext) -> Result<Vec<u8>, FactoryError>,
    /// Bincode state → params in scene syntax (RON text), which the constructor reads.
    pub load: fn(&[u8]) -> Result<String, FactoryError>,
}

/// A built-in type: its type information and its constructor.
#[derive(Clone, Copy)]
pub struct BuiltinType {
    /// Name scenes use.
    pub name: &'static str,
    /// Other names for the same type.
    pub aliases: &'static [&'static str],
    /// Version of the parameter struct (the blob state schema).
    pub version: u32,
    /// One line on what it is.
    pub description: &'static str,
    /// The parameter table.
    pub params: &'static [Param],
    /// The constructor.
    pub build: Build,
    /// Blob state, for the kinds that can be blobs (materials, lights, SPDs, observers).
    pub state: Option<StateFns>,
}

impl BuiltinType {
    /// Its kind.
    pub fn kind(&self) -> Kind {
        self.build.kind()
    }

    /// Its type information, under `name` (its own or an alias).
    pub fn doc(&self, name: &str) -> TypeDoc {
        TypeDoc {
            kind: self.kind(),
            name: name.to_string(),
            version: self.version,
            description: if name == self.name {
                self.description.to_string()
            } else {
                format!("alias of `{}`", self.name)
            },
            params: self.params.iter().map(Into::into).collect(),
            alias_of: (name != self.name).then(|| self.name.to_string()),
        }
    }
}

impl std::fmt::Debug for BuiltinType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} `{}`", self.kind(), self.name)
    }
}

/// Data a parameter struct reads from files, copied into it so that its saved state is
/// self-contained (a CSV spectrum becomes its table, a mesh file its triangles).
pub trait Embed {
    /// Replace every file reference by the file's data (paths resolve against `ctx`).
    fn embed(&mut self, _ctx: &FactoryContext) -> Result<(), FactoryError> {
        Ok(())
    }
}

/// [`StateFns`] of a parameter struct `P`.
pub const fn state_fns<P: Serialize + DeserializeOwned + Embed>() -> StateFns {
    StateFns {
        save: save_state::<P>,
        load: load_state::<P>,
    }
}

fn save_state<P: Serialize + DeserializeOwned + Embed>(
    params: &Value,
    ctx: &FactoryContext,
) -> Result<Vec<u8>, FactoryError> {
    let mut p: P = from_value(params)?;
    p.embed(ctx)?;
    bincode::serde::encode_to_vec(&p, bincode::config::standard())
        .map_err(|e| FactoryError::Param(format!("cannot encode the parameters: {e}")))
}

fn load_state<P: Serialize + DeserializeOwned + Embed>(
    bytes: &[u8],
) -> Result<String, FactoryError> {
    let (p, used): (P, usize) =
        bincode::serde::decode_from_slice(bytes, bincode::config::standard())
            .map_err(|e| FactoryError::Param(format!("cannot decode the saved state: {e}")))?;
    if used != bytes.len() {
        return Err(FactoryError::Param(format!(
            "cannot decode the saved state: {} bytes left over",
            bytes.len() - used
        )));
    }
    to_scene_text(&p)
}

/// A parameter struct in scene syntax.
pub fn to_scene_text<P: Serialize>(p: &P) -> Result<String, FactoryError> {
    ron::to_string(p).map_err(|e| FactoryError::Param(format!("cannot write the parameters: {e}")))
}
