//! `mesh`: a triangle mesh written inline.
//!
//! | parameter   | unit         | default | meaning                                   |
//! |-------------|--------------|---------|-------------------------------------------|
//! | `positions` | object units | —       | vertex positions, list of (x, y, z)       |
//! | `indices`   | —            | —       | triangles, list of (a, b, c) vertex indices |
//! | `normals`   | —            | none    | per-vertex shading normals, (x, y, z)     |
//! | `uvs`       | —            | none    | per-vertex texture coordinates, (u, v)    |

use crate::builtin::{from_value, param_err, Build, BuiltinType};
use crate::geometry::{Shape, TriangleMesh};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use glam::{Vec2, Vec3A};
use serde::{Deserialize, Serialize};

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "mesh",
    aliases: &[],
    version: 1,
    description: "triangle mesh given inline",
    params: &[
        Param::required(
            "positions",
            "object units",
            "vertex positions, list of (x, y, z)",
        ),
        Param::required("indices", "", "triangles, list of (a, b, c) vertex indices"),
        Param::optional(
            "normals",
            "",
            "none",
            "per-vertex shading normals, list of (x, y, z)",
        ),
        Param::optional(
            "uvs",
            "",
            "none",
            "per-vertex texture coordinates, list of (u, v)",
        ),
    ],
    build: Build::Shape(|v, ctx| build(&from_value(v)?, ctx)),
    state: None,
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshParams {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Triangles (whole numbers ≥ 0).
    pub indices: Vec<[f64; 3]>,
    /// Shading normals.
    #[serde(default)]
    pub normals: Option<Vec<[f64; 3]>>,
    /// Texture coordinates.
    #[serde(default)]
    pub uvs: Option<Vec<[f64; 2]>>,
}

fn vec3s(v: &[[f64; 3]]) -> Vec<Vec3A> {
    v.iter()
        .map(|l| Vec3A::new(l[0] as f32, l[1] as f32, l[2] as f32))
        .collect()
}

/// Build the shape.
pub fn build(p: &MeshParams, _ctx: &FactoryContext) -> Result<Shape, FactoryError> {
    let indices = p
        .indices
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if l.iter().all(|x| *x >= 0.0 && x.fract() == 0.0) {
                Ok([l[0] as u32, l[1] as u32, l[2] as u32])
            } else {
                Err(param_err(
                    "indices",
                    format!("entry {i} is not three vertex indices"),
                ))
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mesh = TriangleMesh {
        positions: vec3s(&p.positions),
        normals: p.normals.as_deref().map(vec3s),
        uvs: p.uvs.as_ref().map(|uv| {
            uv.iter()
                .map(|l| Vec2::new(l[0] as f32, l[1] as f32))
                .collect()
        }),
        indices,
    };
    mesh.validate()
        .map_err(|e| FactoryError::Param(e.to_string()))?;
    Ok(Shape::Mesh(mesh))
}
