//! The colour half of a beam-representation adapter: a beam's RGB colour becomes a wavelength
//! and a power, flux preserved.
//!
//! The colour is uplifted to a smooth spectrum `S(λ)` by the same RGB uplift materials use
//! ([`uplift_srgb`], Jakob & Hanika 2019; the colour is first scaled so its largest component is
//! 1, since only its chromaticity matters). Normalised over the uplift range, `p(λ) =
//! S(λ)/∫S` is the beam's spectral distribution: a beam of flux estimate Φ (W) stands for the
//! spectral flux `Φ·p(λ)`. The wavelength is drawn from a 1 nm histogram `q` of `S` (exact CDF
//! inversion) and the power becomes `Φ·p(λ)/q(λ)`, so `E[power·δ(λ − λ')] = Φ·p(λ')` exactly,
//! whatever the histogram's error: the weight `p/q` stays within a fraction of a percent of 1.

use crate::color::uplift::{uplift_srgb, SigmoidPolynomial, UPLIFT_RANGE};
use crate::spectrum::piecewise_constant::PiecewiseConstant1D;
use std::sync::{Arc, RwLock};

/// Histogram bin width for sampling the uplifted spectrum, nm.
const BIN_NM: f64 = 1.0;
/// Sub-steps per bin of the midpoint rule that normalises `S` (error ~1e-9 relative for these
/// smooth spectra).
const NORM_STEPS_PER_BIN: usize = 16;
/// Colours remembered per light (a light usually has one or a few).
const CACHE_COLOURS: usize = 64;

/// One colour's uplifted spectrum, normalised, with its sampling histogram.
#[derive(Debug)]
pub struct RgbSpectrum {
    poly: SigmoidPolynomial,
    norm: f64,
    histogram: PiecewiseConstant1D,
}

impl RgbSpectrum {
    /// The spectrum of linear-sRGB `rgb` (finite, ≥ 0, not all 0); `None` otherwise.
    pub fn new(rgb: [f64; 3]) -> Option<Self> {
        let max = rgb.iter().copied().fold(0.0, f64::max);
        if !(rgb.iter().all(|c| c.is_finite() && *c >= 0.0) && max > 0.0) {
            return None;
        }
        let poly = uplift_srgb(rgb.map(|c| c / max));
        let (lo, hi) = UPLIFT_RANGE;
        let bins = ((hi - lo) / BIN_NM).round() as usize;
        let edges: Vec<f64> = (0..=bins).map(|i| lo + i as f64 * BIN_NM).collect();
        let values: Vec<f64> = edges
            .windows(2)
            .map(|w| poly.value(0.5 * (w[0] + w[1])))
            .collect();
        let h = BIN_NM / NORM_STEPS_PER_BIN as f64;
        let norm: f64 = (0..bins * NORM_STEPS_PER_BIN)
            .map(|k| poly.value(lo + (k as f64 + 0.5) * h) * h)
            .sum();
        let histogram = PiecewiseConstant1D::new(&edges, &values)?;
        (norm.is_finite() && norm > 0.0).then_some(Self {
            poly,
            norm,
            histogram,
        })
    }

    /// The normalised spectral distribution `p(λ)`, 1/nm (0 outside the uplift range).
    pub fn pdf(&self, lambda_nm: f64) -> f64 {
        let (lo, hi) = UPLIFT_RANGE;
        if !(lo..=hi).contains(&lambda_nm) {
            return 0.0;
        }
        self.poly.value(lambda_nm) / self.norm
    }

    /// Draw a wavelength with `u ∈ [0,1)`: `(λ nm, weight p(λ)/q(λ))`; the beam's power is
    /// multiplied by the weight.
    pub fn sample(&self, u: f64) -> (f64, f64) {
        let (lambda, q) = self.histogram.sample(u);
        (lambda, self.pdf(lambda) / q)
    }
}

/// Per-light cache of uplifted colours: fitting one costs ~100 µs, a beam must cost far less.
#[derive(Debug, Default)]
pub struct ColourCache {
    entries: RwLock<Vec<([u64; 3], Arc<RgbSpectrum>)>>,
}

