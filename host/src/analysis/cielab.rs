//! CIE 1976 L*a*b* from CIE XYZ relative to a reference white (here D65 with Y = 1, the white of
//! linear sRGB), the space CIEDE2000 is defined in.

use crate::color::SRGB;

/// CIELAB coordinates (L* in 0..100 for Y in 0..Yn; a*, b* unbounded).
pub type Lab = [f64; 3];

/// The CIE function f(t): cube root above (6/29)³, linear below (CIE 15:2004, §8.2.1).
#[inline]
fn lab_f(t: f64) -> f64 {
    const D: f64 = 6.0 / 29.0;
    if t > D * D * D {
        t.cbrt()
    } else {
        t / (3.0 * D * D) + 4.0 / 29.0
    }
}

/// L*a*b* of `xyz` relative to `white` (both absolute; `white` is usually Y = 1).
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> Lab {
    let fx = lab_f(xyz[0] / white[0]);
    let fy = lab_f(xyz[1] / white[1]);
    let fz = lab_f(xyz[2] / white[2]);
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// L*a*b* of a linear sRGB colour (through XYZ, D65 white with Y = 1: sRGB (1,1,1) is L* = 100).
pub fn linear_srgb_to_lab(rgb: [f64; 3]) -> Lab {
    xyz_to_lab(SRGB.rgb_to_xyz(rgb), SRGB.white_xyz())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// sRGB white maps to L* = 100, a* = b* = 0 (to 1e-9: only rounding of the matrix product);
    /// sRGB red (1,0,0) to the published Lab (53.24, 80.09, 67.20) of the sRGB primary (values
    /// given to 2 decimals, so 0.01 tolerance plus the 4-digit primaries' effect: 0.05).
    #[test]
    fn white_and_red() {
        let w = linear_srgb_to_lab([1.0; 3]);
        assert!(
            (w[0] - 100.0).abs() < 1e-9 && w[1].abs() < 1e-9 && w[2].abs() < 1e-9,
            "{w:?}"
        );
        let r = linear_srgb_to_lab([1.0, 0.0, 0.0]);
        for (got, want) in r.iter().zip([53.24, 80.09, 67.20]) {
            assert!((got - want).abs() < 0.05, "{r:?}");
        }
    }
}
