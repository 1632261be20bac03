//! A spectrum resampled on a 1 nm grid over the observers' range (360–830 nm) for O(1)
//! evaluation in the render loop (one index and one lerp instead of a binary search per lane).
//! Piecewise-linear data with breakpoints on integer nm (all bundled data) is reproduced exactly;
//! smooth curves to well below 1e-4 relative. Outside the grid the original function is used.

use crate::spectrum::spd::line_mass_at_lane;
use crate::spectrum::{DeltaLine, SampledSpectrum, SampledWavelengths, Spd, LANES};
use glam::Vec4;
use std::fmt::Debug;
use std::sync::Arc;

/// First grid wavelength (nm).
pub const DENSE_START: f32 = 360.0;
/// Last grid wavelength (nm).
pub const DENSE_END: f32 = 830.0;
const N: usize = (DENSE_END - DENSE_START) as usize + 1;
/// Quantiles of an SPD's power probed by [`DenseSpectrum::from_spd`] to find sub-nm spikes.
pub const SPIKE_PROBES: usize = 4096;

/// A tabulated copy of a spectral function (values at 360, 361, …, 830 nm).
///
/// A cell whose linear interpolation does not reproduce the function at its midpoint (a step,
/// such as where a tabulated spectrum ends and drops to zero, or a breakpoint off the integer
/// grid) is marked and evaluated exactly instead, so the copy never smears a discontinuity.
#[derive(Clone)]
pub struct DenseSpectrum {
    values: Vec<f32>,
    /// Per cell [i, i+1]: the value at i and the difference to i+1, read together by
    /// [`value`](Self::value) (fixed size, so a clamped index needs no bounds check). An exact
    /// cell holds (NaN, NaN), so that [`eval`](Self::eval) can interpolate four lanes without
    /// a branch per lane and notice such a cell by the NaN it yields.
    cells: Box<[(f32, f32); N - 1]>,
    /// Per cell [i, i+1]: evaluate the original function instead of interpolating.
    exact: Box<[bool; N - 1]>,
    outside: Arc<dyn Fn(f32) -> f32 + Send + Sync>,
    /// Delta lines with their scaled power (see [`crate::spectrum::spd::spd_at`]): a lane on
    /// a line's exact wavelength gets its power instead of the continuous value.
    lines: Vec<DeltaLine>,
}

impl Debug for DenseSpectrum {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseSpectrum")
            .field("at_560nm", &self.value(560.0))
            .finish()
    }
}

/// The cell index of each lane of [`DenseSpectrum::eval`]: the mantissa of `x + 2²³`
/// (`rounded`), one lower where that rounded up (`up`), at most `N − 2` (a wrapped `0 − 1`
/// included). On x86-64 the four lanes at once with SSE2 (part of the x86-64 baseline), where
/// the scalar version moves each lane to a general register and masks, subtracts and clamps
/// it there: the same integers, fewer instructions in every spectrum lookup of a path
/// (reflectances, emission). [`cell_indices_scalar`] is the definition.
#[inline(always)]
fn cell_indices(rounded: Vec4, up: glam::BVec4A) -> [usize; LANES] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let r: __m128 = rounded.into();
        let u: __m128 = up.into();
        // SAFETY: SSE2 is part of the x86-64 baseline, so every x86-64 CPU runs these
        // intrinsics; they only compute on registers (no memory is read or written).
        unsafe {
            // Mantissa plus the all-ones (−1) of an `up` lane.
            let i = _mm_add_epi32(
                _mm_and_si128(_mm_castps_si128(r), _mm_set1_epi32(0x7F_FFFF)),
                _mm_castps_si128(u),
            );
            // Unsigned `min(i, N − 2)` through a signed comparison with the sign bits flipped.
            let last = _mm_set1_epi32(N as i32 - 2);
            let flip = _mm_set1_epi32(i32::MIN);
            let over = _mm_cmpgt_epi32(_mm_xor_si128(i, flip), _mm_xor_si128(last, flip));
            let i = _mm_or_si128(_mm_andnot_si128(over, i), _mm_and_si128(over, last));
            // Every index is now below 2¹⁶: the low half of each 32-bit lane is all of it.
            [
                _mm_extract_epi16::<0>(i) as usize,
                _mm_extract_epi16::<2>(i) as usize,
                _mm_extract_epi16::<4>(i) as usize,
                _mm_extract_epi16::<6>(i) as usize,
            ]
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        cell_indices_scalar(rounded, up)
    }
}

