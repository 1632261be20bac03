//! Everything a render has accumulated: the camera film's exact sums and counts, the splat
//! film's exact sums, how many samples per pixel (light paths per pixel for light tracing) the
//! splats stand for, and the refused samples. Two states of disjoint sample ranges merge by
//! exact addition, so a render cut into slices or interrupted and resumed gives the same bits
//! as one uninterrupted run. When a spectral image is asked for, its exact sums
//! ([`SpectralSums`]) travel with the film and merge the same way.

use super::exact_sum::ExactSum;
use super::pixel_film::PixelFilm;
use super::rejected::{RejectedSamples, Rejection};
use super::spectral::SpectralImage;
use super::spectral_film::SpectralSums;
use super::XyzImage;
use serde::{Deserialize, Serialize};

/// The accumulated film of a render or of part of one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FilmState {
    /// Camera-driven estimates (path tracing, BDPT with t ≥ 2): sums and counts per pixel.
    pub camera: PixelFilm,
    /// Splatted estimates (light tracing, BDPT's t = 1), row-major; empty for path tracing.
    pub splats: Vec<[ExactSum; 3]>,
    /// Samples per pixel that the splat sums stand for (their divisor).
    pub spp: u64,
    /// Samples refused by the guard.
    pub rejected: RejectedSamples,
    /// Spectral sums (camera samples and splats together, divided by [`spp`](Self::spp)),
    /// when a spectral image is asked for.
    pub spectral: Option<SpectralSums>,
}

impl FilmState {
    /// An empty film; `splats` says whether it keeps splat sums.
    pub fn new(width: u32, height: u32, splats: bool) -> Self {
        let n = width as usize * height as usize;
        Self {
            camera: PixelFilm::new(width, height),
            splats: if splats {
                vec![Default::default(); n]
            } else {
                Vec::new()
            },
            spp: 0,
            rejected: RejectedSamples::new(width),
            spectral: None,
        }
    }

    /// (width, height).
    pub fn resolution(&self) -> (u32, u32) {
        self.camera.resolution()
    }

    /// Add refused samples met while rendering.
    pub fn record_rejected(&mut self, rejected: &[Rejection]) {
        let n = self.camera.pixels().len();
        for r in rejected {
            self.rejected.record(r, n);
        }
    }

    /// Add a pass's splat sums (row-major, this film's size).
    pub fn add_splats(&mut self, sums: &[[ExactSum; 3]]) {
        if self.splats.is_empty() {
            self.splats = vec![Default::default(); sums.len()];
        }
        for (a, b) in self.splats.iter_mut().zip(sums) {
            for c in 0..3 {
                a[c].merge(&b[c]);
            }
        }
    }

    /// Add another state of the same size holding other sample indices.
    pub fn merge(&mut self, other: &FilmState) {
        self.camera.merge_film(&other.camera);
        if !other.splats.is_empty() {
            self.add_splats(&other.splats);
        }
        self.spp += other.spp;
        self.rejected.merge(&other.rejected);
        match (&mut self.spectral, &other.spectral) {
            (Some(a), Some(b)) => a.merge(b),
            (None, Some(b)) => self.spectral = Some(b.clone()),
            _ => {}
        }
    }

    /// The spectral image (W/(m²·sr·nm) at the nodes), when the film keeps spectral sums.
    pub fn spectral_image(&self) -> Option<SpectralImage> {
        self.spectral.as_ref().map(|s| s.image(self.spp))
    }

    /// The image: each pixel's camera mean plus its splat sums divided by [`spp`](Self::spp).
    pub fn image(&self) -> XyzImage {
        let mut image = self.camera.image();
        if !self.splats.is_empty() {
            let scale = 1.0 / self.spp.max(1) as f64;
            for (p, s) in image.xyz.iter_mut().zip(&self.splats) {
                for c in 0..3 {
                    p[c] += s[c].value() * scale;
                }
            }
        }
        image
    }
}