impl ColourCache {
    /// The spectrum of `rgb`, fitted once per distinct colour (the first
    /// [`CACHE_COLOURS`] are kept; beyond, each call fits anew: correct, only slower).
    pub fn get(&self, rgb: [f64; 3]) -> Option<Arc<RgbSpectrum>> {
        let key = rgb.map(f64::to_bits);
        if let Ok(e) = self.entries.read() {
            if let Some((_, s)) = e.iter().find(|(k, _)| *k == key) {
                return Some(s.clone());
            }
        }
        let s = Arc::new(RgbSpectrum::new(rgb)?);
        if let Ok(mut e) = self.entries.write() {
            if e.len() < CACHE_COLOURS && !e.iter().any(|(k, _)| *k == key) {
                e.push((key, s.clone()));
            }
        }
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The uplift is the materials' one: the normalised distribution is S(λ)/∫S with S the very
    // polynomial `uplift_srgb` fits for the max-scaled colour (1e-12 relative: same arithmetic).
    #[test]
    fn the_spectrum_is_the_material_uplift_normalised() {
        let rgb = [0.8, 0.4, 0.1];
        let s = RgbSpectrum::new(rgb).unwrap();
        let poly = uplift_srgb([1.0, 0.5, 0.125]);
        let ratio = s.pdf(500.0) / poly.value(500.0);
        for l in [400.0, 550.0, 700.0] {
            assert!(((s.pdf(l) / poly.value(l)) / ratio - 1.0).abs() < 1e-12);
        }
        // ∫p = 1 by a finer independent midpoint rule (0.01 nm): 1e-6.
        let n = 47_000;
        let h = (UPLIFT_RANGE.1 - UPLIFT_RANGE.0) / n as f64;
        let total: f64 = (0..n)
            .map(|k| s.pdf(UPLIFT_RANGE.0 + (k as f64 + 0.5) * h) * h)
            .sum();
        assert!((total - 1.0).abs() < 1e-6, "∫p = {total}");
        // The scale of the colour does not matter; grey is flat.
        let t = RgbSpectrum::new([8.0, 4.0, 1.0]).unwrap();
        assert!((t.pdf(600.0) / s.pdf(600.0) - 1.0).abs() < 1e-12);
        let g = RgbSpectrum::new([0.3, 0.3, 0.3]).unwrap();
        assert!((g.pdf(400.0) * (UPLIFT_RANGE.1 - UPLIFT_RANGE.0) - 1.0).abs() < 1e-9);
        for bad in [[0.0; 3], [-1.0, 1.0, 1.0], [f64::NAN, 1.0, 1.0]] {
            assert!(RgbSpectrum::new(bad).is_none());
        }
    }

    // Flux preserved: with λ drawn by `sample` and power multiplied by the weight, the expected
    // power falling in each 10 nm band equals Φ·∫_band p. Estimated with 200 000 stratified
    // draws (u = (k + ½)/N): the stratified estimate's error is far below the 1e-3 tolerance
    // (bands hold ≥ ~4000 draws, weight ≈ 1 ± 0.3%), and the weight p/q itself must stay
    // within 1% of 1 (the histogram is 1 nm wide on a smooth spectrum).
    #[test]
    fn sampling_preserves_the_flux_per_wavelength() {
        let s = RgbSpectrum::new([1.0, 0.6, 0.25]).unwrap();
        let n = 200_000;
        let phi = 3.0;
        let bands = 47;
        let mut got = vec![0.0; bands];
        let mut total = 0.0;
        for k in 0..n {
            let (l, w) = s.sample((k as f64 + 0.5) / n as f64);
            assert!((w - 1.0).abs() < 0.01, "weight {w} at {l} nm");
            let b = (((l - UPLIFT_RANGE.0) / 10.0) as usize).min(bands - 1);
            got[b] += phi * w / n as f64;
            total += phi * w / n as f64;
        }
        assert!((total / phi - 1.0).abs() < 1e-3, "total {total}");
        for (b, g) in got.iter().enumerate() {
            let lo = UPLIFT_RANGE.0 + 10.0 * b as f64;
            let want: f64 = (0..1000)
                .map(|i| s.pdf(lo + (i as f64 + 0.5) * 0.01) * 0.01)
                .sum::<f64>()
                * phi;
            assert!(
                (g - want).abs() < 1e-3 * want.max(phi / bands as f64),
                "band {lo} nm: {g} vs {want}"
            );
        }
    }

    // The cache returns the same fit for the same colour and fits a different colour anew.
    #[test]
    fn the_cache_fits_each_colour_once() {
        let c = ColourCache::default();
        let a = c.get([1.0, 0.5, 0.2]).unwrap();
        let b = c.get([1.0, 0.5, 0.2]).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        let d = c.get([0.2, 0.5, 1.0]).unwrap();
        assert!(!Arc::ptr_eq(&a, &d));
        assert!(c.get([0.0; 3]).is_none());
    }
}