/// [`cell_indices`] lane by lane.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn cell_indices_scalar(rounded: Vec4, up: glam::BVec4A) -> [usize; LANES] {
    let (bits, up) = (rounded.to_array(), up.bitmask());
    std::array::from_fn(|k| {
        let i = (bits[k].to_bits() & 0x7F_FFFF).wrapping_sub((up >> k) & 1);
        (i as usize).min(N - 2)
    })
}

impl DenseSpectrum {
    /// Tabulate `f` (nm → value).
    pub fn new(f: Arc<dyn Fn(f32) -> f32 + Send + Sync>) -> Self {
        let values: Vec<f32> = (0..N).map(|i| f(DENSE_START + i as f32)).collect();
        let mut exact = Box::new([false; N - 1]);
        let mut cells = Box::new([(0.0, 0.0); N - 1]);
        for i in 0..N - 1 {
            let mid = f(DENSE_START + i as f32 + 0.5);
            let lerp = 0.5 * (values[i] + values[i + 1]);
            // Smooth spectra interpolate to ~h²f''/8 (≲ 1e-4 relative for a 2000 K blackbody);
            // a step (relative miss ~1) or an off-grid
            // kink misses by far more.
            exact[i] = (mid - lerp).abs() > 2e-4 * mid.abs().max(lerp.abs()) + 1e-30;
            cells[i] = if exact[i] {
                (f32::NAN, f32::NAN)
            } else {
                (values[i], values[i + 1] - values[i])
            };
        }
        Self {
            values,
            cells,
            exact,
            outside: f,
            lines: Vec::new(),
        }
    }

    /// `scale ·` a normalised SPD: its continuous part (1/nm) on the grid, its delta lines
    /// (power fraction × `scale`) on the lanes that land on them.
    ///
    /// A peak narrower than the 1 nm grid (a tabulated spike of 0.01 nm) can fall between
    /// nodes and cell midpoints and vanish from the copy; every cell that holds one of
    /// [`SPIKE_PROBES`] equally spaced quantiles of the SPD's power (inverse CDF) is therefore
    /// evaluated exactly too, so any feature holding more than 1/[`SPIKE_PROBES`] of the power
    /// is kept.
    pub fn from_spd(spd: Arc<dyn Spd>, scale: f32) -> Self {
        let lines: Vec<DeltaLine> = spd
            .delta_lines()
            .into_iter()
            .map(|l| DeltaLine {
                lambda: l.lambda,
                weight: l.weight * scale as f64,
            })
            .collect();
        let probe = spd.clone();
        let mut dense = Self::new(Arc::new(move |l: f32| scale * spd.value(l as f64) as f32));
        for k in 0..SPIKE_PROBES {
            let s = probe.sample((k as f64 + 0.5) / SPIKE_PROBES as f64);
            if s.is_delta {
                continue;
            }
            let x = s.lambda - DENSE_START as f64;
            if x >= 0.0 && x < (N - 1) as f64 {
                // Flag only where the interpolation misses (same test as at the midpoints), so
                // smooth SPDs keep their interpolated cells and their images do not change.
                let l = s.lambda as f32;
                let exact = (dense.outside)(l);
                let lerp = dense.value(l);
                if (exact - lerp).abs() > 2e-4 * exact.abs().max(lerp.abs()) + 1e-30 {
                    dense.exact[x as usize] = true;
                    dense.cells[x as usize] = (f32::NAN, f32::NAN);
                }
            }
        }
        dense.lines = lines;
        dense
    }

    /// Value at `lambda_nm`.
    #[inline]
    pub fn value(&self, lambda_nm: f32) -> f32 {
        let x = lambda_nm - DENSE_START;
        if x >= 0.0 && x < (N - 1) as f32 {
            // x < N − 1, so the clamp never moves i; it only proves the index in range.
            // Through `i32`: one truncating conversion, where `as usize` (f32 → u64) costs
            // about fifteen instructions; both floor the same non-negative x.
            let i = (x as i32 as usize).min(N - 2);
            if !self.exact[i] {
                let t = x - i as f32;
                let (a, d) = self.cells[i];
                return a + t * d;
            }
        }
        self.value_slow(lambda_nm)
    }

    /// [`value`](Self::value) off the interpolated grid: an exactly evaluated cell, the last
    /// node, or outside the grid. Kept out of line so the common path inlines small.
    #[cold]
    #[inline(never)]
    fn value_slow(&self, lambda_nm: f32) -> f32 {
        if lambda_nm - DENSE_START == (N - 1) as f32 {
            self.values[N - 1]
        } else {
            (self.outside)(lambda_nm)
        }
    }

