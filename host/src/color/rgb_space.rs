//! RGB colour spaces defined by primaries and a white point (CIE 1931 xy); the XYZ↔RGB matrices
//! are *computed* from those, and Bradford adaptation is applied when the XYZ data's white
//! differs from the space's white.

use super::matrix3::{diag, inverse, mul, mul_vec, Mat3};
use super::xyz::xyz_from_xy;

/// An additive RGB space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbColorSpace {
    /// Identifier, e.g. `srgb`.
    pub name: &'static str,
    /// xy chromaticities of the red, green and blue primaries.
    pub primaries: [[f64; 2]; 3],
    /// xy chromaticity of the white point (RGB = 1,1,1).
    pub white: [f64; 2],
}

/// D65 as the RGB standards round it (IEC 61966-2-1, ITU-R BT.709/2020, SMPTE EG 432-1).
pub const D65_XY: [f64; 2] = [0.3127, 0.3290];
/// The ACES white (≈ D60), SMPTE ST 2065-1.
pub const ACES_WHITE_XY: [f64; 2] = [0.32168, 0.33767];

/// sRGB / Rec.709 primaries, D65 white (IEC 61966-2-1, ITU-R BT.709).
pub const SRGB: RgbColorSpace = RgbColorSpace {
    name: "srgb",
    primaries: [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
    white: D65_XY,
};
/// Rec.2020 (ITU-R BT.2020), D65 white.
pub const REC2020: RgbColorSpace = RgbColorSpace {
    name: "rec2020",
    primaries: [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]],
    white: D65_XY,
};
/// Display P3 (DCI-P3 primaries, D65 white; SMPTE EG 432-1).
pub const DISPLAY_P3: RgbColorSpace = RgbColorSpace {
    name: "display-p3",
    primaries: [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]],
    white: D65_XY,
};
/// ACES2065-1 (AP0 primaries, ACES white; SMPTE ST 2065-1).
pub const ACES2065_1: RgbColorSpace = RgbColorSpace {
    name: "aces2065-1",
    primaries: [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.0770]],
    white: ACES_WHITE_XY,
};

/// Bradford cone-response matrix (Lam 1985, as standardized in ICC.1 / CIECAM97s).
const BRADFORD: Mat3 = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// Matrix that maps XYZ seen under white `from` to the corresponding XYZ under white `to`
/// (both XYZ), by von Kries scaling in the Bradford cone space.
pub fn bradford(from: [f64; 3], to: [f64; 3]) -> Mat3 {
    let inv = inverse(&BRADFORD).expect("Bradford matrix is invertible");
    let s = mul_vec(&BRADFORD, from);
    let d = mul_vec(&BRADFORD, to);
    mul(
        &inv,
        &mul(&diag([d[0] / s[0], d[1] / s[1], d[2] / s[2]]), &BRADFORD),
    )
}

impl RgbColorSpace {
    /// All built-in spaces.
    pub const ALL: [RgbColorSpace; 4] = [SRGB, REC2020, DISPLAY_P3, ACES2065_1];

