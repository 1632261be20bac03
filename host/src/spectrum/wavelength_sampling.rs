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

/// Knots of the visible-importance table: the density is constant between consecutive knots.
pub const VISIBLE_TABLE_SEGMENTS: usize = 1024;

/// `tanh(a(λ−c))` at the two ends of [`VISIBLE_RANGE`]: the smooth CDF is linear in this quantity.
fn visible_tanh_bounds() -> (f64, f64) {
    let t = |l: f64| (VISIBLE_SHARPNESS * (l - VISIBLE_CENTRE)).tanh();
    (t(VISIBLE_RANGE.0), t(VISIBLE_RANGE.1))
}

/// The sampling table: `knots[k]` is the smooth inverse CDF at `u = k/N` (nm) and `pdf[k]` the
/// constant density `1/(N·(knots[k+1] − knots[k]))` (1/nm) of segment `k`.
struct VisibleTable {
    knots: [f64; VISIBLE_TABLE_SEGMENTS + 1],
    pdf: [f64; VISIBLE_TABLE_SEGMENTS],
}

/// Built once: the exact inverse `λ = c + atanh(t₀ + u(t₁ − t₀))/a` at the knots. Sampling then
/// costs a multiply, a table read and a linear interpolation instead of the `atanh` and `cosh`
/// per lane that took about 6% of path-tracing time.
fn visible_table() -> &'static VisibleTable {
    static TABLE: std::sync::OnceLock<Box<VisibleTable>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let (t0, t1) = visible_tanh_bounds();
        let n = VISIBLE_TABLE_SEGMENTS;
        let mut table = Box::new(VisibleTable {
            knots: [0.0; VISIBLE_TABLE_SEGMENTS + 1],
            pdf: [0.0; VISIBLE_TABLE_SEGMENTS],
        });
        for k in 0..=n {
            let u = k as f64 / n as f64;
            table.knots[k] = VISIBLE_CENTRE + (t0 + u * (t1 - t0)).atanh() / VISIBLE_SHARPNESS;
        }
        // Exact ends, so the support is exactly the range.
        table.knots[0] = VISIBLE_RANGE.0;
        table.knots[n] = VISIBLE_RANGE.1;
        for k in 0..n {
            table.pdf[k] = 1.0 / (n as f64 * (table.knots[k + 1] - table.knots[k]));
        }
        table
    })
}

/// Segment of the table holding `lambda_nm` (which must lie in [`VISIBLE_RANGE`]).
#[inline]
fn visible_segment(table: &VisibleTable, lambda_nm: f64) -> usize {
    // First knot above λ, minus one; the last knot belongs to the last segment.
    let k = table.knots.partition_point(|&x| x <= lambda_nm);
    k.clamp(1, VISIBLE_TABLE_SEGMENTS) - 1
}

/// Density (1/nm) of visible-importance sampling, 0 outside 360–830 nm. It follows the shape
/// `1/cosh²(0.0072 (λ − 538))`, the fit to the CIE 1931 observer's luminance response introduced
/// by pbrt-v4 (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., 2023, chapter
/// "Cameras and Film"; `SampleVisibleWavelengths` in pbrt-v4's sampling code; only the two shape
/// constants are taken from there), as a piecewise-constant density on
/// [`VISIBLE_TABLE_SEGMENTS`] segments of equal probability whose ends are the smooth shape's
/// exact CDF quantiles (`∫ sech²(a(λ−c)) dλ = [tanh(a(λ−c))/a]`). This is exactly the density
/// [`visible_sample`] draws from; it is within 3% of the smooth shape everywhere (the widest
/// segments, ≈ 4 nm, are in the far tails).
pub fn visible_pdf(lambda_nm: f64) -> f64 {
    if !(lambda_nm >= VISIBLE_RANGE.0 && lambda_nm <= VISIBLE_RANGE.1) {
        return 0.0;
    }
    let table = visible_table();
    table.pdf[visible_segment(table, lambda_nm)]
}

/// Exact inverse CDF of [`visible_pdf`]: linear interpolation between the table's knots.
pub fn visible_sample(u: f64) -> f64 {
    visible_sample_with_pdf(u).0
}

/// [`visible_sample`] and the density at the returned wavelength, from one table read.
#[inline]
pub fn visible_sample_with_pdf(u: f64) -> (f64, f64) {
    let table = visible_table();
    let x = u.clamp(0.0, 1.0) * VISIBLE_TABLE_SEGMENTS as f64;
    let k = (x as usize).min(VISIBLE_TABLE_SEGMENTS - 1);
    let f = x - k as f64;
    let (a, b) = (table.knots[k], table.knots[k + 1]);
    (a + f * (b - a), table.pdf[k])
}

