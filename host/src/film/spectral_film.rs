//! The spectral film: per pixel and wavelength node, exact sums ([`ExactSum`]) of the samples'
//! tent-weighted lane values (the rule is in [`super::spectral`]). Exact sums are
//! order-independent, so camera samples and splats from any thread, pass, slice or resumed run
//! give the same bits; the sums travel in the film state ([`SpectralSums`], part of
//! [`super::FilmState`]) and merge like the XYZ film.
//!
//! | type | role |
//! |---|---|
//! | [`LaneEnergies`] | one sample's lanes: wavelength (nm) and `e` (W/(m²·sr)) each |
//! | [`SpectralFilm`] | thread-safe accumulator of one pass (a lock per pixel) |
//! | [`SpectralSums`] | the accumulated sums of whole passes, serialised in state files |
//!
//! Memory: 32 bytes per node and pixel for the sums, and as much again for the pixels a pass
//! has touched (the pass accumulator, emptied into the sums when the pass completes, so an
//! interrupted pass is dropped exactly like the XYZ film's). 81 nodes (the default 380:780:5)
//! cost about 5 KB per pixel, 471 nodes (360:830:1) about 30 KB.
//!
//! A sample enters only if the XYZ film accepted it ([`check_sample`] of its XYZ) and all its
//! lane values are finite and non-negative (a lane the film's XYZ guard let through but that is
//! negative on its own is a broken material or light; the whole sample is left out here).

use super::exact_sum::ExactSum;
use super::rejected::check_sample;
use super::spectral::{SpectralBins, SpectralImage};
use crate::spectrum::LANES;
use serde::{Deserialize, Serialize};
use std::sync::Mutex;

/// One sample's lanes: wavelength `lambda` (nm) and `e` (W/(m²·sr)), its share of the pixel's
/// radiance integral, such that its share of the film's XYZ is `e·x̄ȳz̄(λ)/∫ȳ`. Lanes with
/// `e = 0` contribute nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LaneEnergies {
    /// Wavelength of each lane (nm).
    pub lambda: [f32; LANES],
    /// Value of each lane (W/(m²·sr)).
    pub e: [f64; LANES],
}

impl LaneEnergies {
    /// A single wavelength carrying `e` (a beam).
    pub fn single(lambda_nm: f32, e: f64) -> Self {
        let mut out = Self {
            lambda: [lambda_nm; LANES],
            e: [0.0; LANES],
        };
        out.e[0] = e;
        out
    }

    /// Add `other`'s values lane by lane (the same wavelengths: strategies of one sample).
    #[inline]
    pub fn accumulate(&mut self, other: &LaneEnergies) {
        self.lambda = other.lambda;
        for i in 0..LANES {
            self.e[i] += other.e[i];
        }
    }

    fn valid(&self) -> bool {
        self.e.iter().all(|v| v.is_finite() && *v >= 0.0)
    }
}

