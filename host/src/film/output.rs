//! Writing images: OpenEXR (f32 channels R, G, B in the chosen linear RGB space, plus the film's
//! X, Y, Z) and an 8-bit sRGB PNG preview.

use super::XyzImage;
use crate::color::{linear_to_srgb8, RgbColorSpace, SRGB};
use std::path::{Path, PathBuf};

/// A failure to write an image; names the file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The EXR encoder or the file system failed.
    #[error("cannot write OpenEXR {path}: {message}")]
    Exr {
        /// Target file.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// The PNG encoder or the file system failed.
    #[error("cannot write PNG {path}: {message}")]
    Png {
        /// Target file.
        path: PathBuf,
        /// Cause.
        message: String,
    },
}

/// Write `image` as OpenEXR with channels R, G, B (linear `space`) and X, Y, Z (f32).
pub fn write_exr(path: &Path, image: &XyzImage, space: &RgbColorSpace) -> Result<(), OutputError> {
    write_exr_with_layers(path, image, space, Vec::new())
}

/// [`write_exr`] plus `extra` f32 channels (name, one value per pixel, row-major), e.g. the
/// guard's `rejected` counts.
pub fn write_exr_with_layers(
    path: &Path,
    image: &XyzImage,
    space: &RgbColorSpace,
    extra: Vec<(String, Vec<f32>)>,
) -> Result<(), OutputError> {
    use exr::prelude::*;
    let rgb = image.to_rgb(space);
    let chan = |name: &str, vals: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(vals));
    let pick = |data: &[[f64; 3]], c: usize| data.iter().map(|p| p[c] as f32).collect::<Vec<_>>();
    let mut list = vec![
        chan("R", pick(&rgb, 0)),
        chan("G", pick(&rgb, 1)),
        chan("B", pick(&rgb, 2)),
        chan("X", pick(&image.xyz, 0)),
        chan("Y", pick(&image.xyz, 1)),
        chan("Z", pick(&image.xyz, 2)),
    ];
    for (name, values) in extra {
        list.push(chan(&name, values));
    }
    let channels = SmallVec::from_vec(list);
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        LayerAttributes::named(""),
        // Blocks in increasing order: the parallel encoder then writes the same bytes for the
        // same image (with the default unspecified order the chunk table varies run to run).
        Encoding {
            line_order: LineOrder::Increasing,
            ..Encoding::FAST_LOSSLESS
        },
        AnyChannels::sort(channels),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| OutputError::Exr {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
}

/// Write an 8-bit sRGB PNG preview (linear sRGB × `exposure`, clamped, sRGB-encoded).
pub fn write_png(path: &Path, image: &XyzImage, exposure: f64) -> Result<(), OutputError> {
    let err = |message: String| OutputError::Png {
        path: path.to_path_buf(),
        message,
    };
    let rgb = image.to_rgb(&SRGB);
    let mut bytes = Vec::with_capacity(rgb.len() * 3);
    for p in &rgb {
        let v = p.map(|c| {
            let c = c * exposure;
            if c.is_finite() {
                c.clamp(0.0, 1.0)
            } else {
                0.0
            }
        });
        bytes.extend_from_slice(&linear_to_srgb8(v));
    }
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), image.width, image.height);
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

    /// An EXR written here reads back with the same six channels and values (f32 exact), and a
    /// PNG is produced; an unwritable path gives an error naming the file, not a panic.
    #[test]
    fn exr_round_trip_and_errors() {
        let dir = std::env::temp_dir().join(format!("spectrace-film-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let img = XyzImage {
            width: 2,
            height: 1,
            xyz: vec![[0.5, 1.0, 0.25], [0.0, 0.0, 0.0]],
        };
        let p = dir.join("t.exr");
        write_exr(&p, &img, &SRGB).unwrap();
        let read = exr::prelude::read_all_flat_layers_from_file(&p).unwrap();
        let names: Vec<String> = read.layer_data[0]
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(names, ["B", "G", "R", "X", "Y", "Z"]);
        let y = &read.layer_data[0].channel_data.list[4].sample_data;
        assert_eq!(y.value_by_flat_index(0).to_f32(), 1.0);
        write_png(&dir.join("t.png"), &img, 1.0).unwrap();
        let bad = dir.join("missing-dir").join("x.exr");
        let e = write_exr(&bad, &img, &SRGB).unwrap_err().to_string();
        assert!(e.contains("x.exr"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
