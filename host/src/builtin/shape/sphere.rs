//! `sphere`: an analytic sphere.
//!
//! | parameter | unit         | default     | meaning      |
//! |-----------|--------------|-------------|--------------|
//! | `center`  | object units | `(0, 0, 0)` | its centre   |
//! | `radius`  | object units | —           | radius, > 0  |

use crate::builtin::{finite, finite3, from_value, param_err, Build, BuiltinType};
use crate::geometry::Shape;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use glam::Vec3A;
use serde::{Deserialize, Serialize};

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "sphere",
    aliases: &[],
    version: 1,
    description: "analytic sphere",
    params: &[
        Param::optional("center", "object units", "(0, 0, 0)", "centre, (x, y, z)"),
        Param::required("radius", "object units", "radius, > 0"),
    ],
    build: Build::Shape(|v, ctx| build(&from_value(v)?, ctx)),
    state: None,
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereParams {
    /// Centre.
    #[serde(default)]
    pub center: Option<[f64; 3]>,
    /// Radius.
    pub radius: f64,
}

/// Build the shape.
pub fn build(p: &SphereParams, _ctx: &FactoryContext) -> Result<Shape, FactoryError> {
    let radius = finite("radius", p.radius)? as f32;
    if !(radius > 0.0) {
        return Err(param_err("radius", "must be > 0"));
    }
    Ok(Shape::Sphere {
        center: match p.center {
            Some(c) => finite3("center", c)?,
            None => Vec3A::ZERO,
        },
        radius,
    })
}
