//! Affine 4×4 transforms, stored row-major in f64 together with their inverse.
//!
//! Convention: points are column vectors, `p' = M · p`, and `m[row][col]` is row-major, so the
//! translation sits in the last column (`m[0][3]`, `m[1][3]`, `m[2][3]`). Compositions are
//! written in the order they are applied: `Transform::scale(s).then(&Transform::rotate(a, d))
//! .then(&Transform::translate(t))` scales first, then rotates, then translates (`M = T·R·S`).
//!
//! Matrices are kept in f64 so that composing many transforms and inverting them stays exact to
//! far below f32 resolution; the results are rounded to f32 once, and [`Transform::point_with_error`]
//! reports a conservative bound on that rounding.

use glam::{DMat4, DVec3, DVec4, Vec3A};

use super::GeometryError;

/// An affine transform `M` with its inverse (both row-major, f64).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    m: [[f64; 4]; 4],
    inv: [[f64; 4]; 4],
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

const IDENTITY_ROWS: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// f64 unit roundoff, for the (tiny) error of the f64 matrix–vector product itself.
const F64_EPS: f64 = f64::EPSILON * 0.5;

fn rows_to_dmat(r: &[[f64; 4]; 4]) -> DMat4 {
    // glam stores columns; transpose the row-major input.
    DMat4::from_cols_array_2d(r).transpose()
}

