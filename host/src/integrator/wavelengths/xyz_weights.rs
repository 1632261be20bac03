//! Per-lane factors that turn a spectral sample into film XYZ, shared by the drivers that
//! splat (BDPT, light tracing).

use crate::film::spectral_film::LaneEnergies;
use crate::film::Sensor;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};

/// Per-lane factors turning a spectral sample into film XYZ (`x̄ȳz̄(λ)/(pdf(λ)·LANES·∫ȳ)`), for
/// all lanes and for the hero alone (after a dispersive event: pdf/LANES, see
/// `SampledWavelengths::terminate_secondary`).
#[derive(Clone, Copy, Debug)]
pub struct XyzWeights {
    full: [[f64; 3]; LANES],
    hero: [f64; 3],
    /// `1/(pdf·LANES)` per lane (0 where pdf is 0), for the spectral film.
    inv_pdf: [f64; LANES],
    lambda: [f32; LANES],
}

impl XyzWeights {
    /// Factors for `lambda` under `sensor`'s observer.
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn new(sensor: &Sensor, lambda: &SampledWavelengths) -> Self {
        let iy = sensor.observer().integral_y();
        let inv_iy = if iy > 0.0 { 1.0 / iy } else { 0.0 };
        let mut full = [[0.0; 3]; LANES];
        let mut hero = [0.0; 3];
        let mut inv_pdf = [0.0; LANES];
        for i in 0..LANES {
            let p = lambda.pdf[i] as f64;
            if p > 0.0 {
                inv_pdf[i] = 1.0 / (p * LANES as f64);
                let bar = sensor.observer().xyz_bar(lambda.lambda[i] as f64);
                full[i] = bar.map(|b| b * inv_iy / (p * LANES as f64));
                if i == 0 {
                    hero = bar.map(|b| b * inv_iy / p);
                }
            }
        }
        Self {
            full,
            hero,
            inv_pdf,
            lambda: lambda.lambda,
        }
    }

    /// The lanes of spectral sample `l` for the spectral film: the terms [`xyz`](Self::xyz)
    /// sums, without the colour-matching functions (`e = L/(pdf·LANES)·LANES/|live|`, the hero
    /// alone `L/pdf`).
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn energies(&self, l: &SampledSpectrum, lanes: LaneMask) -> LaneEnergies {
        let mut out = LaneEnergies {
            lambda: self.lambda,
            e: [0.0; LANES],
        };
        if lanes == LaneMask::HERO {
            out.e[0] = l.0[0] as f64 * self.inv_pdf[0] * LANES as f64;
            return out;
        }
        let live = lanes.count();
        if live == 0 {
            return out;
        }
        let scale = LANES as f64 / live as f64;
        for i in 0..LANES {
            let v = l.0[i] as f64;
            if v != 0.0 && lanes.contains(i) {
                out.e[i] = v * self.inv_pdf[i] * scale;
            }
        }
        out
    }

    /// XYZ of spectral sample `l` whose valid lanes are `lanes` (the mask its subpath
    /// vertices carry): the mean over the live lanes of `L(λᵢ)·x̄ȳz̄(λᵢ)/pdf(λᵢ)`, each live
    /// lane an unbiased estimate on its own (every lane is marginally drawn with its pdf).
    #[inline]
    #[allow(clippy::needless_range_loop)] // lanes index several arrays at once
    pub fn xyz(&self, l: &SampledSpectrum, lanes: LaneMask) -> [f64; 3] {
        if lanes == LaneMask::HERO {
            let v = l.0[0] as f64;
            return if v == 0.0 {
                [0.0; 3]
            } else {
                self.hero.map(|h| h * v)
            };
        }
        // LANES/|live|: 1 for a full mask (skipped so the sum is the plain one).
        let live = lanes.count();
        let scale = if live == 0 {
            return [0.0; 3];
        } else {
            LANES as f64 / live as f64
        };
        let mut out = [0.0; 3];
        for i in 0..LANES {
            let v = l.0[i] as f64;
            if v != 0.0 && lanes.contains(i) {
                for c in 0..3 {
                    out[c] += self.full[i][c] * v;
                }
            }
        }
        if !lanes.is_all() {
            out = out.map(|x| x * scale);
        }
        out
    }
}
