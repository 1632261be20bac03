//! Reading texture and environment-map images: PNG, JPEG and Radiance HDR through the `image`
//! crate, OpenEXR through the `exr` crate (RGB, luminance-only `Y`, or the spectral
//! `S0.<λ>nm` layout spectrace writes, see [`crate::film::spectral`]).
//!
//! | format | pixel values | default encoding |
//! |---|---|---|
//! | PNG (8/16-bit), JPEG | integers scaled to [0, 1] | `srgb`: the sRGB transfer curve is undone |
//! | Radiance HDR (`.hdr`, RGBE) | linear floats | `linear` |
//! | OpenEXR, channels `R`,`G`,`B` (or `Y`) | linear floats (half or full) | `linear` |
//! | OpenEXR, channels `S0.<λ>nm` | spectral radiance / reflectance per node | (spectral) |
//!
//! Alpha is ignored; grey images give equal channels. Rows are stored top row first, as every
//! one of these formats stores them. Negative and non-finite values (possible in EXR and HDR)
//! become 0 (a count is returned so the caller can warn).
//!
//! Limits (checked from the header before any pixel is decoded): each side ≤
//! [`MAX_SIDE`], and width × height × channels × 8 bytes ≤ half the available memory
//! ([`crate::limits::available_memory_bytes`]); files ≤ [`max_file_bytes`]. A broken or
//! truncated file is an error naming the file; decoder panics are caught and reported as
//! errors too.

use crate::color::srgb_decode as srgb_to_linear;
use std::io::Cursor;
use std::path::Path;

/// Largest width or height accepted (pixels): 64k, beyond any real texture or sky.
pub const MAX_SIDE: u64 = 1 << 16;

/// How integer pixel values map to linear ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// The sRGB transfer function (IEC 61966-2-1) is undone.
    Srgb,
    /// Values are linear already.
    Linear,
}

impl Encoding {
    /// `"srgb"` or `"linear"`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "srgb" | "sRGB" => Ok(Self::Srgb),
            "linear" => Ok(Self::Linear),
            other => Err(format!(
                "unknown encoding `{other}` (expected \"srgb\" or \"linear\")"
            )),
        }
    }

    /// The scene name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Srgb => "srgb",
            Self::Linear => "linear",
        }
    }
}

/// The file formats recognised (by their first bytes, not their names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// PNG.
    Png,
    /// JPEG.
    Jpeg,
    /// Radiance RGBE.
    Hdr,
    /// OpenEXR.
    Exr,
}

impl Format {
    /// The format of a file starting with `bytes`, if known.
    pub fn sniff(bytes: &[u8]) -> Option<Self> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some(Self::Png)
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            Some(Self::Jpeg)
        } else if bytes.starts_with(b"#?RADIANCE") || bytes.starts_with(b"#?RGBE") {
            Some(Self::Hdr)
        } else if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
            Some(Self::Exr)
        } else {
            None
        }
    }

    /// The encoding a file of this format has unless the scene says otherwise.
    pub fn default_encoding(self) -> Encoding {
        match self {
            Self::Png | Self::Jpeg => Encoding::Srgb,
            Self::Hdr | Self::Exr => Encoding::Linear,
        }
    }
}

/// A linear RGB image, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major linear RGB, ≥ 0 and finite.
    pub pixels: Vec<[f32; 3]>,
}

/// A spectral image, top row first: values at evenly spaced wavelength nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralTexels {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// First node (nm).
    pub start: f32,
    /// Node spacing (nm), > 0.
    pub step: f32,
    /// Number of nodes (≥ 1).
    pub nodes: usize,
    /// Row-major pixels, nodes innermost; ≥ 0 and finite.
    pub values: Vec<f32>,
}

impl SpectralTexels {
    /// Value of pixel `i` at `lambda_nm`, linear between nodes, 0 outside `[start, last]`.
    #[inline]
    pub fn value(&self, i: usize, lambda_nm: f32) -> f32 {
        let x = (lambda_nm - self.start) / self.step;
        let last = (self.nodes - 1) as f32;
        if !(x >= 0.0 && x <= last) {
            return 0.0;
        }
        let k = (x as usize).min(self.nodes.saturating_sub(2));
        let t = x - k as f32;
        let px = &self.values[i * self.nodes..(i + 1) * self.nodes];
        if self.nodes == 1 {
            return px[0];
        }
        px[k] * (1.0 - t) + px[k + 1] * t
    }

    /// The wavelength of node `k` (nm).
    pub fn node(&self, k: usize) -> f32 {
        self.start + self.step * k as f32
    }
}

