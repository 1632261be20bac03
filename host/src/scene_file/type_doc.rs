//! What the registry knows about every type, built in or loaded: its kind, name, version,
//! description and parameter table. Plugin types arrive as the API's `TypeInfo` and are
//! converted; built-in types declare the same table in their own file (see [`crate::builtin`]).

use spectrace_plugin_api::abi::std_types::ROption;
use spectrace_plugin_api::{ObjectKind, TypeInfo};
use std::fmt;

/// Every kind of registered type. The first four are also what plugins can provide
/// ([`ObjectKind`]); shapes, cameras and integrators are host-only kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// A material (`materials: [...]`).
    Material,
    /// A light that is not an emissive surface (`lights: [...]`).
    Light,
    /// A spectral power distribution (`spd: (type: .., params: ..)`).
    Spd,
    /// A colour observer (`observer: "..."`).
    Observer,
    /// A geometry shape (`objects: [...]`).
    Shape,
    /// A camera (`cameras: [...]`).
    Camera,
    /// A rendering algorithm. Integrator types register under this kind with
    /// [`crate::plugin::Registry::register_builtin`]; the integrator module provides their constructors.
    Integrator,
}

impl Kind {
    /// All kinds in documentation order.
    pub const ALL: [Kind; 7] = [
        Kind::Material,
        Kind::Light,
        Kind::Spd,
        Kind::Observer,
        Kind::Shape,
        Kind::Camera,
        Kind::Integrator,
    ];

    /// Lower-case name as used in messages.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Material => "material",
            Kind::Light => "light",
            Kind::Spd => "spd",
            Kind::Observer => "observer",
            Kind::Shape => "shape",
            Kind::Camera => "camera",
            Kind::Integrator => "integrator",
        }
    }

    /// Parse [`Kind::as_str`] (also `object` for shapes).
    pub fn parse(s: &str) -> Option<Kind> {
        if s == "object" {
            return Some(Kind::Shape);
        }
        Kind::ALL.into_iter().find(|k| k.as_str() == s)
    }

    /// The plugin API's kind, for the kinds plugins can provide.
    pub fn object_kind(self) -> Option<ObjectKind> {
        Some(match self {
            Kind::Material => ObjectKind::Material,
            Kind::Light => ObjectKind::Light,
            Kind::Spd => ObjectKind::Spd,
            Kind::Observer => ObjectKind::Observer,
            _ => return None,
        })
    }
}

impl From<ObjectKind> for Kind {
    fn from(k: ObjectKind) -> Kind {
        match k {
            ObjectKind::Material => Kind::Material,
            ObjectKind::Light => Kind::Light,
            ObjectKind::Spd => Kind::Spd,
            ObjectKind::Observer => Kind::Observer,
        }
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One row of a parameter table.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDoc {
    /// Name as written in the scene.
    pub name: String,
    /// Unit (`W`, `nm`, `scene units`, …); empty when unitless.
    pub unit: String,
    /// Default in scene syntax; `None` when required.
    pub default: Option<String>,
    /// What it does.
    pub description: String,
}

/// A row of a built-in parameter table, as written in the type's file.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    /// Name as written in the scene.
    pub name: &'static str,
    /// Unit; empty when unitless.
    pub unit: &'static str,
    /// Default in scene syntax; `None` when required.
    pub default: Option<&'static str>,
    /// What it does.
    pub description: &'static str,
}

impl Param {
    /// A required parameter.
    pub const fn required(
        name: &'static str,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: None,
            description,
        }
    }

    /// An optional parameter with its default in scene syntax.
    pub const fn optional(
        name: &'static str,
        unit: &'static str,
        default: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: Some(default),
            description,
        }
    }
}

impl From<&Param> for ParamDoc {
    fn from(p: &Param) -> Self {
        ParamDoc {
            name: p.name.into(),
            unit: p.unit.into(),
            default: p.default.map(Into::into),
            description: p.description.into(),
        }
    }
}

/// Everything the registry, `spectrace plugins` and the scene-format reference say about a type.
#[derive(Clone, Debug, PartialEq)]
pub struct TypeDoc {
    /// Kind.
    pub kind: Kind,
    /// Name scenes use in `type: "..."`.
    pub name: String,
    /// Version of the parameter/state schema.
    pub version: u32,
    /// One line on what it is.
    pub description: String,
    /// The parameter table.
    pub params: Vec<ParamDoc>,
    /// For an alias: the name of the type it stands for.
    pub alias_of: Option<String>,
}

impl From<&TypeInfo> for TypeDoc {
    fn from(t: &TypeInfo) -> Self {
        TypeDoc {
            kind: t.kind.into(),
            name: t.name.to_string(),
            version: t.version,
            description: t.description.to_string(),
            params: t
                .params
                .iter()
                .map(|p| ParamDoc {
                    name: p.name.to_string(),
                    unit: p.unit.to_string(),
                    default: match &p.default {
                        ROption::RSome(d) => Some(d.to_string()),
                        ROption::RNone => None,
                    },
                    description: p.description.to_string(),
                })
                .collect(),
            alias_of: None,
        }
    }
}
