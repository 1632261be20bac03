//! Importance sampling of emission directions for a [`Luminaire`]: a piecewise-constant density
//! over the cells of the symmetry-expanded angle grid, each cell weighted by its mean corner
//! candela times its solid angle, and uniform in solid angle inside a cell. The pdf is therefore
//! proportional to the table's intensity up to the grid resolution, and positive wherever the
//! bilinear intensity is.

use super::luminaire::{segment, Luminaire, PhotometricType};
use std::f64::consts::PI;

/// Piecewise-constant direction density over a luminaire's angle grid (pdf per sr).
#[derive(Clone, Debug)]
pub struct DirectionSampler {
    ptype: PhotometricType,
    /// Cell edges in `h` (degrees); type C: periodic, the last edge is the first + 360.
    h_edges: Vec<f64>,
    /// Cell edges in `v` (degrees).
    v_edges: Vec<f64>,
    /// Cumulative cell weights (lm), row-major `[ih * (nv - 1) + iv]`, last = total.
    cdf: Vec<f64>,
    /// Cell weights (mean cd × sr = lm).
    weight: Vec<f64>,
}

impl DirectionSampler {
    /// Build the table; `None` when the luminaire emits nothing (all zero candela).
    pub fn new(lum: &Luminaire) -> Option<Self> {
        let mut h_edges = lum.expanded_h_deg();
        if lum.photometric_type == PhotometricType::C {
            if h_edges.len() == 1 {
                h_edges = vec![0.0, 360.0];
            } else {
                h_edges.push(h_edges[0] + 360.0);
            }
        }
        let v_edges = lum.v_deg.clone();
        if h_edges.len() < 2 || v_edges.len() < 2 {
            return None;
        }
        let (nh, nv) = (h_edges.len() - 1, v_edges.len() - 1);
        let mut weight = Vec::with_capacity(nh * nv);
        for i in 0..nh {
            for j in 0..nv {
                let (h0, h1, v0, v1) = (h_edges[i], h_edges[i + 1], v_edges[j], v_edges[j + 1]);
                let mean = 0.25
                    * (lum.candela_at(h0, v0)
                        + lum.candela_at(h1, v0)
                        + lum.candela_at(h0, v1)
                        + lum.candela_at(h1, v1));
                weight.push(mean * cell_solid_angle(lum.photometric_type, h0, h1, v0, v1));
            }
        }
        let mut cdf = Vec::with_capacity(weight.len());
        let mut acc = 0.0;
        for w in &weight {
            acc += w;
            cdf.push(acc);
        }
        (acc > 0.0).then_some(Self {
            ptype: lum.photometric_type,
            h_edges,
            v_edges,
            cdf,
            weight,
        })
    }

    /// Sum of cell weights in lm: the flux of the piecewise-constant approximation.
    pub fn total_lm(&self) -> f64 {
        *self.cdf.last().unwrap_or(&0.0)
    }

    /// A direction (unit, luminaire frame) for uniform `u1`, `u2` in [0, 1), with its pdf per sr.
    pub fn sample(&self, lum: &Luminaire, u1: f64, u2: f64) -> ([f64; 3], f64) {
        let total = self.total_lm();
        let target = u1 * total;
        let k = self
            .cdf
            .partition_point(|&c| c <= target)
            .min(self.cdf.len() - 1);
        let start = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        // Reuse u1's position inside the chosen cell for the first in-cell coordinate.
        let s = ((target - start) / self.weight[k]).clamp(0.0, 1.0 - 1e-12);
        let nv = self.v_edges.len() - 1;
        let (i, j) = (k / nv, k % nv);
        let (h0, h1, v0, v1) = (
            self.h_edges[i],
            self.h_edges[i + 1],
            self.v_edges[j],
            self.v_edges[j + 1],
        );
        let (h, v) = match self.ptype {
            // Uniform in solid angle: uniform in cos γ and in C.
            PhotometricType::C => {
                let (c0, c1) = (v0.to_radians().cos(), v1.to_radians().cos());
                let v = (c0 + (c1 - c0) * u2).clamp(-1.0, 1.0).acos().to_degrees();
                (h0 + (h1 - h0) * s, v)
            }
            // Latitude v: uniform in sin v and in h.
            PhotometricType::A => {
                let (s0, s1) = (v0.to_radians().sin(), v1.to_radians().sin());
                let v = (s0 + (s1 - s0) * u2).clamp(-1.0, 1.0).asin().to_degrees();
                (h0 + (h1 - h0) * s, v)
            }
            // Latitude h: uniform in sin h and in v.
            PhotometricType::B => {
                let (s0, s1) = (h0.to_radians().sin(), h1.to_radians().sin());
                let h = (s0 + (s1 - s0) * s).clamp(-1.0, 1.0).asin().to_degrees();
                (h, v0 + (v1 - v0) * u2)
            }
        };
        let omega = cell_solid_angle(self.ptype, h0, h1, v0, v1);
        let d = lum.direction_of(h, v);
        (d, self.weight[k] / (total * omega))
    }

    /// The pdf per sr of [`Self::sample`] for a unit direction in the luminaire frame.
    pub fn pdf(&self, lum: &Luminaire, direction: [f64; 3]) -> f64 {
        let (mut h, v) = lum.angles_of(direction);
        if self.ptype == PhotometricType::C && h < self.h_edges[0] {
            h += 360.0;
        }
        let (Some((i, _)), Some((j, _))) = (
            segment(&self.h_edges, h).map(|(i, t)| (i.min(self.h_edges.len() - 2), t)),
            segment(&self.v_edges, v).map(|(j, t)| (j.min(self.v_edges.len() - 2), t)),
        ) else {
            return 0.0;
        };
        let nv = self.v_edges.len() - 1;
        let k = i * nv + j;
        let omega = cell_solid_angle(
            self.ptype,
            self.h_edges[i],
            self.h_edges[i + 1],
            self.v_edges[j],
            self.v_edges[j + 1],
        );
        self.weight[k] / (self.total_lm() * omega)
    }
}

/// Solid angle in sr of the cell [h0, h1] × [v0, v1] (degrees) of a grid of the given type.
fn cell_solid_angle(ptype: PhotometricType, h0: f64, h1: f64, v0: f64, v1: f64) -> f64 {
    let r = |a: f64| a * PI / 180.0;
    match ptype {
        PhotometricType::C => r(h1 - h0) * (r(v0).cos() - r(v1).cos()),
        PhotometricType::A => r(h1 - h0) * (r(v1).sin() - r(v0).sin()),
        PhotometricType::B => r(v1 - v0) * (r(h1).sin() - r(h0).sin()),
    }
}
