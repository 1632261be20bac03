//! Floating-point error bounds for f32 geometry.
//!
//! Every rounded f32 operation `x ⊕ y` returns `(x + y)(1 ± ε)` with `ε = 2⁻²⁴` (half an ULP
//! at 1). A chain of `n` such operations is bounded by `γₙ = nε / (1 − nε)` (Higham, *Accuracy
//! and Stability of Numerical Algorithms*, §3.1); the intersection routines use these bounds to
//! report how far a computed hit point may lie from the true surface.

/// Unit roundoff of f32: half the distance from 1.0 to the next float (2⁻²⁴).
pub const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// `γₙ = nε / (1 − nε)`: relative error bound of `n` chained f32 roundings.
#[inline]
pub fn gamma(n: i32) -> f32 {
    let ne = n as f32 * MACHINE_EPSILON;
    ne / (1.0 - ne)
}

/// The smallest f32 strictly greater than `v` (`+∞` stays `+∞`; `-0.0` steps like `+0.0`).
#[inline]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The largest f32 strictly smaller than `v` (`−∞` stays `−∞`; `+0.0` steps like `-0.0`).
#[inline]
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v > 0.0 { bits - 1 } else { bits + 1 };
    f32::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Stepping must move by exactly one representable value (no tolerance: it is bit-exact).
    #[test]
    fn next_float_steps_one_ulp() {
        assert_eq!(next_float_up(1.0), 1.0 + f32::EPSILON);
        assert_eq!(next_float_down(1.0), 1.0 - f32::EPSILON / 2.0);
        assert!(next_float_up(0.0) > 0.0);
        assert!(next_float_down(0.0) < 0.0);
        assert!(next_float_up(-0.0) > 0.0);
        assert_eq!(next_float_up(-1.0), -1.0 + f32::EPSILON / 2.0);
        assert_eq!(next_float_up(f32::INFINITY), f32::INFINITY);
    }

    // γ₃ must exceed 3ε (it is 3ε/(1−3ε)); checked exactly against the formula in f64.
    #[test]
    fn gamma_matches_definition() {
        let g = gamma(3) as f64;
        let e = MACHINE_EPSILON as f64;
        assert!((g - 3.0 * e / (1.0 - 3.0 * e)).abs() < 1e-12);
        assert!(g > 3.0 * e);
    }
}
