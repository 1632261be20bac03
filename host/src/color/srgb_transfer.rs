//! The sRGB transfer function (IEC 61966-2-1) and 8-bit quantization for display output.

/// Linear → encoded sRGB, for `v` in [0,1] (values outside are clamped first).
pub fn srgb_encode(v: f64) -> f64 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Encoded sRGB → linear, for `e` in [0,1] (clamped first).
pub fn srgb_decode(e: f64) -> f64 {
    let e = if e.is_nan() { 0.0 } else { e.clamp(0.0, 1.0) };
    if e <= 0.040_45 {
        e / 12.92
    } else {
        ((e + 0.055) / 1.055).powf(2.4)
    }
}

/// Quantize an encoded value in [0,1] to 8 bits by rounding to nearest.
pub fn quantize_8bit(e: f64) -> u8 {
    let e = if e.is_nan() { 0.0 } else { e.clamp(0.0, 1.0) };
    (e * 255.0).round() as u8
}

/// Linear RGB → 8-bit sRGB triple.
pub fn linear_to_srgb8(rgb: [f64; 3]) -> [u8; 3] {
    rgb.map(|v| quantize_8bit(srgb_encode(v)))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Known points: linear 0.5 → 0.7354 (188/255), 0.18 → 0.4614 (118); round trip to 1e-12;
    // continuity at the breakpoint to 1e-7 (the standard's constants are rounded).
    #[test]
    fn transfer_known_values() {
        assert!((srgb_encode(0.5) - 0.735_356_983).abs() < 1e-8);
        assert_eq!(linear_to_srgb8([0.5, 0.18, 1.0]), [188, 118, 255]);
        for k in 0..=100 {
            let v = k as f64 / 100.0;
            assert!((srgb_decode(srgb_encode(v)) - v).abs() < 1e-12);
        }
        assert!(
            (12.92 * 0.003_130_8 - (1.055 * 0.003_130_8f64.powf(1.0 / 2.4) - 0.055)).abs() < 1e-7
        );
        assert_eq!(quantize_8bit(f64::NAN), 0);
        assert_eq!(quantize_8bit(2.0), 255);
    }
}
