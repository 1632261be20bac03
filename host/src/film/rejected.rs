//! The film's guard: samples that are NaN, infinite or negative never enter the image. They are
//! counted per pixel (an optional diagnostic EXR channel `rejected`) and per strategy, and the
//! render summary names the strategies and the worst pixels. Counts are sums, so they merge
//! across threads, passes, slices and checkpoints like the film itself.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Why a sample was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RejectKind {
    /// NaN or ±∞ in a component.
    NonFinite,
    /// A finite negative component (radiance and colour-matching functions are non-negative).
    Negative,
}

/// Classify an XYZ sample: `None` when it may enter the film.
#[inline]
pub fn check_sample(xyz: &[f64; 3]) -> Option<RejectKind> {
    if xyz.iter().any(|v| !v.is_finite()) {
        Some(RejectKind::NonFinite)
    } else if xyz.iter().any(|&v| v < 0.0) {
        Some(RejectKind::Negative)
    } else {
        None
    }
}

/// One refused sample, as recorded by a tile or a splat film before merging.
#[derive(Clone, Debug, PartialEq)]
pub struct Rejection {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The strategy that produced it (e.g. `pt camera path`, `bdpt s=2 t=1`).
    pub strategy: String,
    /// Why.
    pub kind: RejectKind,
}

/// Refused samples of a whole film.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RejectedSamples {
    /// Width in pixels (of `per_pixel`).
    pub width: u32,
    /// Per pixel (row-major) the number refused; empty while there are none.
    pub per_pixel: Vec<u32>,
    /// Refused samples by strategy name.
    pub by_strategy: BTreeMap<String, u64>,
    /// Refused for a NaN or infinite component.
    pub non_finite: u64,
    /// Refused for a negative component.
    pub negative: u64,
}

impl RejectedSamples {
    /// None refused on a film `width` pixels wide.
    pub fn new(width: u32) -> Self {
        Self {
            width,
            ..Self::default()
        }
    }

    /// Total refused.
    pub fn total(&self) -> u64 {
        self.non_finite + self.negative
    }

    /// Record `r` on a film of `pixels` pixels.
    pub fn record(&mut self, r: &Rejection, pixels: usize) {
        if self.per_pixel.is_empty() {
            self.per_pixel = vec![0; pixels];
        }
        let i = r.y as usize * self.width as usize + r.x as usize;
        if let Some(c) = self.per_pixel.get_mut(i) {
            *c = c.saturating_add(1);
        }
        *self.by_strategy.entry(r.strategy.clone()).or_insert(0) += 1;
        match r.kind {
            RejectKind::NonFinite => self.non_finite += 1,
            RejectKind::Negative => self.negative += 1,
        }
    }

    /// Add another film's counts (same size).
    pub fn merge(&mut self, other: &RejectedSamples) {
        if !other.per_pixel.is_empty() {
            if self.per_pixel.is_empty() {
                self.per_pixel = vec![0; other.per_pixel.len()];
            }
            for (a, b) in self.per_pixel.iter_mut().zip(&other.per_pixel) {
                *a = a.saturating_add(*b);
            }
        }
        for (k, v) in &other.by_strategy {
            *self.by_strategy.entry(k.clone()).or_insert(0) += v;
        }
        self.non_finite += other.non_finite;
        self.negative += other.negative;
    }

    /// Per-pixel counts as a float channel for `pixels` pixels (zeros when none were refused).
    pub fn layer(&self, pixels: usize) -> Vec<f32> {
        if self.per_pixel.is_empty() {
            vec![0.0; pixels]
        } else {
            self.per_pixel.iter().map(|&c| c as f32).collect()
        }
    }

    /// Lines for the render summary: empty when nothing was refused; otherwise the counts, the
    /// strategies and up to five pixels with the most refusals (ties: the first in row order).
    pub fn summary(&self) -> Vec<String> {
        if self.total() == 0 {
            return Vec::new();
        }
        let mut lines = vec![format!(
            "rejected samples: {} ({} non-finite, {} negative), never entered the image",
            self.total(),
            self.non_finite,
            self.negative
        )];
        let by: Vec<String> = self
            .by_strategy
            .iter()
            .map(|(k, v)| format!("{k}: {v}"))
            .collect();
        lines.push(format!("  by strategy: {}", by.join(", ")));
        let mut worst: Vec<(usize, u32)> = self
            .per_pixel
            .iter()
            .copied()
            .enumerate()
            .filter(|&(_, c)| c > 0)
            .collect();
        worst.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let w = self.width.max(1) as usize;
        let px: Vec<String> = worst
            .iter()
            .take(5)
            .map(|&(i, c)| format!("({}, {}): {c}", i % w, i / w))
            .collect();
        lines.push(format!("  pixels (x, y): {}", px.join(", ")));
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// NaN, ±∞ and negative components are refused with the right kind, -0.0 and 0 pass;
    /// counts merge by addition and the summary names strategy and pixel.
    #[test]
    fn classify_count_and_report() {
        assert_eq!(check_sample(&[0.0, -0.0, 1.0]), None);
        assert_eq!(
            check_sample(&[f64::NAN, 0.0, 0.0]),
            Some(RejectKind::NonFinite)
        );
        assert_eq!(
            check_sample(&[-1e-30, f64::INFINITY, 0.0]),
            Some(RejectKind::NonFinite)
        );
        assert_eq!(
            check_sample(&[1.0, -1e-30, 0.0]),
            Some(RejectKind::Negative)
        );
        let mut a = RejectedSamples::new(4);
        a.record(
            &Rejection {
                x: 3,
                y: 1,
                strategy: "pt camera path".into(),
                kind: RejectKind::Negative,
            },
            8,
        );
        let mut b = RejectedSamples::new(4);
        b.merge(&a);
        b.merge(&a);
        assert_eq!(b.total(), 2);
        assert_eq!(b.per_pixel[7], 2);
        let s = b.summary().join("\n");
        assert!(
            s.contains("pt camera path: 2") && s.contains("(3, 1): 2"),
            "{s}"
        );
        assert!(RejectedSamples::new(4).summary().is_empty());
    }
}
