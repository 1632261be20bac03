//! Indexed triangle meshes (object or world space) and their validation.

use glam::{Vec2, Vec3A};
use rayon::prelude::*;

use super::triangle::{barycentrics_of, triangle_derivatives};
use super::{GeometryError, SurfaceDerivatives};

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

impl TriangleMesh {
    /// ∂p/∂(b1, b2) and ∂n/∂(b1, b2) at point `p` of triangle `i`, in its barycentrics. With
    /// vertex normals the shading normal is `n = ñ/|ñ|`, `ñ = Σ bᵢ nᵢ`, so
    /// `∂n/∂b_k = (I − n nᵀ)(n_k − n₀)/|ñ|`; without them, or where `ñ` vanishes, the triangle
    /// is flat. `None` for a degenerate triangle.
    pub fn derivatives(&self, i: usize, p: Vec3A) -> Option<SurfaceDerivatives> {
        let [p0, p1, p2] = self.triangle(i);
        let mut d = triangle_derivatives(p0, p1, p2);
        let (b0, b1, b2) = barycentrics_of(p, p0, p1, p2)?;
        if let Some(ns) = &self.normals {
            let [a, b, c] = self.indices[i].map(|k| ns[k as usize]);
            let m = a * b0 + b * b1 + c * b2;
            let len = m.length();
            if len > 0.0 {
                let n = m / len;
                let project = |v: Vec3A| (v - n * n.dot(v)) / len;
                d.dndu = project(b - a);
                d.dndv = project(c - a);
            }
        }
        Some(d)
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

#[cfg(test)]
mod tests {
    use super::*;

    // ∂p/∂(b1, b2) and ∂n/∂(b1, b2) of a triangle with (non-unit, differing) vertex normals
    // against central differences of the chart `p(b1, b2)`, `n = normalize(Σ bᵢ nᵢ)`, step 1e-3
    // in f32 work: truncation O(h²) ≈ 1e-6, rounding ≈ 1e-7/h = 1e-4 of the normal; bound 5e-4.
    // The flat mesh (no normals) must give zero ∂n and the same ∂p.
    #[test]
    fn derivatives_match_finite_differences() {
        let positions = vec![
            Vec3A::new(0.0, 0.0, 0.0),
            Vec3A::new(1.0, 0.2, 0.0),
            Vec3A::new(0.1, 0.9, 0.3),
        ];
        let normals = vec![
            Vec3A::new(0.0, 0.0, 1.0),
            Vec3A::new(0.3, 0.0, 1.2),
            Vec3A::new(-0.2, 0.4, 0.8),
        ];
        let mut mesh = TriangleMesh {
            positions: positions.clone(),
            normals: Some(normals.clone()),
            uvs: None,
            indices: vec![[0, 1, 2]],
        };
        let point = |b1: f32, b2: f32| {
            positions[0] * (1.0 - b1 - b2) + positions[1] * b1 + positions[2] * b2
        };
        let normal = |b1: f32, b2: f32| {
            (normals[0] * (1.0 - b1 - b2) + normals[1] * b1 + normals[2] * b2).normalize()
        };
        let h = 1e-3;
        for &(b1, b2) in &[(0.2f32, 0.3f32), (0.6, 0.1), (0.1, 0.7)] {
            let d = mesh.derivatives(0, point(b1, b2)).unwrap();
            let fd = |f: &dyn Fn(f32, f32) -> Vec3A, k: usize| {
                let (e1, e2) = if k == 0 { (h, 0.0) } else { (0.0, h) };
                (f(b1 + e1, b2 + e2) - f(b1 - e1, b2 - e2)) / (2.0 * h)
            };
            assert!((d.dpdu - fd(&point, 0)).length() < 5e-4);
            assert!((d.dpdv - fd(&point, 1)).length() < 5e-4);
            assert!((d.dndu - fd(&normal, 0)).length() < 5e-4, "{:?}", d.dndu);
            assert!((d.dndv - fd(&normal, 1)).length() < 5e-4, "{:?}", d.dndv);
        }
        mesh.normals = None;
        let d = mesh.derivatives(0, point(0.2, 0.3)).unwrap();
        assert_eq!((d.dndu, d.dndv), (Vec3A::ZERO, Vec3A::ZERO));
        assert!((d.dpdu - (positions[1] - positions[0])).length() < 1e-6);
    }
}
