//! Spectral film: per-pixel histogram of spectral radiance, written as an OpenEXR in the layout
//! of Fichet, Pacanowski and Wilkie 2021 ("An OpenEXR Layout for Spectral Images", JCGT 10(3)).
//!
//! | parameter | meaning |
//! |---|---|
//! | `start`, `end` (nm) | the binned range; bin k covers `[start + k·step, start + (k+1)·step)` |
//! | `step` (nm) | bin width Δ; CLI `--bins START:END:STEP`, default `380:780:5` |
//!
//! Each camera sample lane (wavelength λ, value L, density pdf in 1/nm) adds
//! `L·w/(pdf·LANES·Δ)` to the bin holding λ: the histogram estimate of the bin-averaged
//! spectral radiance in W/(m²·sr·nm). Wavelengths outside the range are dropped (the film XYZ
//! still sees them). Only the thread rendering a pixel's tile adds to it, in sample order, so
//! the plain f64 sums are the same bits for any thread count.
//!
//! Channels are `S0.<λ>nm` with λ the bin centre printed with six decimals and a comma as
//! decimal separator (e.g. `S0.382,500000nm`), header attributes `spectralLayoutVersion = "1.0"`
//! and `emissiveUnits = "W.m^-2.sr^-1"` (the values are densities per nm, as pbrt-v4 writes them).

use super::rejected::check_sample;
use crate::color::Observer;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use std::path::Path;
use std::sync::Mutex;

/// Wavelength bins of a spectral image, in nm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralBins {
    /// Lower edge of the first bin (nm).
    pub start: f64,
    /// Bin width Δ (nm).
    pub step: f64,
    /// Number of bins.
    pub count: usize,
}

impl SpectralBins {
    /// Parse `START:END:STEP` in nm (e.g. `380:780:5`); END − START must be a whole number of
    /// steps.
    pub fn parse(s: &str) -> Result<Self, String> {
        let bad = |why: &str| {
            format!("--bins {s}: {why} (expected START:END:STEP in nm, e.g. 380:780:5)")
        };
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 3 {
            return Err(bad("three numbers separated by ':' needed"));
        }
        let num = |p: &str| {
            p.trim()
                .parse::<f64>()
                .map_err(|_| bad(&format!("'{p}' is not a number")))
        };
        let (a, b, d) = (num(parts[0])?, num(parts[1])?, num(parts[2])?);
        if !(a.is_finite() && b.is_finite() && d.is_finite()) || a < 0.0 || b <= a || d <= 0.0 {
            return Err(bad("need 0 ≤ START < END and STEP > 0"));
        }
        let n = (b - a) / d;
        let count = n.round() as usize;
        if (n - count as f64).abs() > 1e-6 || count == 0 {
            return Err(bad("END − START must be a whole number of steps"));
        }
        if count > 4096 {
            return Err(bad("more than 4096 bins"));
        }
        Ok(Self {
            start: a,
            step: d,
            count,
        })
    }

    /// Centre of bin `k` (nm).
    pub fn center(&self, k: usize) -> f64 {
        self.start + (k as f64 + 0.5) * self.step
    }

    /// The bin holding `lambda_nm`, if any.
    #[inline]
    pub fn bin(&self, lambda_nm: f64) -> Option<usize> {
        let k = ((lambda_nm - self.start) / self.step).floor();
        (k >= 0.0 && (k as usize) < self.count).then_some(k as usize)
    }

    /// The layout's channel name for bin `k`: `S0.<centre>nm`, comma as decimal separator.
    pub fn channel_name(&self, k: usize) -> String {
        format!("S0.{:.6}nm", self.center(k))
            .replace('.', ",")
            .replacen("S0,", "S0.", 1)
    }
}

/// Per-pixel spectral histogram sums and sample counts.
#[derive(Debug)]
pub struct SpectralFilm {
    bins: SpectralBins,
    width: u32,
    height: u32,
    /// Per pixel: (Σ bin values, sample count).
    pixels: Vec<Mutex<(Vec<f64>, u64)>>,
}

