//! Per-lane factors that turn a spectral sample into film XYZ, shared by the drivers that
//! splat (BDPT, light tracing).

use crate::film::Sensor;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};

/// Per-lane factors turning a spectral sample into film XYZ (`x̄ȳz̄(λ)/(pdf(λ)·LANES·∫ȳ)`), for
/// all lanes and for the hero alone (after a dispersive event: pdf/LANES, see
/// `SampledWavelengths::terminate_secondary`).
#[derive(Clone, Copy, Debug)]
pub struct XyzWeights {
    full: [[f64; 3]; LANES],
    hero: [f64; 3],
}

impl XyzWeights {
    /// Factors for `lambda` under `sensor`'s observer.
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn new(sensor: &Sensor, lambda: &SampledWavelengths) -> Self {
        let iy = sensor.observer().integral_y();
        let inv_iy = if iy > 0.0 { 1.0 / iy } else { 0.0 };
        let mut full = [[0.0; 3]; LANES];
        let mut hero = [0.0; 3];
        for i in 0..LANES {
            let p = lambda.pdf[i] as f64;
            if p > 0.0 {
                let bar = sensor.observer().xyz_bar(lambda.lambda[i] as f64);
                full[i] = bar.map(|b| b * inv_iy / (p * LANES as f64));
                if i == 0 {
                    hero = bar.map(|b| b * inv_iy / p);
                }
            }
        }
        Self { full, hero }
    }

    /// XYZ of spectral sample `l`; `hero_only` after a dispersive event.
    #[inline]
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn xyz(&self, l: &SampledSpectrum, hero_only: bool) -> [f64; 3] {
        if hero_only {
            let v = l.0[0] as f64;
            return if v == 0.0 {
                [0.0; 3]
            } else {
                self.hero.map(|h| h * v)
            };
        }
        let mut out = [0.0; 3];
        for i in 0..LANES {
            let v = l.0[i] as f64;
            if v != 0.0 {
                for c in 0..3 {
                    out[c] += self.full[i][c] * v;
                }
            }
        }
        out
    }
}
