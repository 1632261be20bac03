//! Parallelograms ("quads"): a corner plus two edge vectors.
//!
//! A quad is intersected as the two triangles `(v0, v1, v2)` and `(v0, v2, v3)` with the
//! watertight triangle test, so it is exactly as robust as a mesh and two quads sharing an edge
//! (e.g. Cornell box walls) cannot leak. It is sampled by area through its chart
//! `(s, t) ↦ corner + s·edge0 + t·edge1` ([`Quad::point`], whose error bound covers the
//! distance to the triangles rays hit), which [`Quad::coords`] inverts.

use glam::{Vec2, Vec3A};

use super::SurfaceDerivatives;

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

    /// ∂p/∂(s, t) (the two edges, as [`Self::uv`] parameterises the quad) and a normal that
    /// does not turn (a flat surface).
    pub fn derivatives(&self) -> SurfaceDerivatives {
        let v = &self.vertices;
        SurfaceDerivatives::flat(v[1] - v[0], v[3] - v[0])
    }

    /// The point `corner + s·edge0 + t·edge1` (the edges as the rounded vertices give them)
    /// and its error bound, which also covers the distance to the half-triangle rays hit (the
    /// far vertex is rounded on its own, so the two halves may differ by its rounding). An
    /// axis-aligned quad's points lie exactly in its plane.
    #[inline]
    pub fn point(&self, s: f32, t: f32) -> (Vec3A, Vec3A) {
        let v = &self.vertices;
        let (a, b) = ((v[1] - v[0]) * s, (v[3] - v[0]) * t);
        let p = v[0] + a + b;
        let err = (v[0].abs() + a.abs() + b.abs() + v[2].abs()) * super::float_error::gamma(7);
        (p, err)
    }

    /// The chart parameters `(s, t)`, clamped to [0, 1]², of the point of the quad's plane
    /// nearest `p` (`corner + s·edge0 + t·edge1`), by the dual basis of the two edges.
    pub fn coords(&self, p: Vec3A) -> Vec2 {
        let v = &self.vertices;
        let (e0, e1) = (v[1] - v[0], v[3] - v[0]);
        let n = e0.cross(e1);
        let (d0, d1) = (e1.cross(n), n.cross(e0));
        let r = p - v[0];
        let s = r.dot(d0) / e0.dot(d0);
        let t = r.dot(d1) / e1.dot(d1);
        Vec2::new(s.clamp(0.0, 1.0), t.clamp(0.0, 1.0))
    }

    /// Area (scene units²) as the sum of the two triangles actually intersected.
    pub fn area(&self) -> f32 {
        let [a, b, c] = self.triangle(0);
        let [d, e, f] = self.triangle(1);
        super::triangle::triangle_area(a, b, c) + super::triangle::triangle_area(d, e, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The quad's (s, t) chart `corner + s·edge0 + t·edge1` is linear, so the derivatives are
    // the edges exactly (up to one f32 rounding of the vertices: 1e-6 relative) and the point
    // of the half-triangle uv (0.3, 0.6) is reproduced by the chart to 1e-6.
    #[test]
    fn derivatives_are_the_edges() {
        let (c, e0, e1) = (
            Vec3A::new(-1.0, 0.5, 2.0),
            Vec3A::new(2.0, 0.0, 0.5),
            Vec3A::new(0.0, 1.5, -0.25),
        );
        let q = Quad::new(c, e0, e1).unwrap();
        let d = q.derivatives();
        assert!((d.dpdu - e0).length() < 1e-6 && (d.dpdv - e1).length() < 1e-6);
        assert_eq!((d.dndu, d.dndv), (Vec3A::ZERO, Vec3A::ZERO));
        // Half 1 holds (s, t) with t > s: barycentrics (b1, b2) give uv (b1, b1 + b2).
        let (b1, b2) = (0.3, 0.3);
        let [p0, p1, p2] = q.triangle(1);
        let p = p0 * (1.0 - b1 - b2) + p1 * b1 + p2 * b2;
        let uv = Quad::uv(1, b1, b2);
        let chart = c + d.dpdu * uv.x + d.dpdv * uv.y;
        assert!((p - chart).length() < 1e-6, "{p:?} vs {chart:?}");
    }
}
