//! `obj` and `ply`: a triangle mesh read from a Wavefront OBJ or a PLY file (ASCII or binary).
//! Two types in one file because they differ only in the reader.
//!
//! | parameter | unit | default | meaning                                      |
//! |-----------|------|---------|----------------------------------------------|
//! | `file`    | —    | —       | the mesh file, relative to the scene file    |
//! | `flip_v`  | —    | false   | texture coordinate v read as 1 − v (for files written with v = 0 at the image's top row, as Mitsuba reads PLY files) |

use crate::builtin::{from_value, Build, BuiltinType};
use crate::geometry::{load_obj, load_ply, Shape};
use crate::scene_file::type_doc::Param;
use crate::scene_file::FactoryError;
use serde::{Deserialize, Serialize};

/// Wavefront OBJ.
pub const OBJ: BuiltinType = BuiltinType {
    name: "obj",
    aliases: &[],
    version: 1,
    description: "triangle mesh from a Wavefront OBJ file",
    params: &[
        Param::required("file", "", "OBJ file, relative to the scene file"),
        Param::optional(
            "flip_v",
            "",
            "false",
            "texture coordinate v read as 1 − v (uvs written with v = 0 at the image's top row)",
        ),
    ],
    build: Build::Shape(|v, ctx| {
        let p: MeshFileParams = from_value(v)?;
        load_obj(&ctx.resolve(&p.file))
            .map(|m| Shape::Mesh(p.apply(m)))
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
    params: &[
        Param::required("file", "", "PLY file, relative to the scene file"),
        Param::optional(
            "flip_v",
            "",
            "false",
            "texture coordinate v read as 1 − v (uvs written with v = 0 at the image's top row)",
        ),
    ],
    build: Build::Shape(|v, ctx| {
        let p: MeshFileParams = from_value(v)?;
        load_ply(&ctx.resolve(&p.file))
            .map(|m| Shape::Mesh(p.apply(m)))
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
    /// Texture coordinate v read as 1 − v.
    #[serde(default)]
    pub flip_v: bool,
}

impl MeshFileParams {
    /// The mesh with its texture coordinates flipped in v when asked.
    fn apply(&self, mut m: crate::geometry::TriangleMesh) -> crate::geometry::TriangleMesh {
        if self.flip_v {
            if let Some(uvs) = &mut m.uvs {
                for t in uvs {
                    t.y = 1.0 - t.y;
                }
            }
        }
        m
    }
}
