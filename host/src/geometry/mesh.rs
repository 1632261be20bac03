//! Indexed triangle meshes (object or world space) and their validation.

use glam::{Vec2, Vec3A};

use super::GeometryError;

/// A triangle mesh: shared vertices with optional per-vertex normals and texture coordinates.
/// Counter-clockwise winding (seen from outside) is the front face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions (scene units).
    pub positions: Vec<Vec3A>,
    /// Optional per-vertex shading normals (same length as `positions`; need not be unit).
    pub normals: Option<Vec<Vec3A>>,
    /// Optional per-vertex texture coordinates (same length as `positions`).
    pub uvs: Option<Vec<Vec2>>,
    /// Triangles as indices into `positions`.
    pub indices: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Checks lengths, index ranges and finiteness. Degenerate (zero-area) triangles are
    /// allowed: they are never hit and have zero sampling weight.
    pub fn validate(&self) -> Result<(), GeometryError> {
        let n = self.positions.len();
        if let Some(ns) = &self.normals {
            if ns.len() != n {
                return Err(GeometryError::InvalidMesh(format!(
                    "{} normals for {n} positions",
                    ns.len()
                )));
            }
            if let Some(i) = ns.iter().position(|v| !v.is_finite()) {
                return Err(GeometryError::InvalidMesh(format!(
                    "normal {i} is not finite"
                )));
            }
        }
        if let Some(uvs) = &self.uvs {
            if uvs.len() != n {
                return Err(GeometryError::InvalidMesh(format!(
                    "{} uvs for {n} positions",
                    uvs.len()
                )));
            }
            if let Some(i) = uvs.iter().position(|v| !v.is_finite()) {
                return Err(GeometryError::InvalidMesh(format!("uv {i} is not finite")));
            }
        }
        if let Some(i) = self.positions.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::InvalidMesh(format!(
                "position {i} is not finite"
            )));
        }
        for (f, tri) in self.indices.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(GeometryError::InvalidMesh(format!(
                    "triangle {f} uses vertex {bad} but there are only {n}"
                )));
            }
        }
        if self.indices.len() > u32::MAX as usize {
            return Err(GeometryError::InvalidMesh("more than 2³² triangles".into()));
        }
        Ok(())
    }

    /// The three vertex positions of triangle `i`.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3A; 3] {
        let [a, b, c] = self.indices[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }
}