impl SpectralFilm {
    /// A black film of `width`×`height` pixels.
    pub fn new(bins: SpectralBins, width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            bins,
            width,
            height,
            pixels: (0..n)
                .map(|_| Mutex::new((vec![0.0; bins.count], 0)))
                .collect(),
        }
    }

    /// The bins.
    pub fn bins(&self) -> SpectralBins {
        self.bins
    }

    /// Add one camera sample to pixel (`x`, `y`): `groups` are its wavelength groups with
    /// radiances `l` (each scaled by `weight`); the groups are averaged as the film's XYZ
    /// does. `film_xyz` is what the XYZ film got: a sample its guard refuses adds only to the
    /// count here too.
    pub fn add(
        &self,
        x: u32,
        y: u32,
        l: &[SampledSpectrum],
        groups: &[SampledWavelengths],
        weight: f32,
        film_xyz: &[f64; 3],
    ) {
        if x >= self.width || y >= self.height {
            return;
        }
        let Ok(mut p) = self.pixels[(y * self.width + x) as usize].lock() else {
            return;
        };
        p.1 += 1;
        if check_sample(film_xyz).is_some() || groups.is_empty() {
            return;
        }
        let scale = 1.0 / (groups.len() as f64 * LANES as f64 * self.bins.step);
        for (lg, wg) in l.iter().zip(groups) {
            for i in 0..LANES {
                let pdf = wg.pdf[i] as f64;
                let v = (lg.0[i] * weight) as f64;
                if pdf <= 0.0 || v == 0.0 {
                    continue;
                }
                if let Some(k) = self.bins.bin(wg.lambda[i] as f64) {
                    p.0[k] += v / pdf * scale;
                }
            }
        }
    }

    /// Mean spectral radiance per pixel and bin (W/(m²·sr·nm)), row-major, bins innermost.
    pub fn means(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.pixels.len() * self.bins.count);
        for p in &self.pixels {
            let p = p.lock().map(|g| g.clone()).unwrap_or_default();
            let inv = if p.1 > 0 { 1.0 / p.1 as f64 } else { 0.0 };
            out.extend(p.0.iter().map(|v| v * inv));
            if p.0.len() < self.bins.count {
                out.extend(std::iter::repeat_n(0.0, self.bins.count - p.0.len()));
            }
        }
        out
    }

    /// The spectral image.
    pub fn image(&self) -> SpectralImage {
        SpectralImage {
            width: self.width,
            height: self.height,
            wavelengths: (0..self.bins.count).map(|k| self.bins.center(k)).collect(),
            step: self.bins.step,
            values: self.means(),
        }
    }
}

/// A spectral image: per pixel, radiance density at `wavelengths` (bin centres, nm) in
/// W/(m²·sr·nm), each bin `step` nm wide.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Bin centres (nm), increasing.
    pub wavelengths: Vec<f64>,
    /// Bin width (nm): the spacing of `wavelengths`.
    pub step: f64,
    /// Row-major pixels, bins innermost.
    pub values: Vec<f64>,
}

impl SpectralImage {
    /// Per-pixel XYZ under the film convention `∫L·x̄ȳz̄ dλ / ∫ȳ dλ`, with the bins as a
    /// piecewise-constant spectrum and the observer sampled at the bin centres (midpoint rule).
    pub fn to_xyz(&self, observer: &dyn Observer) -> Vec<[f64; 3]> {
        let iy = observer.integral_y();
        let inv = if iy > 0.0 { 1.0 / iy } else { 0.0 };
        let bars: Vec<[f64; 3]> = self
            .wavelengths
            .iter()
            .map(|&l| observer.xyz_bar(l))
            .collect();
        let n = self.wavelengths.len().max(1);
        self.values
            .chunks(n)
            .map(|px| {
                let mut xyz = [0.0; 3];
                for (v, b) in px.iter().zip(&bars) {
                    for c in 0..3 {
                        xyz[c] += v * b[c] * self.step * inv;
                    }
                }
                xyz
            })
            .collect()
    }

    /// Write as OpenEXR in the Fichet–Pacanowski–Wilkie layout (32-bit float channels).
    pub fn write_exr(&self, path: &Path) -> Result<(), String> {
        use exr::prelude::*;
        let n = self.wavelengths.len();
        let bins = SpectralBins {
            start: self.wavelengths.first().copied().unwrap_or(0.0) - 0.5 * self.step,
            step: self.step,
            count: n,
        };
        let list: Vec<AnyChannel<FlatSamples>> = (0..n)
            .map(|k| {
                let vals = self
                    .values
                    .iter()
                    .skip(k)
                    .step_by(n)
                    .map(|&v| v as f32)
                    .collect();
                AnyChannel::new(bins.channel_name(k).as_str(), FlatSamples::F32(vals))
            })
            .collect();
        let mut attributes = LayerAttributes::named("");
        for (k, v) in [
            ("spectralLayoutVersion", "1.0"),
            ("emissiveUnits", "W.m^-2.sr^-1"),
        ] {
            attributes
                .other
                .insert(Text::from(k), AttributeValue::Text(Text::from(v)));
        }
        let layer = Layer::new(
            (self.width as usize, self.height as usize),
            attributes,
            Encoding {
                line_order: LineOrder::Increasing,
                ..Encoding::FAST_LOSSLESS
            },
            AnyChannels::sort(SmallVec::from_vec(list)),
        );
        Image::from_layer(layer)
            .write()
            .to_file(path)
            .map_err(|e| format!("cannot write spectral EXR {}: {e}", path.display()))
    }

