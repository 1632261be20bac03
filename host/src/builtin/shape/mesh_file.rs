//! `obj` and `ply`: a triangle mesh read from a Wavefront OBJ or a PLY file (ASCII or binary).
//! Two types in one file because they differ only in the reader.
//!
//! | parameter | unit | default | meaning                                      |
//! |-----------|------|---------|----------------------------------------------|
//! | `file`    | —    | —       | the mesh file, relative to the scene file    |

use crate::builtin::{from_value, Build, BuiltinType};
use crate::geometry::{load_obj, load_ply, Shape};
use crate::plugin::type_doc::Param;
use crate::scene::FactoryError;
use serde::{Deserialize, Serialize};

/// Wavefront OBJ.
pub const OBJ: BuiltinType = BuiltinType {
    name: "obj",
    aliases: &[],
    version: 1,
    description: "triangle mesh from a Wavefront OBJ file",
    params: &[Param::required(
        "file",
        "",
        "OBJ file, relative to the scene file",
    )],
    build: Build::Shape(|v, ctx| {
        let p: MeshFileParams = from_value(v)?;
        load_obj(&ctx.resolve(&p.file))
            .map(Shape::Mesh)
            .map_err(|e| FactoryError::Param(e.to_string()))
    }),
    state: None,
};

/// PLY.
pub const PLY: BuiltinType = BuiltinType {
    name: "ply",
    aliases: &[],
    version: 1,
    description: "triangle mesh from a PLY file (ASCII or binary)",
    params: &[Param::required(
        "file",
        "",
        "PLY file, relative to the scene file",
    )],
    build: Build::Shape(|v, ctx| {
        let p: MeshFileParams = from_value(v)?;
        load_ply(&ctx.resolve(&p.file))
            .map(Shape::Mesh)
            .map_err(|e| FactoryError::Param(e.to_string()))
    }),
    state: None,
};

/// Parameters of [`OBJ`] and [`PLY`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshFileParams {
    /// The file.
    pub file: String,
}