/// A decoded image: RGB or spectral.
#[derive(Clone, Debug, PartialEq)]
pub enum LoadedImage {
    /// Linear RGB (any format).
    Rgb(RgbImage),
    /// Spectral (EXR with `S0.<λ>nm` channels).
    Spectral(SpectralTexels),
}

impl LoadedImage {
    /// `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        match self {
            Self::Rgb(i) => (i.width, i.height),
            Self::Spectral(s) => (s.width, s.height),
        }
    }
}

/// What loading found besides the pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Pixel values that were negative, NaN or infinite and became 0.
    pub replaced: usize,
}

/// Largest image file read: 1/8 of the available memory, at least 64 MiB, at most 4 GiB.
pub fn max_file_bytes() -> u64 {
    (crate::limits::available_memory_bytes() / 8).clamp(64 << 20, 4 << 30)
}

/// Refuse an image of `width × height` pixels with `channels` channels before decoding it:
/// each side ≤ [`MAX_SIDE`], and 8 bytes per channel value (the decoded floats and their
/// copy) within half of `available` bytes.
pub fn check_size(width: u64, height: u64, channels: u64, available: u64) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the image is empty ({width} × {height} pixels)"));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!(
            "the image is {width} × {height} pixels; each side may be at most {MAX_SIDE}"
        ));
    }
    let need = width
        .saturating_mul(height)
        .saturating_mul(channels.max(1))
        .saturating_mul(8);
    if need > available / 2 {
        return Err(format!(
            "the image ({width} × {height} pixels, {channels} channels) needs about {} once \
             decoded, more than half of the available memory ({})",
            crate::limits::human_bytes(need),
            crate::limits::human_bytes(available)
        ));
    }
    Ok(())
}

/// Read and decode the image file `path` (any supported format). `encoding` overrides the
/// format's default for integer formats (HDR and EXR are always linear: asking for `srgb`
/// there is an error). Errors name the file.
pub fn load(path: &Path, encoding: Option<Encoding>) -> Result<(LoadedImage, LoadReport), String> {
    let bytes = crate::limits::read_limited(path, max_file_bytes(), "image")
        .map_err(|e| format!("cannot read image {}: {e}", path.display()))?;
    decode(&bytes, encoding, crate::limits::available_memory_bytes())
        .map_err(|e| format!("image {}: {e}", path.display()))
}

/// Decode an image held in memory (what [`load`] does after reading the file); `available`
/// is the memory budget in bytes (see [`check_size`]).
pub fn decode(
    bytes: &[u8],
    encoding: Option<Encoding>,
    available: u64,
) -> Result<(LoadedImage, LoadReport), String> {
    let format = Format::sniff(bytes)
        .ok_or("not a PNG, JPEG, Radiance HDR or OpenEXR file (unrecognised first bytes)")?;
    let encoding_used = encoding.unwrap_or(format.default_encoding());
    if matches!(format, Format::Hdr | Format::Exr) && encoding_used == Encoding::Srgb {
        return Err(
            "HDR and EXR files hold linear values: `encoding: \"srgb\"` does not apply".into(),
        );
    }
    // Third-party decoders: a panic on hostile input becomes an error, not an abort.
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match format {
        Format::Exr => decode_exr(bytes, available),
        _ => decode_with_image_crate(bytes, format, encoding_used, available),
    }));
    match run {
        Ok(r) => r,
        Err(_) => Err("the decoder failed on this file (malformed data)".into()),
    }
}

fn decode_with_image_crate(
    bytes: &[u8],
    format: Format,
    encoding: Encoding,
    available: u64,
) -> Result<(LoadedImage, LoadReport), String> {
    let image_format = match format {
        Format::Png => image::ImageFormat::Png,
        Format::Jpeg => image::ImageFormat::Jpeg,
        Format::Hdr => image::ImageFormat::Hdr,
        Format::Exr => unreachable!("EXR is read by the exr crate"),
    };
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), image_format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE as u32);
    limits.max_image_height = Some(MAX_SIDE as u32);
    limits.max_alloc = Some(available / 2);
    reader.limits(limits);
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| format!("cannot read the header: {e}"))?;
    check_size(w as u64, h as u64, 3, available)?;
    let mut reader = image::ImageReader::with_format(Cursor::new(bytes), image_format);
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(available / 2);
    reader.limits(limits);
    let img = reader.decode().map_err(|e| format!("cannot decode: {e}"))?;
    let mut report = LoadReport::default();
    let pixels: Vec<[f32; 3]> = match (&img, encoding) {
        // 8-bit sRGB: one table of the 256 decoded values.
        (
            image::DynamicImage::ImageRgb8(_)
            | image::DynamicImage::ImageRgba8(_)
            | image::DynamicImage::ImageLuma8(_)
            | image::DynamicImage::ImageLumaA8(_),
            _,
        ) => {
            let lut: Vec<f32> = (0..256)
                .map(|i| {
                    let x = i as f64 / 255.0;
                    (match encoding {
                        Encoding::Srgb => srgb_to_linear(x),
                        Encoding::Linear => x,
                    }) as f32
                })
                .collect();
            img.to_rgb8()
                .pixels()
                .map(|p| [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]])
                .collect()
        }
        _ => img
            .to_rgb32f()
            .pixels()
            .map(|p| {
                let mut c = [p[0], p[1], p[2]];
                for v in &mut c {
                    if !(v.is_finite() && *v >= 0.0) {
                        report.replaced += 1;
                        *v = 0.0;
                    } else if format != Format::Hdr && encoding == Encoding::Srgb {
                        *v = srgb_to_linear(*v as f64) as f32;
                    }
                }
                c
            })
            .collect(),
    };
    Ok((
        LoadedImage::Rgb(RgbImage {
            width: w,
            height: h,
            pixels,
        }),
        report,
    ))
}

