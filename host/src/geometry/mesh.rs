//! Indexed triangle meshes (object or world space) and their validation.

use glam::{Vec2, Vec3A};
use rayon::prelude::*;

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
            if let Some(i) = first_where(ns, |v| !v.is_finite()) {
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
            if let Some(i) = first_where(uvs, |v| !v.is_finite()) {
                return Err(GeometryError::InvalidMesh(format!("uv {i} is not finite")));
            }
        }
        // In parallel (a serial pass over a large mesh held up the parallel build); the
        // first offender is reported, as a serial scan would.
        if let Some(i) = first_where(&self.positions, |v| !v.is_finite()) {
            return Err(GeometryError::InvalidMesh(format!(
                "position {i} is not finite"
            )));
        }
        let bad_triangle = first_where(&self.indices, |tri| tri.iter().any(|&i| i as usize >= n));
        if let Some(f) = bad_triangle {
            let bad = self.indices[f].iter().find(|&&i| i as usize >= n);
            return Err(GeometryError::InvalidMesh(format!(
                "triangle {f} uses vertex {} but there are only {n}",
                bad.copied().unwrap_or_default()
            )));
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

/// Index of the first element of `v` for which `bad` holds: chunks of 16,384 scanned in
/// parallel, each serially (rayon's `position_first` tests every element through its
/// consumer and took three times the instructions of a serial scan).
fn first_where<T: Sync>(v: &[T], bad: impl Fn(&T) -> bool + Sync) -> Option<usize> {
    const CHUNK: usize = 16 * 1024;
    v.par_chunks(CHUNK)
        .enumerate()
        .filter_map(|(k, c)| c.iter().position(&bad).map(|i| k * CHUNK + i))
        .min()
}