    /// Look up a built-in space by name (case-insensitive; `rec709`/`linear-srgb` = sRGB,
    /// `p3` = Display P3, `aces`/`ap0` = ACES2065-1).
    pub fn by_name(name: &str) -> Option<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "srgb" | "linear-srgb" | "rec709" | "bt709" => Some(SRGB),
            "rec2020" | "bt2020" => Some(REC2020),
            "display-p3" | "p3" => Some(DISPLAY_P3),
            "aces2065-1" | "aces" | "ap0" => Some(ACES2065_1),
            _ => None,
        }
    }

    /// White point XYZ with Y = 1.
    pub fn white_xyz(&self) -> [f64; 3] {
        xyz_from_xy(self.white[0], self.white[1], 1.0)
    }

    /// Linear RGB → XYZ (Y of white = 1): columns are the primaries' XYZ scaled so that
    /// RGB (1,1,1) maps to the white point.
    pub fn rgb_to_xyz_matrix(&self) -> Mat3 {
        let p: Vec<[f64; 3]> = self
            .primaries
            .iter()
            .map(|xy| xyz_from_xy(xy[0], xy[1], 1.0))
            .collect();
        let m: Mat3 = std::array::from_fn(|r| [p[0][r], p[1][r], p[2][r]]);
        let s = mul_vec(
            &inverse(&m).expect("primaries are not collinear"),
            self.white_xyz(),
        );
        std::array::from_fn(|r| std::array::from_fn(|c| m[r][c] * s[c]))
    }

    /// XYZ → linear RGB for XYZ whose white is this space's white.
    pub fn xyz_to_rgb_matrix(&self) -> Mat3 {
        inverse(&self.rgb_to_xyz_matrix()).expect("RGB→XYZ is invertible")
    }

    /// XYZ → linear RGB for XYZ measured relative to `source_white` (XYZ, any scale): Bradford
    /// adaptation to this space's white, then the inverse primaries matrix.
    pub fn xyz_to_rgb_matrix_from(&self, source_white: [f64; 3]) -> Mat3 {
        let src = source_white.map(|v| v / source_white[1]);
        mul(&self.xyz_to_rgb_matrix(), &bradford(src, self.white_xyz()))
    }

    /// Convert XYZ (white = this space's white) to linear RGB.
    pub fn xyz_to_rgb(&self, xyz: [f64; 3]) -> [f64; 3] {
        mul_vec(&self.xyz_to_rgb_matrix(), xyz)
    }

    /// Convert linear RGB to XYZ.
    pub fn rgb_to_xyz(&self, rgb: [f64; 3]) -> [f64; 3] {
        mul_vec(&self.rgb_to_xyz_matrix(), rgb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Mat3, b: &Mat3, tol: f64) -> bool {
        (0..3).all(|r| (0..3).all(|c| (a[r][c] - b[r][c]).abs() < tol))
    }

    // sRGB: IEC 61966-2-1 publishes the RGB→XYZ matrix to 4 decimals; 1e-4 is that rounding.
    #[test]
    fn srgb_matrix_matches_standard() {
        let m = SRGB.rgb_to_xyz_matrix();
        let iec = [
            [0.4124, 0.3576, 0.1805],
            [0.2126, 0.7152, 0.0722],
            [0.0193, 0.1192, 0.9505],
        ];
        assert!(close(&m, &iec, 1.0e-4), "{m:?}");
    }

    // ACES2065-1: SMPTE ST 2065-1 publishes the AP0→XYZ matrix to 10 decimals; 1e-8 leaves
    // room for our different rounding order.
    #[test]
    fn aces_matrix_matches_standard() {
        let m = ACES2065_1.rgb_to_xyz_matrix();
        let st = [
            [0.9525523959, 0.0, 0.0000936786],
            [0.3439664498, 0.7281660966, -0.0721325464],
            [0.0, 0.0, 1.0088251844],
        ];
        assert!(close(&m, &st, 1e-8), "{m:?}");
    }

    // Bradford D65→D50 against the matrix Lindbloom publishes (brucelindbloom.com, "Chromatic
    // Adaptation", 7 decimals, with white XYZ D65 = 0.95047,1,1.08883 and D50 = 0.96422,1,0.82521);
    // 1e-6 is the published rounding.
    #[test]
    fn bradford_d65_to_d50() {
        let m = bradford([0.95047, 1.0, 1.08883], [0.96422, 1.0, 0.82521]);
        let lindbloom = [
            [1.0478112, 0.0228866, -0.0501270],
            [0.0295424, 0.9904844, -0.0170491],
            [-0.0092345, 0.0150436, 0.7521316],
        ];
        assert!(close(&m, &lindbloom, 1e-6), "{m:?}");
        // Same white: identity.
        let id = bradford([0.95, 1.0, 1.09], [0.95, 1.0, 1.09]);
        assert!(close(&id, &diag([1.0; 3]), 1e-12));
    }

    // The luminance rows (Y of each primary) are published: ITU-R BT.2020 gives 0.2627,
    // 0.6780, 0.0593 for Rec.2020; SMPTE EG 432-1 gives 0.2290, 0.6917, 0.0793 for Display P3
    // (4 decimals, so 1e-4).
    #[test]
    fn luminance_rows_match_standards() {
        let rec = REC2020.rgb_to_xyz_matrix()[1];
        let p3 = DISPLAY_P3.rgb_to_xyz_matrix()[1];
        for (got, want) in rec.iter().zip([0.2627, 0.6780, 0.0593]) {
            assert!((got - want).abs() < 1e-4, "{rec:?}");
        }
        for (got, want) in p3.iter().zip([0.2290, 0.6917, 0.0793]) {
            assert!((got - want).abs() < 1e-4, "{p3:?}");
        }
    }

    // White maps to RGB (1,1,1) in every space (1e-12: matrix round trip).
    #[test]
    fn white_is_one() {
        for s in RgbColorSpace::ALL {
            let rgb = s.xyz_to_rgb(s.white_xyz());
            assert!(
                rgb.iter().all(|v| (v - 1.0).abs() < 1e-12),
                "{}: {rgb:?}",
                s.name
            );
        }
    }
}