fn decode_exr(bytes: &[u8], available: u64) -> Result<(LoadedImage, LoadReport), String> {
    use exr::prelude::*;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| format!("cannot read the OpenEXR header: {e}"))?;
    let header = meta
        .headers
        .first()
        .ok_or("the OpenEXR file has no layer")?;
    let channels = header.channels.list.len() as u64;
    // Every layer is decoded: its pixels count against the budget too.
    let mut total_values = 0u64;
    for h in meta.headers.iter() {
        let (w, ht) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        check_size(w, ht, h.channels.list.len() as u64, available)?;
        total_values = total_values.saturating_add(w * ht * h.channels.list.len() as u64);
    }
    if total_values.saturating_mul(8) > available / 2 {
        return Err(format!(
            "the OpenEXR layers hold {total_values} values, more than half of the available memory allows"
        ));
    }
    let _ = channels;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .non_parallel()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| format!("cannot decode the OpenEXR data: {e}"))?;
    let mut report = LoadReport::default();
    let mut clean = |v: f32| {
        if v.is_finite() && v >= 0.0 {
            v
        } else {
            report.replaced += 1;
            0.0
        }
    };
    // Spectral first: a layer with S0.<λ>nm channels.
    for layer in &image.layer_data {
        let (w, h) = (layer.size.width(), layer.size.height());
        let mut spectral: Vec<(f64, &AnyChannel<FlatSamples>)> = layer
            .channel_data
            .list
            .iter()
            .filter_map(|c| {
                crate::film::spectral::parse_channel(&c.name.to_string()).map(|l| (l, c))
            })
            .collect();
        if spectral.is_empty() {
            continue;
        }
        spectral.sort_by(|a, b| a.0.total_cmp(&b.0));
        let nodes = spectral.len();
        let step = if nodes > 1 {
            spectral[1].0 - spectral[0].0
        } else {
            1.0
        };
        if !(step > 0.0) {
            return Err(format!("two spectral channels at {} nm", spectral[0].0));
        }
        for p in spectral.windows(2) {
            if ((p[1].0 - p[0].0) - step).abs() > 1e-3 * step {
                return Err(format!(
                    "spectral channels are not evenly spaced ({step} nm then {} nm apart)",
                    p[1].0 - p[0].0
                ));
            }
        }
        let mut values = vec![0.0f32; w * h * nodes];
        for (k, (_, c)) in spectral.iter().enumerate() {
            for (i, v) in c.sample_data.values_as_f32().enumerate().take(w * h) {
                values[i * nodes + k] = clean(v);
            }
        }
        return Ok((
            LoadedImage::Spectral(SpectralTexels {
                width: w as u32,
                height: h as u32,
                start: spectral[0].0 as f32,
                step: step as f32,
                nodes,
                values,
            }),
            report,
        ));
    }
    // RGB (or Y) in the first layer that has them; names may carry a layer prefix (`diffuse.R`).
    for layer in &image.layer_data {
        let (w, h) = (layer.size.width(), layer.size.height());
        let find = |name: &str| {
            layer.channel_data.list.iter().find(|c| {
                let n = c.name.to_string();
                n == name || n.ends_with(&format!(".{name}"))
            })
        };
        let rgb = match (find("R"), find("G"), find("B"), find("Y")) {
            (Some(r), Some(g), Some(b), _) => [r, g, b],
            (_, _, _, Some(y)) => [y, y, y],
            _ => continue,
        };
        let mut pixels = vec![[0.0f32; 3]; w * h];
        for (c, ch) in rgb.iter().enumerate() {
            for (i, v) in ch.sample_data.values_as_f32().enumerate().take(w * h) {
                pixels[i][c] = clean(v);
            }
        }
        return Ok((
            LoadedImage::Rgb(RgbImage {
                width: w as u32,
                height: h as u32,
                pixels,
            }),
            report,
        ));
    }
    Err("the OpenEXR file has neither R, G, B (or Y) nor spectral S0.<λ>nm channels".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png_bytes(w: u32, h: u32, px: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let img = image::RgbImage::from_raw(w, h, px.to_vec()).unwrap();
        img.write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
            .unwrap();
        out
    }

    /// 8-bit sRGB decodes through the IEC 61966-2-1 curve (128/255 → 0.21586, the
    /// published value, to 1e-4), `linear` keeps v/255.
    #[test]
    fn srgb_png_decodes_to_linear() {
        let bytes = png_bytes(2, 1, &[128, 188, 255, 0, 1, 10]);
        let (img, _) = decode(&bytes, None, 1 << 30).unwrap();
        let LoadedImage::Rgb(img) = img else { panic!() };
        assert!(
            (img.pixels[0][0] - 0.21586).abs() < 1e-4,
            "{:?}",
            img.pixels
        );
        assert!((img.pixels[0][1] as f64 - srgb_to_linear(188.0 / 255.0)).abs() < 1e-6);
        assert_eq!(img.pixels[0][2], 1.0);
        assert_eq!(img.pixels[1][0], 0.0);
        assert!((img.pixels[1][1] - 1.0 / 255.0 / 12.92).abs() < 1e-7);
        let (lin, _) = decode(&bytes, Some(Encoding::Linear), 1 << 30).unwrap();
        let LoadedImage::Rgb(lin) = lin else { panic!() };
        assert!((lin.pixels[0][0] - 128.0 / 255.0).abs() < 1e-6);
    }

    /// A JPEG (written by the `image` crate's encoder at quality 95) decodes as sRGB: a flat
    /// 8 × 8 block of (200, 100, 50) comes back within 3/255 per encoded channel (JPEG is
    /// lossy; flat blocks keep their DC value to about one code value).
    #[test]
    fn jpeg_decodes_as_srgb() {
        let img = image::RgbImage::from_pixel(8, 8, image::Rgb([200, 100, 50]));
        let mut bytes = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 95)
            .encode_image(&img)
            .unwrap();
        assert_eq!(Format::sniff(&bytes), Some(Format::Jpeg));
        let (LoadedImage::Rgb(out), _) = decode(&bytes, None, 1 << 30).unwrap() else {
            panic!("not RGB")
        };
        for (c, want) in [200.0, 100.0, 50.0].iter().enumerate() {
            let lin = out.pixels[27][c] as f64;
            let back = crate::color::srgb_encode(lin) * 255.0;
            assert!((back - want).abs() < 3.0, "channel {c}: {back} vs {want}");
        }
    }

    /// Broken input of each kind is an error, not a panic: unknown bytes, a truncated PNG, a
    /// PNG header declaring 100000 × 100000 pixels (refused before decoding), garbage after an
    /// EXR magic number, and sRGB asked of an HDR file.
    #[test]
    fn broken_images_are_errors() {
        assert!(decode(b"hello", None, 1 << 30)
            .unwrap_err()
            .contains("unrecognised"));
        let good = png_bytes(4, 4, &[7; 48]);
        let e = decode(&good[..good.len() / 2], None, 1 << 30).unwrap_err();
        assert!(e.contains("cannot"), "{e}");
        // IHDR with width = height = 100000 (CRC wrong too: either is refused).
        let mut huge = good.clone();
        huge[16..20].copy_from_slice(&100_000u32.to_be_bytes());
        huge[20..24].copy_from_slice(&100_000u32.to_be_bytes());
        assert!(decode(&huge, None, 1 << 30).is_err());
        let mut exr = vec![0x76, 0x2f, 0x31, 0x01];
        exr.extend_from_slice(&[0xff; 64]);
        assert!(decode(&exr, None, 1 << 30).is_err());
        assert!(decode(b"#?RADIANCE\n", Some(Encoding::Srgb), 1 << 30).is_err());
    }

    /// The size check refuses an image that would not fit the memory budget, and sides
    /// beyond [`MAX_SIDE`], with the numbers in the message.
    #[test]
    fn size_limits() {
        assert!(check_size(4096, 2048, 3, 1 << 30).is_ok());
        let e = check_size(4096, 2048, 3, 100 << 20).unwrap_err();
        assert!(e.contains("4096 × 2048"), "{e}");
        assert!(check_size(MAX_SIDE + 1, 1, 3, u64::MAX).is_err());
        assert!(check_size(0, 5, 3, u64::MAX).is_err());
    }
}
