//! Constructors of [`SampledWavelengths`] that importance-sample the wavelength.
//!
//! All of them draw the hero from `u` and the other lanes from the *rotated* primary samples
//! `uᵢ = frac(u + i/LANES)`. Each `uᵢ` on its own is uniform on `[0,1)`, so lane `i`'s marginal
//! density is exactly the density the inversion maps a uniform number to: that is the pdf
//! stored for the lane. The rotation keeps the lanes stratified across the spectrum.

use super::spd::Spd;
use super::{LaneMask, SampledWavelengths, LANES};

/// Shape parameter (1/nm) of the visible-wavelength importance density.
pub const VISIBLE_SHARPNESS: f64 = 0.0072;
/// Centre (nm) of the visible-wavelength importance density.
pub const VISIBLE_CENTRE: f64 = 538.0;
/// Range (nm) of the visible-wavelength importance density: the CIE observers' tables.
pub const VISIBLE_RANGE: (f64, f64) = (360.0, 830.0);

/// `tanh(a(λ−c))` at the two ends of [`VISIBLE_RANGE`]: the CDF is linear in this quantity.
fn visible_tanh_bounds() -> (f64, f64) {
    // Computed once: `sample_visible` runs for every camera path, and two `tanh` calls per path
    // were a measurable share of path-tracing time.
    static BOUNDS: std::sync::OnceLock<(f64, f64)> = std::sync::OnceLock::new();
    *BOUNDS.get_or_init(|| {
        let t = |l: f64| (VISIBLE_SHARPNESS * (l - VISIBLE_CENTRE)).tanh();
        (t(VISIBLE_RANGE.0), t(VISIBLE_RANGE.1))
    })
}

/// Density (1/nm) of visible-importance sampling: `p(λ) ∝ 1/cosh²(0.0072 (λ − 538))` on
/// 360–830 nm, 0 outside. The shape is the fit to the CIE 1931 observer's luminance response
/// introduced by pbrt-v4 (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed.,
/// 2023, chapter "Cameras and Film"; `SampleVisibleWavelengths` in pbrt-v4's sampling code).
/// Only the two shape constants are taken from there; the normalization is computed here exactly:
/// `∫ sech²(a(λ−c)) dλ = [tanh(a(λ−c))/a]` over the range.
pub fn visible_pdf(lambda_nm: f64) -> f64 {
    if !(lambda_nm >= VISIBLE_RANGE.0 && lambda_nm <= VISIBLE_RANGE.1) {
        return 0.0;
    }
    let (t0, t1) = visible_tanh_bounds();
    let a = VISIBLE_SHARPNESS;
    let ch = (a * (lambda_nm - VISIBLE_CENTRE)).cosh();
    a / ((t1 - t0) * ch * ch)
}

/// Exact inverse CDF of [`visible_pdf`]: `λ = c + atanh(t₀ + u(t₁ − t₀))/a`.
pub fn visible_sample(u: f64) -> f64 {
    let (t0, t1) = visible_tanh_bounds();
    let l = VISIBLE_CENTRE + (t0 + u.clamp(0.0, 1.0) * (t1 - t0)).atanh() / VISIBLE_SHARPNESS;
    l.clamp(VISIBLE_RANGE.0, VISIBLE_RANGE.1)
}

/// `frac(u + k/n)`: the primary sample of the k-th of `n` rotated lanes (exactly `u` for k = 0).
/// Each is uniform on [0, 1) on its own, and together they stratify the range.
pub fn rotated(u: f64, k: usize, n: usize) -> f64 {
    if k == 0 {
        return u;
    }
    let v = u + k as f64 / n as f64;
    if v >= 1.0 {
        v - 1.0
    } else {
        v
    }
}

impl SampledWavelengths {
    /// Wavelengths importance-sampled for a human observer (see [`visible_pdf`]); lane `i` has
    /// wavelength `visible_sample(frac(u + i/LANES))` and pdf `visible_pdf` of it.
    pub fn sample_visible(u: f32) -> Self {
        let mut lambda = [0.0f32; LANES];
        let mut pdf = [0.0f32; LANES];
        for i in 0..LANES {
            // The pdf is evaluated at the stored (f32) wavelength so the pair is consistent.
            let l = visible_sample(rotated(u as f64, i, LANES)) as f32;
            lambda[i] = l;
            pdf[i] = visible_pdf(l as f64) as f32;
        }
        Self {
            lambda,
            pdf,
            lanes: LaneMask::ALL,
        }
    }

    /// Wavelengths importance-sampled from a light's SPD: lane `i` is `spd.sample(frac(u +
    /// i/LANES))` with that sample's pdf (1/nm). When a lane lands on a delta line, its pdf is
    /// the line's discrete probability instead, and the light's emission at that lane must be
    /// the line's power fraction (see [`Spd::delta_lines`]) rather than a density.
    pub fn sample_spd(spd: &dyn Spd, u: f32) -> Self {
        let mut lambda = [0.0f32; LANES];
        let mut pdf = [0.0f32; LANES];
        for i in 0..LANES {
            let s = spd.sample(rotated(u as f64, i, LANES));
            let l = s.lambda as f32;
            lambda[i] = l;
            // As for visible sampling, the pdf belongs to the stored (f32) wavelength; should
            // rounding move λ onto a zero of the SPD, keep the draw's own (positive) pdf.
            let p = if s.is_delta { 0.0 } else { spd.pdf(l as f64) };
            pdf[i] = if p > 0.0 { p as f32 } else { s.pdf as f32 };
        }
        Self {
            lambda,
            pdf,
            lanes: LaneMask::ALL,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The visible pdf integrates to 1 (midpoint rule at 0.01 nm; 1e-8 covers its error for this
    // smooth function) and the inverse CDF is consistent with it: d(λ(u))/du = 1/p(λ)
    // (central difference, 1e-5 relative for the O(h²) difference error at h = 1e-6).
    #[test]
    fn visible_pdf_normalized_and_inverse_consistent() {
        let (lo, hi) = VISIBLE_RANGE;
        let n = 47_000;
        let h = (hi - lo) / n as f64;
        let sum: f64 = (0..n)
            .map(|i| visible_pdf(lo + (i as f64 + 0.5) * h) * h)
            .sum();
        assert!((sum - 1.0).abs() < 1e-8, "{sum}");
        for k in 1..20 {
            let u = k as f64 / 20.0;
            let d = 1e-6;
            let dl = (visible_sample(u + d) - visible_sample(u - d)) / (2.0 * d);
            let p = visible_pdf(visible_sample(u));
            assert!((dl * p - 1.0).abs() < 1e-5, "u={u}: {}", dl * p);
        }
        assert_eq!(visible_sample(0.0), lo);
        assert!((visible_sample(1.0) - hi).abs() < 1e-9);
    }

    // Each lane's stored pdf is the density of its own wavelength (the marginal, because each
    // rotated u is uniform); exact f32 equality since both come from the same f64 value.
    #[test]
    fn lanes_carry_their_own_pdf() {
        let w = SampledWavelengths::sample_visible(0.3);
        for i in 0..LANES {
            assert_eq!(w.pdf[i], visible_pdf(w.lambda[i] as f64) as f32);
        }
        let spd = crate::spectrum::parse_spd_spec("d65").unwrap();
        let w = SampledWavelengths::sample_spd(&spd, 0.9);
        for i in 0..LANES {
            let p = spd.pdf(w.lambda[i] as f64) as f32;
            assert!((w.pdf[i] - p).abs() <= 1e-6 * p, "{} vs {p}", w.pdf[i]);
        }
    }
}
