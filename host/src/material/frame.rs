//! An orthonormal shading frame: materials work in local coordinates where the shading normal is
//! +z, so cosines are plain `z` components and the BSDF code never sees world space.

use glam::Vec3A;

/// Right-handed orthonormal basis `(s, t, n)`; `n` is the shading normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub s: Vec3A,
    /// Second tangent, `n × s`.
    pub t: Vec3A,
    /// Normal (local +z).
    pub n: Vec3A,
}

impl Frame {
    /// A frame around unit normal `n`, tangents chosen without branches on the normal's sign
    /// (Duff et al. 2017, "Building an orthonormal basis, revisited"), so it is continuous except
    /// on the `n.z = -1` pole.
    pub fn from_normal(n: Vec3A) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3A::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// World direction → local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3A) -> Vec3A {
        Vec3A::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local direction → world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3A) -> Vec3A {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Round trip world→local→world must reproduce the vector to f32 rounding (1e-5 relative),
    /// and the basis must be orthonormal to the same precision, for normals on every octant.
    #[test]
    fn frame_is_orthonormal_and_round_trips() {
        for &(x, y, z) in &[
            (0.0, 0.0, 1.0),
            (0.0, 0.0, -1.0),
            (0.3, -0.5, 0.2),
            (-0.7, 0.1, -0.6),
            (1.0, 0.0, 0.0),
        ] {
            let n = Vec3A::new(x, y, z).normalize();
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(
                f.s.dot(f.t).abs() < 1e-5 && f.s.dot(n).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5
            );
            assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed");
            let v = Vec3A::new(0.2, 0.9, -0.4);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
        }
    }
}
