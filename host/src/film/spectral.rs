//! Spectral output: the wavelength nodes of a spectral image ([`SpectralBins`]) and the image
//! itself ([`SpectralImage`]), written and read as OpenEXR in the layout of Fichet, Pacanowski
//! and Wilkie 2021 ("An OpenEXR Layout for Spectral Images", JCGT 10(3)). The exact sums behind
//! it are in [`super::spectral_film`].
//!
//! | parameter | meaning |
//! |---|---|
//! | `start`, `end` (nm) | first and last node; samples outside `[start, end]` are left out |
//! | `step` (nm) | node spacing Δ; CLI `--bins START:END:STEP`, default `380:780:5` (81 nodes) |
//!
//! # The rule (what a channel holds and how to integrate it)
//!
//! Every lane of a film sample carries `e` (W/(m²·sr)): its share of the pixel's
//! radiance integral at wavelength λ, such that its share of the film's XYZ is
//! `e·x̄ȳz̄(λ)/∫ȳ`. The lane is split between the two nodes around λ with linear (tent) weights
//! `1 − t` and `t`, `t = (λ − λₖ)/Δ`. Channel `k` holds
//!
//! `Sₖ = Σ e·wₖ(λ) / (N·hₖ)`  [W/(m²·sr·nm)],
//!
//! with `N` the samples per pixel and `hₖ` the integral of node k's tent inside the range: `Δ`,
//! or `Δ/2` at the two end nodes. `Sₖ` estimates the spectral radiance at `λₖ` smoothed by the
//! tent. The matching integration rule is the trapezoid rule on the nodes:
//!
//! `XYZ = Σₖ Sₖ·x̄ȳz̄(λₖ)·hₖ / ∫ȳ`   (∫ȳ: the observer's Σ ȳ over its 1 nm grid)
//!
//! Because `Σₖ wₖ(λ)·x̄(λₖ)` is x̄ interpolated linearly between nodes, this gives the film's XYZ
//! to rounding whenever the observer is linear between nodes. The CIE observers are tables
//! every 1 nm read linearly between entries, so nodes every 1 nm on whole nm that cover the
//! observer's range (`--bins 360:830:1` for CIE) reproduce the film's XYZ exactly (to f32
//! rounding in the file). A coarser grid differs by the linear interpolation of x̄ȳz̄ between
//! its nodes (about 2e-4 at 5 nm over 380–780 nm on the test scenes), a narrower range by the
//! light outside it; `render` prints both integrals.
//!
//! Channels are `S0.<λ>nm` with λ the node printed with six decimals and a comma as decimal
//! separator (e.g. `S0.382,500000nm`); header attributes `spectralLayoutVersion = "1.0"`,
//! `emissiveUnits = "W.m^-2.sr^-1"` (values are densities per nm, as pbrt-v4 writes them), and
//! the rule above in one line in the standard `comments` attribute.

use crate::color::Observer;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The rule, as written into the EXR header (`comments`).
pub const RULE: &str = "spectrace spectral nodes: S_k = tent-weighted spectral radiance at node k (W m^-2 sr^-1 nm^-1); \
                        XYZ = sum_k S_k xyzbar(lambda_k) h_k / sum_1nm ybar, h_k = step \
                        (step/2 at the end nodes): the trapezoid rule";

/// Wavelength nodes of a spectral image, in nm: `start + k·step` for `k < count`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpectralBins {
    /// The first node (nm).
    pub start: f64,
    /// Node spacing Δ (nm).
    pub step: f64,
    /// Number of nodes (≥ 2).
    pub count: usize,
}

