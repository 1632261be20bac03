//! A linear-RGB image read from OpenEXR (channels R, G, B), the form renders are compared in.

use super::AnalysisError;
use std::path::Path;

/// Linear RGB per pixel, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width·height` RGB triples.
    pub rgb: Vec<[f64; 3]>,
}

impl RgbImage {
    /// The text attribute `name` of `path`'s header (any part), if it has one: what a file
    /// says of itself, such as the colour convention of a bench reference.
    pub fn read_exr_text_attribute(
        path: &Path,
        name: &str,
    ) -> Result<Option<String>, AnalysisError> {
        let meta =
            exr::meta::MetaData::read_from_file(path, false).map_err(|e| AnalysisError::Read {
                path: path.to_path_buf(),
                message: format!("not a readable OpenEXR file ({e})"),
            })?;
        let key = exr::prelude::Text::from(name);
        Ok(meta.headers.iter().find_map(|h| {
            let value = h
                .own_attributes
                .other
                .get(&key)
                .or(h.shared_attributes.other.get(&key));
            match value {
                Some(exr::meta::attribute::AttributeValue::Text(t)) => Some(t.to_string()),
                _ => None,
            }
        }))
    }

    /// Read channels R, G and B of the first layer of `path` that has all three. Channel names
    /// may carry a layer prefix (`layer.R`). Other channels (A, X, Y, Z) are ignored.
    pub fn read_exr(path: &Path) -> Result<Self, AnalysisError> {
        if !path.exists() {
            return Err(AnalysisError::Read {
                path: path.to_path_buf(),
                message: "no such file".into(),
            });
        }
        let image = exr::prelude::read_all_flat_layers_from_file(path).map_err(|e| {
            AnalysisError::Read {
                path: path.to_path_buf(),
                message: format!("not a readable OpenEXR file ({e})"),
            }
        })?;
        let mut seen = Vec::new();
        for layer in &image.layer_data {
            let find = |want: &str| {
                layer.channel_data.list.iter().position(|c| {
                    let name = c.name.to_string();
                    name == want || name.rsplit('.').next() == Some(want)
                })
            };
            seen.extend(layer.channel_data.list.iter().map(|c| c.name.to_string()));
            let (Some(r), Some(g), Some(b)) = (find("R"), find("G"), find("B")) else {
                continue;
            };
            let size = layer.size;
            let (w, h) = (size.width(), size.height());
            let chans = [r, g, b].map(|i| &layer.channel_data.list[i].sample_data);
            let rgb = (0..w * h)
                .map(|i| chans.map(|c| c.value_by_flat_index(i).to_f32() as f64))
                .collect();
            return Ok(Self {
                width: w as u32,
                height: h as u32,
                rgb,
            });
        }
        Err(AnalysisError::Content {
            path: path.to_path_buf(),
            message: format!(
                "no layer has channels R, G and B (channels found: {})",
                if seen.is_empty() {
                    "none".to_string()
                } else {
                    seen.join(", ")
                }
            ),
        })
    }

    /// Convert a film image to linear RGB in `space`.
    pub fn from_xyz(image: &crate::film::XyzImage, space: &crate::color::RgbColorSpace) -> Self {
        Self {
            width: image.width,
            height: image.height,
            rgb: image.to_rgb(space),
        }
    }
}
