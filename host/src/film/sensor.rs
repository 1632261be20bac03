//! Turns one spectral radiance sample into an XYZ estimate with the scene's observer.

use crate::color::Observer;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use std::sync::Arc;

/// The observer plus the normalisation `1/∫ȳ dλ` of the film convention. The colour-matching
/// functions are copied onto a 1 nm grid starting at the observer's first wavelength so the
/// per-sample lookup is one index and one lerp (exact for the CIE tables, which are 1 nm data;
/// other observers are linearly resampled).
#[derive(Clone, Debug)]
pub struct Sensor {
    observer: Arc<dyn Observer>,
    inv_integral_y: f64,
    start: f64,
    table: Vec<[f64; 3]>,
}

impl Sensor {
    /// A sensor with the given colour-matching functions.
    pub fn new(observer: Arc<dyn Observer>) -> Self {
        let iy = observer.integral_y();
        let (lo, hi) = observer.range();
        let start = lo.floor();
        let n = if hi.is_finite() && hi >= start {
            ((hi.ceil() - start) as usize + 1).min(100_000)
        } else {
            0
        };
        let table = (0..n).map(|i| observer.xyz_bar(start + i as f64)).collect();
        Self {
            observer,
            inv_integral_y: if iy > 0.0 { 1.0 / iy } else { 0.0 },
            start,
            table,
        }
    }

    /// `[x̄, ȳ, z̄]` at `lambda_nm` from the 1 nm copy (0 outside).
    #[inline]
    fn xyz_bar(&self, lambda_nm: f64) -> [f64; 3] {
        let x = lambda_nm - self.start;
        if !(x >= 0.0) || self.table.len() < 2 {
            return [0.0; 3];
        }
        // Through `i32` (one truncating conversion; `as usize` from f64 costs about fifteen
        // instructions): the same floor for x < 2³¹, and beyond it i32::MAX, which is past the
        // table's end as any larger index would be.
        let i = x as i32 as usize;
        if i + 1 >= self.table.len() {
            return if i + 1 == self.table.len() && x == i as f64 {
                self.table[i]
            } else {
                [0.0; 3]
            };
        }
        let t = x - i as f64;
        let (a, b) = (self.table[i], self.table[i + 1]);
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]),
            a[2] + t * (b[2] - a[2]),
        ]
    }

    /// The observer.
    pub fn observer(&self) -> &Arc<dyn Observer> {
        &self.observer
    }

    /// Monte Carlo estimate of `∫ L x̄ȳz̄ dλ / ∫ȳ dλ` from one path: the mean over lanes of
    /// `L(λᵢ)·x̄ȳz̄(λᵢ)/pdf(λᵢ)`. Lanes outside `lambda.lanes` (terminated by dispersion) and
    /// lanes with pdf 0 contribute nothing; the hero's pdf already accounts for that
    /// (`terminate_secondary`).
    #[inline]
    pub fn to_xyz(&self, l: &SampledSpectrum, lambda: &SampledWavelengths) -> [f64; 3] {
        let mut xyz = [0.0f64; 3];
        for i in 0..LANES {
            let p = lambda.pdf[i];
            if p == 0.0 || l.0[i] == 0.0 || !lambda.lanes.contains(i) {
                continue;
            }
            let w = l.0[i] as f64 / p as f64;
            let bar = self.xyz_bar(lambda.lambda[i] as f64);
            xyz[0] += w * bar[0];
            xyz[1] += w * bar[1];
            xyz[2] += w * bar[2];
        }
        let s = self.inv_integral_y / LANES as f64;
        [xyz[0] * s, xyz[1] * s, xyz[2] * s]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::CieObserverKind;

    /// A spectrally constant radiance of 1 gives Y = 1 (the film convention). With uniform
    /// wavelength sampling over the observer range and 4·10⁴ stratified hero samples the MC error
    /// of Y is < 1e-3; tolerance 2e-3.
    #[test]
    fn constant_radiance_gives_unit_y() {
        let obs: Arc<dyn Observer> = Arc::new(CieObserverKind::Cie1931_2.get().clone());
        let s = Sensor::new(obs);
        let n = 40_000;
        let mut y = 0.0;
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let lambda = SampledWavelengths::sample_visible(u);
            y += s.to_xyz(&SampledSpectrum::splat(1.0), &lambda)[1];
        }
        y /= n as f64;
        assert!((y - 1.0).abs() < 2e-3, "{y}");
    }

    /// The 1 nm copy reproduces the observer exactly at and between CIE table nodes (1e-12).
    #[test]
    fn dense_copy_matches_observer() {
        let obs: Arc<dyn Observer> = Arc::new(CieObserverKind::Cie1931_2.get().clone());
        let s = Sensor::new(obs.clone());
        for k in 0..5000 {
            let l = 355.0 + k as f64 * 0.0951;
            let (a, b) = (s.xyz_bar(l), obs.xyz_bar(l));
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-12, "{l}: {a:?} vs {b:?}");
            }
        }
    }
}