impl SpectralBins {
    /// Parse `START:END:STEP` in nm (e.g. `380:780:5`: nodes 380, 385, …, 780); END − START
    /// must be a whole number of steps.
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
        let intervals = n.round() as usize;
        if (n - intervals as f64).abs() > 1e-6 || intervals == 0 {
            return Err(bad("END − START must be a whole number of steps"));
        }
        if intervals >= 4096 {
            return Err(bad("more than 4096 nodes"));
        }
        Ok(Self {
            start: a,
            step: d,
            count: intervals + 1,
        })
    }

    /// Node `k` (nm).
    pub fn node(&self, k: usize) -> f64 {
        self.start + k as f64 * self.step
    }

    /// The last node (nm).
    pub fn end(&self) -> f64 {
        self.node(self.count - 1)
    }

    /// The node below `lambda_nm` and the tent weight `t` of the node above it (the node below
    /// gets `1 − t`); `None` outside `[start, end]`.
    #[inline]
    pub fn tent(&self, lambda_nm: f64) -> Option<(usize, f64)> {
        let x = (lambda_nm - self.start) / self.step;
        let last = (self.count - 1) as f64;
        if !(x >= 0.0 && x <= last) {
            return None;
        }
        let k = (x.floor() as usize).min(self.count - 2);
        Some((k, x - k as f64))
    }

    /// `hₖ`: the integral (nm) of node k's tent inside the range (Δ, Δ/2 at the ends).
    pub fn weight(&self, k: usize) -> f64 {
        if k == 0 || k + 1 == self.count {
            0.5 * self.step
        } else {
            self.step
        }
    }

    /// The layout's channel name for node `k`.
    pub fn channel_name(&self, k: usize) -> String {
        channel_name(self.node(k))
    }

    /// `START:END:STEP`, as `--bins` takes it.
    pub fn spec(&self) -> String {
        format!("{}:{}:{}", self.start, self.end(), self.step)
    }
}

/// The layout's channel name for wavelength `lambda_nm`: `S0.<λ>nm`, six decimals, comma as
/// decimal separator.
pub fn channel_name(lambda_nm: f64) -> String {
    format!("S0.{:.6}nm", lambda_nm)
        .replace('.', ",")
        .replacen("S0,", "S0.", 1)
}

/// A spectral image: per pixel, spectral radiance at `wavelengths` (nodes, nm) in
/// W/(m²·sr·nm), `step` nm apart.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Nodes (nm), increasing, evenly spaced.
    pub wavelengths: Vec<f64>,
    /// Node spacing (nm).
    pub step: f64,
    /// Row-major pixels, nodes innermost.
    pub values: Vec<f64>,
}

impl SpectralImage {
    /// Per-pixel XYZ under the film convention `∫L·x̄ȳz̄ dλ / ∫ȳ dλ` by the trapezoid rule on
    /// the nodes (see the module docs): exact against the film when the observer is linear
    /// between nodes.
    pub fn to_xyz(&self, observer: &dyn Observer) -> Vec<[f64; 3]> {
        let iy = observer.integral_y();
        let inv = if iy > 0.0 { 1.0 / iy } else { 0.0 };
        let n = self.wavelengths.len();
        let bars: Vec<[f64; 3]> = self
            .wavelengths
            .iter()
            .enumerate()
            .map(|(k, &l)| {
                let h = if k == 0 || k + 1 == n {
                    0.5 * self.step
                } else {
                    self.step
                };
                observer.xyz_bar(l).map(|b| b * h * inv)
            })
            .collect();
        self.values
            .chunks(n.max(1))
            .map(|px| {
                let mut xyz = [0.0; 3];
                for (v, b) in px.iter().zip(&bars) {
                    for c in 0..3 {
                        xyz[c] += v * b[c];
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
        let list: Vec<AnyChannel<FlatSamples>> = (0..n)
            .map(|k| {
                let vals = self
                    .values
                    .iter()
                    .skip(k)
                    .step_by(n)
                    .map(|&v| v as f32)
                    .collect();
                AnyChannel::new(
                    channel_name(self.wavelengths[k]).as_str(),
                    FlatSamples::F32(vals),
                )
            })
            .collect();
        // The exr crate keeps custom attributes in a std HashMap, written in its (randomly
        // seeded) iteration order: one custom attribute per map keeps the file bytes the same
        // for the same pixels. The rule goes into the standard `comments` attribute.
        let mut attributes = LayerAttributes::named("");
        attributes.other.insert(
            Text::from("emissiveUnits"),
            AttributeValue::Text(Text::from("W.m^-2.sr^-1")),
        );
        attributes.comments = Some(Text::from(RULE));
        attributes.software_name = Some(Text::from("spectrace"));
        let layer = Layer::new(
            (self.width as usize, self.height as usize),
            attributes,
            Encoding {
                line_order: LineOrder::Increasing,
                ..Encoding::FAST_LOSSLESS
            },
            AnyChannels::sort(SmallVec::from_vec(list)),
        );
        let mut image = Image::from_layer(layer);
        image.attributes.other.insert(
            Text::from("spectralLayoutVersion"),
            AttributeValue::Text(Text::from("1.0")),
        );
        image
            .write()
            .to_file(path)
            .map_err(|e| format!("cannot write spectral EXR {}: {e}", path.display()))
    }

    /// Read the emissive `S0.<λ>nm` channels of a spectral OpenEXR (first layer that has
    /// them), sorted by wavelength. The channels must be evenly spaced.
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