/// Exact per-pixel, per-node sums of `e·w` of whole passes (row-major pixels, nodes innermost).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpectralSums {
    /// The wavelength nodes.
    pub bins: SpectralBins,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width·height·bins.count` sums.
    pub sums: Vec<ExactSum>,
}

impl SpectralSums {
    /// Empty sums.
    pub fn new(bins: SpectralBins, width: u32, height: u32) -> Self {
        Self {
            bins,
            width,
            height,
            sums: vec![ExactSum::default(); width as usize * height as usize * bins.count],
        }
    }

    /// Add another film's sums (same size and nodes: checked by the caller, see
    /// [`Self::compatible`]).
    pub fn merge(&mut self, other: &SpectralSums) {
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            a.merge(b);
        }
    }

    /// Why `other` cannot be merged into these sums, if it cannot.
    pub fn compatible(&self, other: &SpectralSums) -> Result<(), String> {
        if self.bins != other.bins {
            return Err(format!(
                "spectral nodes {} here, {} there",
                self.bins.spec(),
                other.bins.spec()
            ));
        }
        if (self.width, self.height) != (other.width, other.height) {
            return Err(format!(
                "spectral film {}×{} here, {}×{} there",
                self.width, self.height, other.width, other.height
            ));
        }
        Ok(())
    }

    /// Internal consistency (for state files).
    pub fn validate(&self) -> Result<(), String> {
        if self.bins.count < 2 || !(self.bins.step > 0.0) {
            return Err(format!("spectral nodes {:?} are not valid", self.bins));
        }
        if self.sums.len() != self.width as usize * self.height as usize * self.bins.count {
            return Err(format!(
                "spectral sums ({}) do not match {}×{} pixels of {} nodes",
                self.sums.len(),
                self.width,
                self.height,
                self.bins.count
            ));
        }
        Ok(())
    }

    /// The spectral image of `spp` samples per pixel: `Sₖ = sum/(spp·hₖ)`.
    pub fn image(&self, spp: u64) -> SpectralImage {
        let n = self.bins.count;
        let scale: Vec<f64> = (0..n)
            .map(|k| 1.0 / (spp.max(1) as f64 * self.bins.weight(k)))
            .collect();
        SpectralImage {
            width: self.width,
            height: self.height,
            wavelengths: (0..n).map(|k| self.bins.node(k)).collect(),
            step: self.bins.step,
            values: self
                .sums
                .iter()
                .enumerate()
                .map(|(i, s)| s.value() * scale[i % n])
                .collect(),
        }
    }
}

/// Bytes per node and pixel a spectral render holds: the sums and the pass accumulator.
pub const BYTES_PER_NODE_AND_PIXEL: u64 = 2 * std::mem::size_of::<ExactSum>() as u64;

/// Refuse a spectral image whose sums would not fit in half of `available` bytes, naming what
/// would fit.
pub fn check_memory(
    bins: SpectralBins,
    width: u32,
    height: u32,
    available: u64,
) -> Result<(), String> {
    use crate::limits::human_bytes;
    let pixels = width as u64 * height as u64;
    let need = pixels
        .saturating_mul(bins.count as u64)
        .saturating_mul(BYTES_PER_NODE_AND_PIXEL);
    let limit = available / 2;
    if need > limit {
        let nodes = limit / (pixels.max(1) * BYTES_PER_NODE_AND_PIXEL);
        return Err(format!(
            "--spectral-exr with {} nodes ({}) on {width}×{height} pixels needs about {} for its \
             exact sums, more than the limit of {} (half the available memory of {}); use at \
             most {nodes} nodes (a larger --bins step) or a smaller image",
            bins.count,
            bins.spec(),
            human_bytes(need),
            human_bytes(limit),
            human_bytes(available)
        ));
    }
    Ok(())
}

/// Thread-safe accumulator of one pass: any thread adds camera samples or splats at any pixel.
#[derive(Debug)]
pub struct SpectralFilm {
    bins: SpectralBins,
    width: u32,
    height: u32,
    /// Per pixel the node sums, allocated when first touched.
    pixels: Vec<Mutex<Vec<ExactSum>>>,
}

impl SpectralFilm {
    /// An empty film of `width`×`height` pixels.
    pub fn new(bins: SpectralBins, width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            bins,
            width,
            height,
            pixels: (0..n).map(|_| Mutex::new(Vec::new())).collect(),
        }
    }

    /// The nodes.
    pub fn bins(&self) -> SpectralBins {
        self.bins
    }

    /// Add a camera sample of pixel (`x`, `y`): its wavelength groups' lanes; `film_xyz` is
    /// what the XYZ film got (a sample it refuses is left out here too).
    pub fn add(&self, x: u32, y: u32, film_xyz: &[f64; 3], groups: &[LaneEnergies]) {
        if x >= self.width || y >= self.height || check_sample(film_xyz).is_some() {
            return;
        }
        if !groups.iter().all(LaneEnergies::valid) {
            return;
        }
        let mut p = self.pixels[(y * self.width + x) as usize]
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        if p.is_empty() {
            *p = vec![ExactSum::default(); self.bins.count];
        }
        for g in groups {
            for i in 0..LANES {
                let e = g.e[i];
                if e == 0.0 {
                    continue;
                }
                if let Some((k, t)) = self.bins.tent(g.lambda[i] as f64) {
                    p[k].add(e * (1.0 - t));
                    p[k + 1].add(e * t);
                }
            }
        }
    }

    /// Add a splat at continuous raster position (`px`, `py`) in pixels (positions off the
    /// film are ignored, as the XYZ splat film does).
    pub fn splat(&self, px: f32, py: f32, film_xyz: &[f64; 3], lanes: &LaneEnergies) {
        if !(px >= 0.0 && py >= 0.0) {
            return;
        }
        self.add(px as u32, py as u32, film_xyz, std::slice::from_ref(lanes));
    }

    /// Move this pass's sums into `sums` (exact addition) and empty the film for the next pass.
    pub fn drain_into(&self, sums: &mut SpectralSums) {
        let n = self.bins.count;
        for (i, p) in self.pixels.iter().enumerate() {
            let mut p = p.lock().unwrap_or_else(|e| e.into_inner());
            if p.is_empty() {
                continue;
            }
            for (a, b) in sums.sums[i * n..(i + 1) * n].iter_mut().zip(p.iter_mut()) {
                if !b.is_zero() {
                    a.merge(b);
                    // Emptied in place: the next pass reuses the allocation.
                    *b = ExactSum::default();
                }
            }
        }
    }

    /// Empty the film (a pass that was dropped).
    pub fn clear(&self) {
        for p in &self.pixels {
            *p.lock().unwrap_or_else(|e| e.into_inner()) = Vec::new();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::CieObserverKind;
    use crate::film::Sensor;
    use crate::spectrum::{SampledSpectrum, SampledWavelengths};
    use std::sync::Arc;

    /// The SAME samples integrated both ways: random wavelengths anywhere in 360–830 nm (not at
    /// nodes), 1 nm nodes 360:830:1. The trapezoid-rule XYZ of the spectral image equals the
    /// sensor's XYZ of those samples up to rounding: tolerance 1e-6 relative (values are f32 in
    /// the EXR round trip, ~6e-8 each; the tent weights reproduce the 1 nm table's linear
    /// interpolation exactly). Also the EXR round trip and the layout's names.
    #[test]
    fn tent_rule_reproduces_film_xyz_for_the_same_samples() {
        let obs = CieObserverKind::Cie1931_2.get();
        let sensor = Sensor::new(Arc::new(obs.clone()));
        let bins = SpectralBins::parse("360:830:1").unwrap();
        assert_eq!(bins.count, 471);
        let film = SpectralFilm::new(bins, 2, 1);
        let mut sums = SpectralSums::new(bins, 2, 1);
        let mut film_xyz = [0.0f64; 3];
        let n = 200;
        let mut u = 0.123_f64;
        for s in 0..n {
            let mut lambda = SampledWavelengths {
                lambda: [0.0; LANES],
                pdf: [0.0; LANES],
                lanes: crate::spectrum::LaneMask::ALL,
            };
            for i in 0..LANES {
                u = (u * 997.0 + 0.271).fract();
                lambda.lambda[i] = (360.0 + 470.0 * u) as f32;
                lambda.pdf[i] = 1.0 / 470.0 + 1e-4 * i as f32;
            }
            let l = SampledSpectrum([0.3, 1.7, 0.05, 2.0].map(|v| v * (1.0 + s as f32 * 0.01)));
            let xyz = sensor.to_xyz(&(l * 0.9), &lambda);
            let mut e = LaneEnergies {
                lambda: lambda.lambda,
                e: [0.0; LANES],
            };
            for i in 0..LANES {
                e.e[i] = (l.0[i] * 0.9) as f64 / lambda.pdf[i] as f64 / LANES as f64;
            }
            film.add(0, 0, &xyz, &[e]);
            for c in 0..3 {
                film_xyz[c] += xyz[c] / n as f64;
            }
        }
        film.drain_into(&mut sums);
        let img = sums.image(n as u64);
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

    /// Node parsing and names; the tent splits a lane between its two nodes, and an end node
    /// divides by half a tent, so a flat spectrum (density 1/nm, 40,000 lanes on a 0.01 nm
    /// grid) reads 1 at every node, the ends included: tolerance 1e-3 (the tent integral of a
    /// midpoint grid is exact for a flat spectrum; f32 wavelengths move lanes by ≤ 3e-5 nm).
    #[test]
    fn nodes_parse_and_tents() {
        let b = SpectralBins::parse("380:780:5").unwrap();
        assert_eq!(b.count, 81);
        assert_eq!(b.channel_name(0), "S0.380,000000nm");
        assert_eq!(
            super::super::spectral::parse_channel("S0.382,500000nm"),
            Some(382.5)
        );
        assert_eq!(super::super::spectral::parse_channel("R"), None);
        assert_eq!(b.tent(380.0), Some((0, 0.0)));
        assert_eq!(b.tent(781.0), None);
        assert_eq!(b.tent(780.0), Some((79, 1.0)));
        assert_eq!(
            b.tent(383.0).map(|(k, t)| (k, (t * 10.0).round())),
            Some((0, 6.0))
        );
        for bad in ["380:780", "a:780:5", "780:380:5", "380:781:5", "380:780:0"] {
            assert!(SpectralBins::parse(bad).is_err(), "{bad}");
        }
        // A flat spectrum: e spread uniformly over 380–780 nm, density 1 per nm.
        let film = SpectralFilm::new(b, 1, 1);
        let mut sums = SpectralSums::new(b, 1, 1);
        let m = 40_000;
        for j in 0..m {
            let l = 380.0 + 400.0 * (j as f64 + 0.5) / m as f64;
            film.add(
                0,
                0,
                &[0.0; 3],
                &[LaneEnergies::single(l as f32, 400.0 / m as f64)],
            );
        }
        film.drain_into(&mut sums);
        let img = sums.image(1);
        assert!(check_memory(b, 256, 256, 1 << 30).is_ok());
        let e = check_memory(b, 4096, 4096, 1 << 30).unwrap_err();
        assert!(
            e.contains("81 nodes") && e.contains("at most 0 nodes"),
            "{e}"
        );
        for (k, v) in img.values.iter().enumerate() {
            assert!((v - 1.0).abs() < 1e-3, "node {k}: {v}");
        }
    }
}
