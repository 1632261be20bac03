//! The built-in types as an [`ObjectFactory`]: the scene builder asks it for every type no
//! plugin provides.

use super::built_in_type::{Build, BuiltinType};
use crate::camera::{Filter, PerspectiveCamera};
use crate::geometry::Shape;
use crate::light::Light;
use crate::material::Material;
use crate::scene_file::type_doc::Kind;
use crate::scene_file::{FactoryContext, FactoryError, ObjectFactory};
use crate::spectrum::Spd;
use ron::Value;
use std::sync::Arc;

/// The built-in types of [`crate::builtin`] as a factory: each type is found in that table (by
/// name or alias) and built by the constructor in its own file. The registry builds built-ins
/// through the same table, so a scene renders the same through either.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuiltinFactory;

fn builtin(kind: Kind, type_name: &str) -> Result<&'static BuiltinType, FactoryError> {
    super::registry::find(kind, type_name).ok_or_else(|| FactoryError::UnknownType {
        kind: kind.as_str(),
        type_name: type_name.to_string(),
    })
}

/// Build the built-in type `$type_name` of kind `$kind` with its own constructor.
macro_rules! build_as {
    ($kind:ident, $type_name:expr, $params:expr, $ctx:expr) => {
        match builtin(Kind::$kind, $type_name)?.build {
            Build::$kind(f) => f($params, $ctx),
            _ => Err(FactoryError::UnknownType {
                kind: Kind::$kind.as_str(),
                type_name: $type_name.to_string(),
            }),
        }
    };
}

impl ObjectFactory for BuiltinFactory {
    fn name(&self) -> &str {
        "builtin"
    }

    fn param_docs(
        &self,
        kind: &'static str,
        type_name: &str,
    ) -> Option<Vec<crate::scene_file::type_doc::ParamDoc>> {
        let ty = super::registry::find(Kind::parse(kind)?, type_name)?;
        Some(ty.doc(type_name).params)
    }

    fn known_types(&self) -> Vec<(&'static str, String)> {
        Kind::ALL
            .into_iter()
            .flat_map(|k| {
                super::registry::names(k)
                    .into_iter()
                    .map(move |n| (k.as_str(), n))
            })
            .collect()
    }

    fn material(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Material>, FactoryError> {
        build_as!(Material, type_name, params, ctx)
    }

    fn light(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Light>, FactoryError> {
        build_as!(Light, type_name, params, ctx)
    }

    fn spd(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn Spd>, FactoryError> {
        build_as!(Spd, type_name, params, ctx)
    }

    fn observer(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Arc<dyn crate::color::Observer>, FactoryError> {
        build_as!(Observer, type_name, params, ctx)
    }

    fn shape(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<Shape, FactoryError> {
        build_as!(Shape, type_name, params, ctx)
    }

    fn camera(
        &self,
        type_name: &str,
        params: &Value,
        ctx: &FactoryContext,
    ) -> Result<(PerspectiveCamera, Filter), FactoryError> {
        build_as!(Camera, type_name, params, ctx)
    }
}
