//! The false-colour difference image of `spectrace compare --diff`: per-pixel CIEDE2000 mapped
//! piecewise-linearly (in 8-bit sRGB) through the stops
//! ΔE00 = 0 black, 1 blue (just noticeable), 2 cyan, 5 yellow, ≥ 10 red;
//! pixels left out of the comparison (the light, non-finite values) are mid grey.

use super::AnalysisError;
use std::path::Path;

/// The colour-map stops: (ΔE00, sRGB 8-bit colour).
pub const DELTA_E_STOPS: [(f64, [u8; 3]); 5] = [
    (0.0, [0, 0, 0]),
    (1.0, [0, 64, 255]),
    (2.0, [0, 220, 220]),
    (5.0, [255, 230, 0]),
    (10.0, [255, 0, 0]),
];

/// Colour of pixels left out of the comparison.
pub const EXCLUDED_COLOR: [u8; 3] = [128, 128, 128];

/// The display colour of one ΔE00 value (`None`: left out).
pub fn delta_e_color(de: Option<f64>) -> [u8; 3] {
    let Some(de) = de else {
        return EXCLUDED_COLOR;
    };
    let last = DELTA_E_STOPS[DELTA_E_STOPS.len() - 1];
    if !(de < last.0) {
        return last.1;
    }
    for pair in DELTA_E_STOPS.windows(2) {
        let ((x0, c0), (x1, c1)) = (pair[0], pair[1]);
        if de <= x1 {
            let t = ((de - x0) / (x1 - x0)).clamp(0.0, 1.0);
            return std::array::from_fn(|i| {
                (c0[i] as f64 + t * (c1[i] as f64 - c0[i] as f64)).round() as u8
            });
        }
    }
    DELTA_E_STOPS[0].1
}

/// Write the per-pixel ΔE00 map as an 8-bit PNG.
pub fn write_delta_e_png(
    path: &Path,
    width: u32,
    height: u32,
    per_pixel: &[Option<f64>],
) -> Result<(), AnalysisError> {
    let err = |message: String| AnalysisError::Write {
        path: path.to_path_buf(),
        message,
    };
    let bytes: Vec<u8> = per_pixel.iter().flat_map(|d| delta_e_color(*d)).collect();
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| err(e.to_string()))?;
    writer
        .write_image_data(&bytes)
        .map_err(|e| err(e.to_string()))?;
    writer.finish().map_err(|e| err(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map hits its stops exactly, interpolates between them, saturates above 10 and greys
    /// out excluded pixels (exact 8-bit values: the map is defined in integers).
    #[test]
    fn colour_map_stops() {
        assert_eq!(delta_e_color(Some(0.0)), [0, 0, 0]);
        assert_eq!(delta_e_color(Some(1.0)), [0, 64, 255]);
        assert_eq!(delta_e_color(Some(0.5)), [0, 32, 128]);
        assert_eq!(delta_e_color(Some(50.0)), [255, 0, 0]);
        assert_eq!(delta_e_color(Some(f64::NAN)), [255, 0, 0]);
        assert_eq!(delta_e_color(None), EXCLUDED_COLOR);
    }
}
