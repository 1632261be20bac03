//! Planck's law for a blackbody emitter at temperature T (K).

/// Speed of light in vacuum, m/s (exact, SI 2019).
const C: f64 = 299_792_458.0;
/// Planck constant, J·s (exact, SI 2019).
const H: f64 = 6.626_070_15e-34;
/// Boltzmann constant, J/K (exact, SI 2019).
const K_B: f64 = 1.380_649e-23;

/// Spectral radiance of a blackbody, in W/(m²·sr·nm), at `lambda_nm` and `kelvin`.
/// Returns 0 for non-positive or non-finite inputs.
pub fn planck(lambda_nm: f64, kelvin: f64) -> f64 {
    if !(lambda_nm > 0.0 && kelvin > 0.0 && lambda_nm.is_finite() && kelvin.is_finite()) {
        return 0.0;
    }
    let l = lambda_nm * 1e-9;
    let per_metre = 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * K_B * kelvin)).exp_m1()));
    per_metre * 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

    // Wien's displacement law: the peak is at b/T with b = 2.897771955e-3 m·K (CODATA). We scan at
    // 0.01 nm so the tolerance 0.02 nm covers the grid, not the physics.
    #[test]
    fn peak_follows_wien() {
        let t = 5000.0;
        let mut best = (0.0, 0.0);
        let mut l = 400.0;
        while l < 800.0 {
            let v = planck(l, t);
            if v > best.1 {
                best = (l, v);
            }
            l += 0.01;
        }
        let wien = 2.897_771_955e-3 / t * 1e9;
        assert!((best.0 - wien).abs() < 0.02, "{} vs {}", best.0, wien);
    }

    // Absolute value against an independent evaluation of Planck at 500 nm, 6000 K (Python,
    // SI-2019 constants): 3.17569e4 W/(m²·sr·nm); 1e-5 relative because the reference is
    // quoted to 6 digits.
    #[test]
    fn absolute_value() {
        let v = planck(500.0, 6000.0);
        assert!((v / 3.17569e4 - 1.0).abs() < 1e-5, "{v}");
    }
}