/// [`visible_pdf`] of `lambda_nm` known to lie at or next to segment `k` (as after rounding a
/// sample of segment `k` to f32): a neighbour check instead of a search.
#[inline]
fn visible_pdf_near(table: &VisibleTable, lambda_nm: f64, k: usize) -> f64 {
    if lambda_nm < table.knots[k] {
        if k == 0 {
            return 0.0;
        }
        return visible_pdf(lambda_nm);
    }
    if lambda_nm >= table.knots[k + 1] && k + 1 < VISIBLE_TABLE_SEGMENTS {
        return visible_pdf(lambda_nm);
    }
    if lambda_nm > VISIBLE_RANGE.1 {
        return 0.0;
    }
    table.pdf[k]
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
        let table = visible_table();
        Self::from_lanes(|i| {
            let x = rotated(u as f64, i, LANES).clamp(0.0, 1.0) * VISIBLE_TABLE_SEGMENTS as f64;
            // x ∈ [0, segments]: `as i32` floors it like `as usize` with one conversion.
            let k = (x as i32 as usize).min(VISIBLE_TABLE_SEGMENTS - 1);
            let (a, b) = (table.knots[k], table.knots[k + 1]);
            let l = (a + (x - k as f64) * (b - a)) as f32;
            // The pdf belongs to the stored (f32) wavelength, so the pair is consistent even when
            // rounding moves λ across a knot.
            (l, visible_pdf_near(table, l as f64, k) as f32)
        })
    }

    /// All lanes live, lane `i` holding the wavelength (nm) and density (1/nm) `draw(i)` gives:
    /// the one loop of the per-lane samplers (visible, an SPD's, a tabulated density).
    #[inline(always)]
    pub fn from_lanes(mut draw: impl FnMut(usize) -> (f32, f32)) -> Self {
        let mut lambda = [0.0f32; LANES];
        let mut pdf = [0.0f32; LANES];
        for i in 0..LANES {
            (lambda[i], pdf[i]) = draw(i);
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
        Self::from_lanes(|i| {
            let s = spd.sample(rotated(u as f64, i, LANES));
            let l = s.lambda as f32;
            // As for visible sampling, the pdf belongs to the stored (f32) wavelength; should
            // rounding move λ onto a zero of the SPD, keep the draw's own (positive) pdf.
            let p = if s.is_delta { 0.0 } else { spd.pdf(l as f64) };
            (l, if p > 0.0 { p as f32 } else { s.pdf as f32 })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // The visible pdf integrates to 1 (midpoint rule at 0.01 nm; the density is piecewise
    // constant, so the rule errs only in the cells holding one of the 1025 knots, each by at
    // most 0.01 nm × the largest density jump ≈ 3e-7, i.e. < 3e-4 in all; 1e-3 allows for that)
    // and the inverse CDF is consistent with it: d(λ(u))/du = 1/p(λ) (central difference inside
    // a segment, where λ(u) is linear; 1e-6 relative for rounding at h = 1e-7).
    #[test]
    fn visible_pdf_normalized_and_inverse_consistent() {
        let (lo, hi) = VISIBLE_RANGE;
        let n = 47_000;
        let h = (hi - lo) / n as f64;
        let sum: f64 = (0..n)
            .map(|i| visible_pdf(lo + (i as f64 + 0.5) * h) * h)
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
        let segments = VISIBLE_TABLE_SEGMENTS as f64;
        for k in 1..20 {
            // Middle of segment ⌊u·N⌋, away from its knots.
            let u = ((k as f64 / 20.0 * segments).floor() + 0.5) / segments;
            let d = 1e-7;
            let dl = (visible_sample(u + d) - visible_sample(u - d)) / (2.0 * d);
            let p = visible_pdf(visible_sample(u));
            assert!((dl * p - 1.0).abs() < 1e-6, "u={u}: {}", dl * p);
            assert_eq!(visible_sample_with_pdf(u).1, p);
        }
        assert_eq!(visible_sample(0.0), lo);
        assert!((visible_sample(1.0) - hi).abs() < 1e-9);
    }

    // The table follows the smooth shape p(λ) ∝ sech²(a(λ−c)) it was made from: at 2001 points
    // the ratio to the normalised smooth density is within 3.1% (the steepest relative slope,
    // 2a·tanh ≤ 0.014/nm, times the widest segment, 4.15 nm at 830 nm, gives at most 2.96%).
    #[test]
    fn visible_table_follows_smooth_shape() {
        let (t0, t1) = visible_tanh_bounds();
        let a = VISIBLE_SHARPNESS;
        let (lo, hi) = VISIBLE_RANGE;
        for i in 0..=2000 {
            let l = lo + (hi - lo) * i as f64 / 2000.0;
            let ch = (a * (l - VISIBLE_CENTRE)).cosh();
            let smooth = a / ((t1 - t0) * ch * ch);
            let ratio = visible_pdf(l) / smooth;
            assert!((ratio - 1.0).abs() < 0.031, "λ={l}: ratio {ratio}");
        }
        assert_eq!(visible_pdf(lo - 1e-9), 0.0);
        assert_eq!(visible_pdf(hi + 1e-9), 0.0);
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