fn dmat_to_rows(m: &DMat4) -> [[f64; 4]; 4] {
    m.transpose().to_cols_array_2d()
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Transform = Transform {
        m: IDENTITY_ROWS,
        inv: IDENTITY_ROWS,
    };

    /// From a row-major matrix. Errors if it is not finite, not affine (last row must be
    /// `[0, 0, 0, 1]`: projective transforms would break shape and error-bound invariants) or
    /// singular (determinant of the 3×3 part below 1e-300 in magnitude relative to its scale).
    pub fn from_rows(rows: [[f64; 4]; 4]) -> Result<Self, GeometryError> {
        if rows.iter().flatten().any(|v| !v.is_finite()) {
            return Err(GeometryError::InvalidTransform(
                "matrix has a NaN or infinite entry".into(),
            ));
        }
        if rows[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(GeometryError::InvalidTransform(format!(
                "last row must be [0, 0, 0, 1] (affine), got {:?}",
                rows[3]
            )));
        }
        let m = rows_to_dmat(&rows);
        let det = m.determinant();
        let scale = rows[..3]
            .iter()
            .flat_map(|r| r[..3].iter())
            .fold(0.0f64, |a, v| a.max(v.abs()));
        if !(det.abs() > 1e-12 * scale * scale * scale) || !det.is_finite() {
            return Err(GeometryError::InvalidTransform(format!(
                "matrix is singular (determinant {det:e})"
            )));
        }
        let inv = dmat_to_rows(&m.inverse());
        Ok(Self { m: rows, inv })
    }

    /// Translation by `t` (scene units).
    pub fn translate(t: DVec3) -> Self {
        let mut m = IDENTITY_ROWS;
        let mut inv = IDENTITY_ROWS;
        for i in 0..3 {
            m[i][3] = t[i];
            inv[i][3] = -t[i];
        }
        Self { m, inv }
    }

    /// Scale by `s` per axis. Errors if any factor is zero or not finite.
    pub fn scale(s: DVec3) -> Result<Self, GeometryError> {
        if !s.is_finite() || s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
            return Err(GeometryError::InvalidTransform(format!(
                "scale factors must be finite and non-zero, got {s}"
            )));
        }
        let mut m = IDENTITY_ROWS;
        let mut inv = IDENTITY_ROWS;
        for i in 0..3 {
            m[i][i] = s[i];
            inv[i][i] = 1.0 / s[i];
        }
        Ok(Self { m, inv })
    }

    /// Right-handed rotation by `degrees` about `axis` (need not be unit; errors if zero).
    pub fn rotate(axis: DVec3, degrees: f64) -> Result<Self, GeometryError> {
        let len = axis.length();
        if !(len > 0.0) || !len.is_finite() || !degrees.is_finite() {
            return Err(GeometryError::InvalidTransform(format!(
                "rotation needs a finite non-zero axis and angle, got axis {axis} angle {degrees}"
            )));
        }
        let r = DMat4::from_axis_angle(axis / len, degrees.to_radians());
        let m = dmat_to_rows(&r);
        // A rotation's inverse is its transpose (exact, no inversion round-off).
        let inv = dmat_to_rows(&r.transpose());
        Ok(Self { m, inv })
    }

    /// `self` followed by `next`: the matrix `next · self`.
    pub fn then(&self, next: &Transform) -> Transform {
        let m = rows_to_dmat(&next.m) * rows_to_dmat(&self.m);
        let inv = rows_to_dmat(&self.inv) * rows_to_dmat(&next.inv);
        Transform {
            m: dmat_to_rows(&m),
            inv: dmat_to_rows(&inv),
        }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Transform {
        Transform {
            m: self.inv,
            inv: self.m,
        }
    }

    /// The row-major matrix.
    pub fn matrix(&self) -> &[[f64; 4]; 4] {
        &self.m
    }

    /// The row-major inverse matrix.
    pub fn inverse_matrix(&self) -> &[[f64; 4]; 4] {
        &self.inv
    }

    /// Whether this is exactly the identity.
    pub fn is_identity(&self) -> bool {
        self.m == IDENTITY_ROWS
    }

    /// Transforms a point in f64 (no rounding to f32).
    pub fn point_f64(&self, p: DVec3) -> DVec3 {
        let v = rows_to_dmat(&self.m) * DVec4::new(p.x, p.y, p.z, 1.0);
        v.truncate()
    }

    /// Transforms a direction in f64 (ignores translation).
    pub fn vector_f64(&self, v: DVec3) -> DVec3 {
        let r = &self.m;
        DVec3::new(
            r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z,
            r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
            r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z,
        )
    }

    /// Transforms a point, rounding once to f32.
    pub fn point(&self, p: Vec3A) -> Vec3A {
        self.point_f64(p.as_dvec3()).as_vec3().into()
    }

    /// Transforms a point that is known to within `p_error` (per-axis absolute bound) and
    /// returns the f32 result with a conservative bound on its absolute error: the input error
    /// carried through `|M₃ₓ₃|`, plus the f64 product's round-off, plus one f32 rounding.
    pub fn point_with_error(&self, p: Vec3A, p_error: Vec3A) -> (Vec3A, Vec3A) {
        let pd = p.as_dvec3();
        let exact = self.point_f64(pd);
        let rounded: Vec3A = exact.as_vec3().into();
        let r = &self.m;
        let mut err = [0.0f64; 3];
        for (i, e) in err.iter_mut().enumerate() {
            let abs_lin = r[i][0].abs() * (pd.x.abs() + p_error.x as f64)
                + r[i][1].abs() * (pd.y.abs() + p_error.y as f64)
                + r[i][2].abs() * (pd.z.abs() + p_error.z as f64)
                + r[i][3].abs();
            let carried = r[i][0].abs() * p_error.x as f64
                + r[i][1].abs() * p_error.y as f64
                + r[i][2].abs() * p_error.z as f64;
            // 4 f64 roundings in the dot product, then one rounding to f32 (≤ ½ ULP, bounded
            // by ε₃₂·|x| with a factor 2 of slack for subnormal-free safety).
            *e = carried * (1.0 + 8.0 * F64_EPS)
                + 4.0 * F64_EPS * abs_lin
                + 2.0 * super::float_error::MACHINE_EPSILON as f64 * exact[i].abs();
        }
        let err = DVec3::from_array(err).as_vec3();
        // Round the bound itself upwards so it never underestimates after conversion.
        let err = Vec3A::new(
            super::float_error::next_float_up(err.x),
            super::float_error::next_float_up(err.y),
            super::float_error::next_float_up(err.z),
        );
        (rounded, err)
    }

    /// Transforms a direction (no translation), rounding once to f32.
    pub fn vector(&self, v: Vec3A) -> Vec3A {
        self.vector_f64(v.as_dvec3()).as_vec3().into()
    }

    /// Transforms a surface normal by the inverse transpose (so it stays perpendicular to
    /// transformed tangents) and renormalises it. Returns zero if `n` is zero.
    pub fn normal(&self, n: Vec3A) -> Vec3A {
        let i = &self.inv;
        let n = n.as_dvec3();
        let out = DVec3::new(
            i[0][0] * n.x + i[1][0] * n.y + i[2][0] * n.z,
            i[0][1] * n.x + i[1][1] * n.y + i[2][1] * n.z,
            i[0][2] * n.x + i[1][2] * n.y + i[2][2] * n.z,
        );
        out.normalize_or_zero().as_vec3().into()
    }

    /// If the linear part is a similarity (rotation × uniform scale, no shear), its scale factor;
    /// used to keep analytic spheres spherical. Tolerance 1e-9 relative.
    pub fn uniform_scale(&self) -> Option<f64> {
        let c0 = self.vector_f64(DVec3::X);
        let c1 = self.vector_f64(DVec3::Y);
        let c2 = self.vector_f64(DVec3::Z);
        let s = c0.length();
        let tol = 1e-9 * s;
        if (c1.length() - s).abs() > tol
            || (c2.length() - s).abs() > tol
            || c0.dot(c1).abs() > tol * s
            || c0.dot(c2).abs() > tol * s
            || c1.dot(c2).abs() > tol * s
        {
            return None;
        }
        Some(s)
    }

    /// Whether the transform flips orientation (negative determinant): triangle windings then
    /// reverse, so mesh normals computed from the winding would point inwards.
    pub fn flips_handedness(&self) -> bool {
        rows_to_dmat(&self.m).determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Row-major layout: the translation must land in the last column and move points by
    // exactly t (integers are exact in f64 and f32, so equality is exact).
    #[test]
    fn translation_is_last_column() {
        let t = Transform::translate(DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(t.matrix()[0][3], 1.0);
        assert_eq!(t.point(Vec3A::ZERO), Vec3A::new(1.0, 2.0, 3.0));
        assert_eq!(t.vector(Vec3A::X), Vec3A::X);
    }

    // Rotating +x by 90° about +y gives −z in a right-handed frame; tolerance 1e-6 covers
    // cos(90°) not being exactly zero in floating point.
    #[test]
    fn rotation_is_right_handed() {
        let r = Transform::rotate(DVec3::Y, 90.0).unwrap();
        let v = r.vector(Vec3A::X);
        assert!((v - Vec3A::new(0.0, 0.0, -1.0)).length() < 1e-6, "{v}");
    }

    // Composition order: scale then translate must scale the point first.
    #[test]
    fn then_applies_in_order() {
        let t = Transform::scale(DVec3::splat(2.0))
            .unwrap()
            .then(&Transform::translate(DVec3::new(1.0, 0.0, 0.0)));
        assert_eq!(
            t.point(Vec3A::new(1.0, 1.0, 1.0)),
            Vec3A::new(3.0, 2.0, 2.0)
        );
        let back = t.inverse().point(Vec3A::new(3.0, 2.0, 2.0));
        assert!((back - Vec3A::ONE).length() < 1e-6);
    }

    // Normals must stay perpendicular to transformed tangents under non-uniform scale
    // (dot product within 1e-6 of 0: f32 rounding of unit vectors).
    #[test]
    fn normals_use_inverse_transpose() {
        let t = Transform::scale(DVec3::new(1.0, 4.0, 1.0)).unwrap();
        let n = Vec3A::new(1.0, 1.0, 0.0).normalize();
        let tangent = Vec3A::new(1.0, -1.0, 0.0);
        let dot = t.normal(n).dot(t.vector(tangent).normalize());
        assert!(dot.abs() < 1e-6, "{dot}");
    }

    // The error bound must contain the true (f64) image of a point far from the origin.
    #[test]
    fn point_error_bound_contains_exact() {
        let t = Transform::rotate(DVec3::new(1.0, 2.0, 3.0), 37.0)
            .unwrap()
            .then(&Transform::translate(DVec3::new(1.0e4, -3.0e4, 7.0)));
        let p = Vec3A::new(123.456, -0.001, 9876.5);
        let (q, e) = t.point_with_error(p, Vec3A::ZERO);
        let exact = t.point_f64(p.as_dvec3());
        let d = (q.as_dvec3() - exact).abs();
        assert!(d.x <= e.x as f64 && d.y <= e.y as f64 && d.z <= e.z as f64);
    }

    // Singular and projective matrices are rejected with an error, not a panic.
    #[test]
    fn rejects_bad_matrices() {
        let mut rows = IDENTITY_ROWS;
        rows[1][1] = 0.0;
        assert!(Transform::from_rows(rows).is_err());
        let mut rows = IDENTITY_ROWS;
        rows[3][0] = 1.0;
        assert!(Transform::from_rows(rows).is_err());
        assert!(Transform::rotate(DVec3::ZERO, 10.0).is_err());
        assert!(Transform::scale(DVec3::new(1.0, 0.0, 1.0)).is_err());
    }
}
