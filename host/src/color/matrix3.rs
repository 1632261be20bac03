//! Minimal 3×3 matrix helpers for colour-space conversions (row-major, `m[row][col]`).

/// A row-major 3×3 matrix.
pub type Mat3 = [[f64; 3]; 3];

/// `m · v`.
pub fn mul_vec(m: &Mat3, v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// `a · b`.
pub fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}

/// Inverse by the adjugate; `None` when the determinant is 0 or not finite.
pub fn inverse(m: &Mat3) -> Option<Mat3> {
    let cof =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let c = [
        [cof(1, 2, 1, 2), -cof(1, 2, 0, 2), cof(1, 2, 0, 1)],
        [-cof(0, 2, 1, 2), cof(0, 2, 0, 2), -cof(0, 2, 0, 1)],
        [cof(0, 1, 1, 2), -cof(0, 1, 0, 2), cof(0, 1, 0, 1)],
    ];
    let det = m[0][0] * c[0][0] + m[0][1] * c[0][1] + m[0][2] * c[0][2];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // inverse = adjugate / det, adjugate = transpose of the cofactor matrix.
    Some(std::array::from_fn(|r| {
        std::array::from_fn(|col| c[col][r] / det)
    }))
}

/// Diagonal matrix.
pub fn diag(d: [f64; 3]) -> Mat3 {
    [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]
}

#[cfg(test)]
mod tests {
    use super::*;

    // m · m⁻¹ = I to 1e-14 (a well-conditioned matrix; only a few roundings per entry).
    #[test]
    fn inverse_round_trips() {
        let m = [[2.0, 1.0, 0.5], [0.3, 4.0, -1.0], [0.0, 0.2, 1.5]];
        let p = mul(&m, &inverse(&m).unwrap());
        for (r, row) in p.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                assert!((v - if r == c { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        assert!(inverse(&[[1.0; 3]; 3]).is_none());
    }
}