    /// Values at each lane's wavelength.
    #[inline]
    pub fn eval(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        if !self.lines.is_empty() {
            return self.eval_with_lines(lambda);
        }
        // The common case (no delta lines, every lane in an interpolated cell): the four
        // lookups of `value` as one SSE vector (`glam::Vec4`) without a branch per lane. A lane
        // off the grid is interpolated at 360 nm and flagged; an exact cell yields NaN (its
        // sentinel); either sends all four lanes through `value`. The cell index is the floor
        // of x taken from the mantissa of x + 2²³ (x rounded to an integer there, one lower if
        // that rounded up): the same integer as `x as i32`, without the saturating conversion
        // per lane. Interpolated lanes are the same IEEE operations on the same numbers as in
        // `value`, so the results are the same bits.
        const ROUND: f32 = 8_388_608.0; // 2²³: x + 2²³ has no fraction bits for 0 ≤ x < 2²³
        let x = Vec4::from_array(lambda.lambda) - Vec4::splat(DENSE_START);
        let on_grid = x.cmpge(Vec4::ZERO) & x.cmplt(Vec4::splat((N - 1) as f32));
        let x = Vec4::select(on_grid, x, Vec4::ZERO);
        let rounded = x + Vec4::splat(ROUND);
        let nearest = rounded - Vec4::splat(ROUND);
        let up = nearest.cmpgt(x);
        let t = x - (nearest - Vec4::select(up, Vec4::ONE, Vec4::ZERO));
        let i = cell_indices(rounded, up);
        let cell = |k: usize| self.cells[i[k].min(N - 2)];
        let (c0, c1, c2, c3) = (cell(0), cell(1), cell(2), cell(3));
        let v = Vec4::new(c0.0, c1.0, c2.0, c3.0) + t * Vec4::new(c0.1, c1.1, c2.1, c3.1);
        if on_grid.all() && !v.is_nan_mask().any() {
            return SampledSpectrum(v.to_array());
        }
        self.eval_lanes(lambda)
    }

    /// [`eval`](Self::eval) lane by lane through [`value`](Self::value): for lanes off the
    /// grid or in an exactly evaluated cell.
    #[cold]
    #[inline(never)]
    fn eval_lanes(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let l = &lambda.lambda;
        SampledSpectrum([
            self.value(l[0]),
            self.value(l[1]),
            self.value(l[2]),
            self.value(l[3]),
        ])
    }