    /// Read the emissive `S0.<λ>nm` channels of a spectral OpenEXR (first layer that has
    /// them), sorted by wavelength. The bins must be evenly spaced.
    pub fn read_exr(path: &Path) -> Result<Self, String> {
        use exr::prelude::*;
        let name = path.display();
        let image = read_all_flat_layers_from_file(path)
            .map_err(|e| format!("cannot read spectral EXR {name}: {e}"))?;
        for layer in &image.layer_data {
            let mut chans: Vec<(f64, &AnyChannel<FlatSamples>)> = Vec::new();
            for c in &layer.channel_data.list {
                let n = c.name.to_string();
                if let Some(l) = parse_channel(&n) {
                    chans.push((l, c));
                }
            }
            if chans.is_empty() {
                continue;
            }
            chans.sort_by(|a, b| a.0.total_cmp(&b.0));
            let wavelengths: Vec<f64> = chans.iter().map(|c| c.0).collect();
            let step = if wavelengths.len() > 1 {
                wavelengths[1] - wavelengths[0]
            } else {
                1.0
            };
            for w in wavelengths.windows(2) {
                if ((w[1] - w[0]) - step).abs() > 1e-3 * step {
                    return Err(format!(
                        "{name}: spectral channels are not evenly spaced ({} nm then {} nm apart)",
                        step,
                        w[1] - w[0]
                    ));
                }
            }
            let (w, h) = (layer.size.width(), layer.size.height());
            let n = wavelengths.len();
            let mut values = vec![0.0; w * h * n];
            for (k, (_, c)) in chans.iter().enumerate() {
                for (i, v) in c.sample_data.values_as_f32().enumerate() {
                    values[i * n + k] = v as f64;
                }
            }
            return Ok(Self {
                width: w as u32,
                height: h as u32,
                wavelengths,
                step,
                values,
            });
        }
        Err(format!(
            "{name}: no emissive spectral channels (S0.<λ>nm) found"
        ))
    }
}

/// The wavelength (nm) of an emissive channel name `S0.<λ>nm` (comma or dot as decimal
/// separator), or `None` for other channels.
pub fn parse_channel(name: &str) -> Option<f64> {
    let rest = name.strip_prefix("S0.")?.strip_suffix("nm")?;
    rest.replace(',', ".")
        .parse::<f64>()
        .ok()
        .filter(|l| l.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::CieObserverKind;
    use crate::film::Sensor;
    use crate::spectrum::SampledWavelengths;
    use std::sync::Arc;

    #[test]
    fn bins_parse_and_names() {
        let b = SpectralBins::parse("380:780:5").unwrap();
        assert_eq!(b.count, 80);
        assert_eq!(b.channel_name(0), "S0.382,500000nm");
        assert_eq!(parse_channel("S0.382,500000nm"), Some(382.5));
        assert_eq!(parse_channel("R"), None);
        assert_eq!(b.bin(380.0), Some(0));
        assert_eq!(b.bin(779.99), Some(79));
        assert_eq!(b.bin(780.0), None);
        for bad in ["380:780", "a:780:5", "780:380:5", "380:781:5", "380:780:0"] {
            assert!(SpectralBins::parse(bad).is_err(), "{bad}");
        }
    }

    /// The SAME samples integrated both ways: lanes placed at bin centres, so the midpoint-rule
    /// XYZ of the bins uses x̄ȳz̄ at exactly the lanes' wavelengths and must equal the sensor's
    /// XYZ of those samples up to f64/f32 rounding (tolerance 1e-6 relative: values are stored
    /// as f32 in the EXR round trip, ~6e-8 each). Also checks the EXR round trip.
    #[test]
    fn xyz_of_bins_matches_film_xyz_for_the_same_samples() {
        let obs = CieObserverKind::Cie1931_2.get();
        let sensor = Sensor::new(Arc::new(obs.clone()));
        let bins = SpectralBins::parse("380:780:5").unwrap();
        let film = SpectralFilm::new(bins, 2, 1);
        let mut film_xyz = [0.0f64; 3];
        let n = 50;
        for s in 0..n {
            let mut lambda = SampledWavelengths {
                lambda: [0.0; LANES],
                pdf: [0.0; LANES],
                lanes: crate::spectrum::LaneMask::ALL,
            };
            for i in 0..LANES {
                lambda.lambda[i] = bins.center((s * 7 + i * 19) % bins.count) as f32;
                lambda.pdf[i] = 1.0 / 400.0 + 1e-4 * i as f32;
            }
            let l = SampledSpectrum([0.3, 1.7, 0.05, 2.0].map(|v| v * (1.0 + s as f32 * 0.01)));
            let xyz = sensor.to_xyz(&(l * 0.9), &lambda);
            film.add(0, 0, &[l], &[lambda], 0.9, &xyz);
            for c in 0..3 {
                film_xyz[c] += xyz[c] / n as f64;
            }
        }
        let img = film.image();
        let dir = std::env::temp_dir().join(format!("spectrace-spectral-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.exr");
        img.write_exr(&p).unwrap();
        let back = SpectralImage::read_exr(&p).unwrap();
        assert_eq!(back.wavelengths, img.wavelengths);
        let xyz = back.to_xyz(obs);
        for c in 0..3 {
            let rel = (xyz[0][c] - film_xyz[c]).abs() / film_xyz[c];
            assert!(
                rel < 1e-6,
                "channel {c}: {} vs {} ({rel})",
                xyz[0][c],
                film_xyz[c]
            );
        }
        assert_eq!(xyz[1], [0.0; 3]);
        assert!(SpectralImage::read_exr(&dir.join("missing.exr")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
