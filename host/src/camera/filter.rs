//! Pixel reconstruction filters, used by importance sampling: the sample position inside the
//! filter footprint is drawn with density ∝ filter, so every sample has weight exactly 1 and a
//! light-tracing splat at a raster position and a camera sample agree on what a pixel measures.

use glam::Vec2;
use std::f32::consts::SQRT_2;

/// A separable pixel filter centred on the pixel centre, offsets in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    /// Uniform over `[-r, r]²` (r = 0.5: one pixel, no overlap).
    Box {
        /// Half-width in pixels.
        radius: f32,
    },
    /// Gaussian `exp(-x²/(2σ²))` truncated at `radius` pixels per axis.
    Gaussian {
        /// Standard deviation in pixels.
        sigma: f32,
        /// Truncation half-width in pixels.
        radius: f32,
    },
}

impl Default for Filter {
    fn default() -> Self {
        Filter::Box { radius: 0.5 }
    }
}

impl Filter {
    /// Half-width of the footprint in pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box { radius } | Filter::Gaussian { radius, .. } => radius,
        }
    }

    /// Draw an offset (pixels) from the pixel centre with density ∝ filter; weight is 1.
    pub fn sample(&self, u: Vec2) -> Vec2 {
        match *self {
            Filter::Box { radius } => (u * 2.0 - Vec2::ONE) * radius,
            Filter::Gaussian { sigma, radius } => Vec2::new(
                sample_truncated_gaussian(u.x, sigma, radius),
                sample_truncated_gaussian(u.y, sigma, radius),
            ),
        }
    }

    /// Normalised filter density at `offset` (1/pixel²): integrates to 1 over the footprint.
    pub fn pdf(&self, offset: Vec2) -> f32 {
        let r = self.radius();
        if offset.x.abs() > r || offset.y.abs() > r {
            return 0.0;
        }
        match *self {
            Filter::Box { radius } => 1.0 / (4.0 * radius * radius),
            Filter::Gaussian { sigma, radius } => {
                let norm = gaussian_mass(sigma, radius);
                let g = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
                g(offset.x) * g(offset.y) / (norm * norm)
            }
        }
    }
}

/// ∫_{-r}^{r} exp(-x²/(2σ²)) dx.
fn gaussian_mass(sigma: f32, radius: f32) -> f32 {
    sigma * (2.0 * std::f32::consts::PI).sqrt() * erf(radius / (sigma * SQRT_2))
}

/// Inverse-CDF sample of a zero-mean Gaussian truncated to `[-r, r]`.
fn sample_truncated_gaussian(u: f32, sigma: f32, radius: f32) -> f32 {
    let e = erf(radius / (sigma * SQRT_2));
    // CDF of the truncated Gaussian maps x to (erf(x/(σ√2)) + e)/(2e).
    let x = sigma * SQRT_2 * erf_inv((2.0 * u - 1.0) * e);
    x.clamp(-radius, radius)
}

/// Error function (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7).
pub fn erf(x: f32) -> f32 {
    let s = x.signum();
    let x = x.abs() as f64;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let y = 1.0
        - (((((1.061_405_429 * t - 1.453_152_027) * t) + 1.421_413_741) * t - 0.284_496_736) * t
            + 0.254_829_592)
            * t
            * (-x * x).exp();
    s * y as f32
}

/// Inverse error function on (-1, 1) (Giles 2012 single-precision approximation, refined with
/// two Newton steps on [`erf`]).
pub fn erf_inv(y: f32) -> f32 {
    let y = y.clamp(-0.999_999_9, 0.999_999_9);
    let w = -((1.0 - y) * (1.0 + y)).ln();
    let mut x = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_4e-8f32;
        p = 3.432_739_4e-7 + p * w;
        p = -3.523_387_7e-6 + p * w;
        p = -4.391_506_5e-6 + p * w;
        p = 0.000_218_580_87 + p * w;
        p = -0.001_253_725 + p * w;
        p = -0.004_177_681_6 + p * w;
        p = 0.246_640_73 + p * w;
        p = 1.501_409_4 + p * w;
        p * y
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_26f32;
        p = 0.000_100_950_56 + p * w;
        p = 0.001_349_343_2 + p * w;
        p = -0.003_673_428_4 + p * w;
        p = 0.005_739_507_7 + p * w;
        p = -0.007_622_461 + p * w;
        p = 0.009_438_870_5 + p * w;
        p = 1.001_674 + p * w;
        p = 2.832_976_8 + p * w;
        p * y
    };
    for _ in 0..2 {
        let err = erf(x) - y;
        x -= err / (2.0 / std::f32::consts::PI.sqrt() * (-x * x).exp());
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// erf_inv inverts erf to 1e-4 over [-0.99, 0.99] (A&S erf is accurate to 1.5e-7; the
    /// tolerance covers f32 rounding amplified by the steep slope near ±1).
    #[test]
    fn erf_inv_inverts_erf() {
        for i in -99..=99 {
            let y = i as f32 / 100.0;
            assert!((erf(erf_inv(y)) - y).abs() < 1e-4, "{y}");
        }
        assert!((erf(1.0) - 0.842_700_8).abs() < 1e-6);
    }

    /// Filter-importance sampling: the histogram of sampled x offsets must follow the filter's
    /// marginal. 10⁵ samples into 10 bins; each bin's expected count ≥ 3·10³ so a 5σ band is ≈ 10%
    /// relative; we allow 6% + 5σ-style slack via |obs−exp| < 5√exp.
    #[test]
    fn gaussian_samples_follow_the_filter() {
        let f = Filter::Gaussian {
            sigma: 0.5,
            radius: 1.5,
        };
        let n = 100_000;
        let bins = 10;
        let mut hist = vec![0u32; bins];
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let x = f.sample(Vec2::new(u, 0.5)).x;
            assert!(x.abs() <= 1.5);
            let b = (((x + 1.5) / 3.0) * bins as f32).min(bins as f32 - 1.0) as usize;
            hist[b] += 1;
        }
        for (b, &count) in hist.iter().enumerate() {
            let a = -1.5 + 3.0 * b as f32 / bins as f32;
            let c = a + 3.0 / bins as f32;
            // Truncated-Gaussian bin mass from the closed-form CDF.
            let p = (erf(c / (0.5 * SQRT_2)) - erf(a / (0.5 * SQRT_2)))
                / (2.0 * erf(1.5 / (0.5 * SQRT_2)));
            let expected = p * n as f32;
            assert!(
                (count as f32 - expected).abs() < 5.0 * expected.sqrt() + 2.0,
                "bin {b}: {count} vs {expected}"
            );
        }
    }

    /// The box filter's pdf integrates to 1 over its footprint and samples stay inside it.
    #[test]
    fn box_filter_is_normalised() {
        let f = Filter::Box { radius: 0.5 };
        assert!((f.pdf(Vec2::ZERO) - 1.0).abs() < 1e-6);
        let s = f.sample(Vec2::new(0.999, 0.0));
        assert!(s.x <= 0.5 && s.y >= -0.5);
    }
}