    /// [`eval`](Self::eval) for a spectrum with delta lines: a lane on a line gets its mass.
    #[inline(never)]
    fn eval_with_lines(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let mut out = [0.0; LANES];
        for (o, &l) in out.iter_mut().zip(&lambda.lambda) {
            let mass = line_mass_at_lane(&self.lines, l);
            *o = if mass > 0.0 {
                mass as f32
            } else {
                self.value(l)
            };
        }
        SampledSpectrum(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::spectral_texture::piecewise_linear_eval;

    /// A piecewise-linear curve with integer-nm breakpoints is reproduced exactly (1e-6, f32
    /// rounding) at arbitrary wavelengths, and the original function is used outside the grid.
    #[test]
    fn dense_copy_is_exact_for_integer_breakpoints() {
        let table = vec![
            (400.0f32, 0.0f32),
            (500.0, 8.0),
            (600.0, 15.6),
            (700.0, 18.4),
        ];
        let t2 = table.clone();
        let d = DenseSpectrum::new(Arc::new(move |l| piecewise_linear_eval(&t2, l)));
        for k in 0..1000 {
            let l = 380.0 + k as f32 * 0.3371;
            let want = piecewise_linear_eval(&table, l);
            assert!((d.value(l) - want).abs() < 1e-4 * want.max(1.0), "{l}");
        }
        // The step where the table ends (700 → 701 nm) is evaluated exactly, not smeared.
        assert_eq!(d.value(700.5), 0.0);
        assert_eq!(d.value(399.5), 0.0);
        let far = DenseSpectrum::new(Arc::new(|l| l));
        assert_eq!(far.value(900.0), 900.0);
        assert_eq!(far.value(830.0), 830.0);
    }

    /// Quantity: `eval`'s four-lane vector path against `value` lane by lane, bit for bit
    /// (images depend on it), on 20 000 wavelength quadruples over 355–835 nm (off-grid lanes,
    /// grid nodes, 830 nm itself, the cell ends either side of the step at 700 nm, which is
    /// evaluated exactly) and NaN. Tolerance: exact equality of the bits (NaN compared as
    /// NaN), since the vector path does the same IEEE operations on the same numbers.
    /// Quantity: the SSE2 cell indices against the scalar definition, exactly, for every
    /// mantissa pattern class `eval` can pass (`x + 2²³` for x over the grid and beyond, with
    /// and without the `up` correction in each lane, including the wrapped `0 − 1`) and
    /// arbitrary bit patterns: 50 000 quadruples. Exact equality, since an index off by one
    /// picks the neighbouring cell.
    #[test]
    fn vector_cell_indices_match_the_scalar_ones() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for k in 0..50_000u32 {
            let lanes: [f32; LANES] = std::array::from_fn(|i| {
                state = crate::sampler::mix64(state);
                match (k as usize + i) % 3 {
                    0 => (state % 600) as f32 * 0.8 + 8_388_608.0,
                    1 => f32::from_bits(state as u32),
                    _ => 8_388_608.0,
                }
            });
            let ups = glam::BVec4A::new(k & 1 != 0, k & 2 != 0, k & 4 != 0, k & 8 != 0);
            let r = Vec4::from_array(lanes);
            assert_eq!(
                cell_indices(r, ups),
                cell_indices_scalar(r, ups),
                "{lanes:?} {ups:?}"
            );
        }
    }

    #[test]
    fn four_lane_eval_equals_value_bit_for_bit() {
        let table = vec![
            (400.0f32, 0.5f32),
            (500.0, 8.0),
            (600.0, 15.6),
            (700.0, 18.4),
        ];
        let t2 = table.clone();
        let d = DenseSpectrum::new(Arc::new(move |l| piecewise_linear_eval(&t2, l)));
        let special = [
            360.0f32,
            361.0,
            400.0,
            699.99,
            700.0,
            700.5,
            701.0,
            829.999,
            830.0,
            830.001,
            359.999,
            f32::NAN,
        ];
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for k in 0..20_000usize {
            let mut lambda = [0.0f32; LANES];
            for (i, l) in lambda.iter_mut().enumerate() {
                *l = if (k + i) % 7 == 0 {
                    special[(k / 7 + i) % special.len()]
                } else {
                    355.0 + 480.0 * uniform()
                };
            }
            let w = SampledWavelengths {
                lambda,
                pdf: [1.0; LANES],
                lanes: crate::spectrum::LaneMask::ALL,
            };
            let got = d.eval(&w).0;
            for i in 0..LANES {
                let want = d.value(lambda[i]);
                assert!(
                    got[i].to_bits() == want.to_bits() || (got[i].is_nan() && want.is_nan()),
                    "{} nm: {} vs {}",
                    lambda[i],
                    got[i],
                    want
                );
            }
        }
    }
}

#[cfg(test)]
mod spike_tests {
    use super::*;
    use crate::spectrum::{Interpolation, TabulatedSpd};

    // A 0.02 nm wide spike at 589.3 nm lies between grid nodes and cell midpoints; the copy
    // must still return the SPD's exact value at that f32 wavelength (about 100/nm for unit area; 1e-4 relative
    // for f32) instead of 0, and a line SPD gives its mass × scale on a lane at the line.
    #[test]
    fn sub_nm_spike_and_lines_survive() {
        let spd = TabulatedSpd::new(
            "spike",
            &[589.29, 589.3, 589.31],
            &[0.0, 1.0, 0.0],
            Interpolation::Linear,
        )
        .unwrap();
        let peak = spd.value(589.3f32 as f64);
        let d = DenseSpectrum::from_spd(Arc::new(spd), 2.0);
        assert!(
            (d.value(589.3) / (2.0 * peak as f32) - 1.0).abs() < 1e-4,
            "{}",
            d.value(589.3)
        );
        let line = DenseSpectrum::from_spd(
            Arc::new(crate::spectrum::parse_spd_spec("line:589").unwrap()),
            3.0,
        );
        let w = SampledWavelengths {
            lambda: [589.0, 500.0, 589.5, 700.0],
            pdf: [1.0; LANES],
            lanes: crate::spectrum::LaneMask::ALL,
        };
        assert_eq!(line.eval(&w).0, [3.0, 0.0, 0.0, 0.0]);
    }
}
