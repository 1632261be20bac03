//! Linear interpolation in a sampled table, shared by normalized SPDs and plain curves.

/// Value of the polyline through `(x_i, f_i)` at `lambda`, 0 outside `[x₀, x_{n−1}]`.
/// `x` must be strictly increasing and `x.len() == f.len() ≥ 1`. O(log n).
pub fn interpolate(x: &[f64], f: &[f64], lambda: f64) -> f64 {
    let n = x.len();
    if n == 0 || !(lambda >= x[0] && lambda <= x[n - 1]) {
        return 0.0;
    }
    if n == 1 {
        return f[0];
    }
    let i = (x.partition_point(|&xi| xi <= lambda).max(1) - 1).min(n - 2);
    let s = (lambda - x[i]) / (x[i + 1] - x[i]);
    (1.0 - s) * f[i] + s * f[i + 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    // Interpolation at nodes, midpoints and outside; exact/1e-15 because only one lerp rounds.
    #[test]
    fn interpolates_and_is_zero_outside() {
        let x = [400.0, 410.0, 430.0];
        let f = [1.0, 3.0, 1.0];
        assert_eq!(interpolate(&x, &f, 400.0), 1.0);
        assert_eq!(interpolate(&x, &f, 430.0), 1.0);
        assert!((interpolate(&x, &f, 405.0) - 2.0).abs() < 1e-15);
        assert!((interpolate(&x, &f, 420.0) - 2.0).abs() < 1e-15);
        assert_eq!(interpolate(&x, &f, 399.999), 0.0);
        assert_eq!(interpolate(&x, &f, 430.001), 0.0);
        assert_eq!(interpolate(&x, &f, f64::NAN), 0.0);
    }
}
