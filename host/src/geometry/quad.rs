//! Parallelograms ("quads"): a corner plus two edge vectors.
//!
//! A quad is intersected as the two triangles `(v0, v1, v2)` and `(v0, v2, v3)` with the
//! watertight triangle test, so it is exactly as robust as a mesh and two quads sharing an edge
//! (e.g. Cornell box walls) cannot leak. It is sampled by area the same way, which keeps sampled
//! points on the very surface that rays hit.

use glam::{Vec2, Vec3A};

/// A parallelogram `corner + s·edge0 + t·edge1`, `s, t ∈ [0, 1]`, front face along
/// `edge0 × edge1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// The four vertices `corner`, `corner+edge0`, `corner+edge0+edge1`, `corner+edge1`, each
    /// rounded once to f32.
    pub vertices: [Vec3A; 4],
    /// Unit normal `normalize(edge0 × edge1)`.
    pub normal: Vec3A,
}

impl Quad {
    /// Builds the quad; `None` if the edges are parallel, zero or not finite.
    pub fn new(corner: Vec3A, edge0: Vec3A, edge1: Vec3A) -> Option<Quad> {
        let c = corner.as_dvec3();
        let (e0, e1) = (edge0.as_dvec3(), edge1.as_dvec3());
        let n = e0.cross(e1);
        if !n.is_finite() || !c.is_finite() || n.length() <= 0.0 {
            return None;
        }
        let v = [c, c + e0, c + e0 + e1, c + e1].map(|p| Vec3A::from(p.as_vec3()));
        Some(Quad {
            vertices: v,
            normal: Vec3A::from(n.normalize().as_vec3()),
        })
    }

    /// The vertices of half `half` (0 or 1) as a triangle.
    #[inline]
    pub fn triangle(&self, half: usize) -> [Vec3A; 3] {
        let v = &self.vertices;
        if half == 0 {
            [v[0], v[1], v[2]]
        } else {
            [v[0], v[2], v[3]]
        }
    }

    /// Quad parameters `(s, t)` of the point with barycentrics `(b1, b2)` in half `half`.
    #[inline]
    pub fn uv(half: usize, b1: f32, b2: f32) -> Vec2 {
        if half == 0 {
            Vec2::new(b1 + b2, b2)
        } else {
            Vec2::new(b1, b1 + b2)
        }
    }

    /// Area (scene units²) as the sum of the two triangles actually intersected.
    pub fn area(&self) -> f32 {
        let [a, b, c] = self.triangle(0);
        let [d, e, f] = self.triangle(1);
        super::triangle::triangle_area(a, b, c) + super::triangle::triangle_area(d, e, f)
    }
}
