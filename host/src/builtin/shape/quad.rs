//! `quad`: a parallelogram `corner + s·edge0 + t·edge1`, s, t ∈ [0, 1]; its normal is
//! `edge0 × edge1`.
//!
//! | parameter | unit         | default | meaning          |
//! |-----------|--------------|---------|------------------|
//! | `corner`  | object units | —       | one corner       |
//! | `edge0`   | object units | —       | first edge       |
//! | `edge1`   | object units | —       | second edge      |

use crate::builtin::{finite3, from_value, Build, BuiltinType};
use crate::geometry::Shape;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "quad",
    aliases: &[],
    version: 1,
    description: "parallelogram corner + s·edge0 + t·edge1, normal edge0 × edge1",
    params: &[
        Param::required("corner", "object units", "one corner, (x, y, z)"),
        Param::required("edge0", "object units", "first edge vector"),
        Param::required("edge1", "object units", "second edge vector"),
    ],
    build: Build::Shape(|v, ctx| build(&from_value(v)?, ctx)),
    state: None,
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadParams {
    /// A corner.
    pub corner: [f64; 3],
    /// First edge.
    pub edge0: [f64; 3],
    /// Second edge.
    pub edge1: [f64; 3],
}

/// Build the shape.
pub fn build(p: &QuadParams, _ctx: &FactoryContext) -> Result<Shape, FactoryError> {
    Ok(Shape::Quad {
        corner: finite3("corner", p.corner)?,
        edge0: finite3("edge0", p.edge0)?,
        edge1: finite3("edge1", p.edge1)?,
    })
}
