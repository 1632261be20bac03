//! A piecewise-constant 2D distribution over the unit square, for importance sampling a
//! tabulated function (an environment map's luminance × solid angle, a sky model's radiance):
//! `nu × nv` cells of non-negative weights; a cell is drawn with probability proportional to
//! its weight (its row from the marginal, then its column from the row's conditional), the
//! point uniformly inside it. Densities are with respect to area on [0, 1]².
//!
//! Inversion is exact in f64 for the cumulative sums; every cell of positive weight has
//! positive probability, cells of zero weight are never drawn. [`Distribution2D::invert`] maps
//! a cell and an offset in it back to the numbers that draw them (the marginal's cumulative
//! sum up to the row plus the offset times the row's probability, likewise for the column in
//! the row's conditional), so a caller can find the sample numbers of a point it was given.

use glam::Vec2;

/// One 1D piecewise-constant distribution on [0, 1) with `n` equal cells.
#[derive(Clone, Debug, PartialEq)]
struct Distribution1D {
    /// Cumulative weights, `cdf[0] = 0`, `cdf[n] = 1` (normalised).
    cdf: Vec<f64>,
    /// Sum of the weights before normalisation.
    total: f64,
}

impl Distribution1D {
    fn new(w: &[f64]) -> Self {
        let mut cdf = Vec::with_capacity(w.len() + 1);
        let mut acc = 0.0;
        cdf.push(0.0);
        for &v in w {
            acc += v;
            cdf.push(acc);
        }
        if acc > 0.0 {
            for c in &mut cdf {
                *c /= acc;
            }
        }
        Self { cdf, total: acc }
    }

    fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// Probability of cell `i`.
    fn p(&self, i: usize) -> f64 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// Cell and the offset in it `[0, 1)` for `u ∈ [0, 1)`.
    fn sample(&self, u: f64) -> (usize, f64) {
        let n = self.len();
        // The last cell with cdf ≤ u and positive probability.
        let mut i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 1);
        while i > 0 && self.p(i) <= 0.0 {
            i -= 1;
        }
        while i + 1 < n && self.p(i) <= 0.0 {
            i += 1;
        }
        let p = self.p(i);
        let off = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, 1.0)
        } else {
            0.5
        };
        (i, off.min(1.0 - f64::EPSILON))
    }

    /// The number in [0, 1] that [`sample`](Self::sample) turns into cell `i` at offset `off`.
    fn invert(&self, i: usize, off: f64) -> f64 {
        self.cdf[i] + off.clamp(0.0, 1.0) * self.p(i)
    }
}

/// The 2D distribution (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    nu: usize,
    nv: usize,
    /// Per row v, the distribution over its columns u.
    conditional: Vec<Distribution1D>,
    /// Over the rows.
    marginal: Distribution1D,
}

/// A drawn point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample2D {
    /// The point in [0, 1)².
    pub uv: Vec2,
    /// Its cell (column, row).
    pub cell: (usize, usize),
    /// The offset inside the cell, [0, 1)² (what a caller that maps cells non-linearly uses).
    pub offset: (f64, f64),
    /// Probability of the cell.
    pub cell_probability: f64,
}

impl Distribution2D {
    /// From row-major weights (`nv` rows of `nu`, row `j` covering `v ∈ [j/nv, (j+1)/nv)`).
    /// `None` when the sizes do not match, a weight is negative or not finite, or all are 0.
    pub fn new(weights: &[f64], nu: usize, nv: usize) -> Option<Self> {
        if nu == 0 || nv == 0 || weights.len() != nu.checked_mul(nv)? {
            return None;
        }
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return None;
        }
        let conditional: Vec<Distribution1D> =
            weights.chunks(nu).map(Distribution1D::new).collect();
        let rows: Vec<f64> = conditional.iter().map(|c| c.total).collect();
        let marginal = Distribution1D::new(&rows);
        (marginal.total > 0.0 && marginal.total.is_finite()).then_some(Self {
            nu,
            nv,
            conditional,
            marginal,
        })
    }

    /// `(nu, nv)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// Draw a point with `u ∈ [0, 1)²`.
    pub fn sample(&self, u: Vec2) -> Sample2D {
        let (j, ov) = self.marginal.sample(u.y as f64);
        let (i, ou) = self.conditional[j].sample(u.x as f64);
        let p = self.marginal.p(j) * self.conditional[j].p(i);
        Sample2D {
            uv: Vec2::new(
                ((i as f64 + ou) / self.nu as f64) as f32,
                ((j as f64 + ov) / self.nv as f64) as f32,
            ),
            cell: (i, j),
            offset: (ou, ov),
            cell_probability: p,
        }
    }

    /// The numbers `u` with which [`sample`](Self::sample) draws cell `(i, j)` at offset
    /// `offset` (in [0, 1]², clamped): the inverse of the draw, exact up to f32 rounding of
    /// the result. `None` for a cell outside the grid or of probability 0 (never drawn).
    pub fn invert(&self, (i, j): (usize, usize), offset: (f64, f64)) -> Option<Vec2> {
        if !(self.cell_probability(i, j) > 0.0) {
            return None;
        }
        let y = self.marginal.invert(j, offset.1);
        let x = self.conditional[j].invert(i, offset.0);
        // `sample` takes u in [0, 1): the top edge of the last cell is the same point as its
        // last representable number.
        let below_one = |v: f64| (v as f32).min(1.0 - f32::EPSILON / 2.0);
        Some(Vec2::new(below_one(x), below_one(y)))
    }

    /// Probability of cell `(i, j)`.
    pub fn cell_probability(&self, i: usize, j: usize) -> f64 {
        if i >= self.nu || j >= self.nv {
            return 0.0;
        }
        self.marginal.p(j) * self.conditional[j].p(i)
    }

    /// Density (per unit area of [0, 1]²) at `uv` (0 outside).
    pub fn pdf(&self, uv: Vec2) -> f64 {
        if !(uv.x >= 0.0 && uv.x < 1.0 && uv.y >= 0.0 && uv.y < 1.0) {
            return 0.0;
        }
        let i = ((uv.x * self.nu as f32) as usize).min(self.nu - 1);
        let j = ((uv.y * self.nv as f32) as usize).min(self.nv - 1);
        self.cell_probability(i, j) * (self.nu * self.nv) as f64
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        (self.nu + 1) * self.nv * 8 + (self.nv + 1) * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each cell is drawn with its weight's share: 200k stratified draws over a 4 × 3 grid
    /// with a zero cell, counts against expectations by Pearson's chi-square (11 non-empty cells, 10 degrees
    /// of freedom: 99.9% quantile 29.59), never the zero cell; `pdf`
    /// integrates to 1 over the square (exact: a sum over cells, 1e-12).
    #[test]
    fn draws_follow_the_weights() {
        let w = [1.0, 2.0, 0.0, 4.0, 0.5, 0.5, 3.0, 1.0, 8.0, 1.0, 1.0, 2.0];
        let d = Distribution2D::new(&w, 4, 3).unwrap();
        let total: f64 = w.iter().sum();
        let n = 200_000usize;
        let mut counts = [0usize; 12];
        let mut state = 12345u64;
        for _ in 0..n {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let a = (state >> 40) as f32 / (1u64 << 24) as f32;
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let b = (state >> 40) as f32 / (1u64 << 24) as f32;
            let s = d.sample(Vec2::new(a, b));
            counts[s.cell.1 * 4 + s.cell.0] += 1;
            assert!((s.cell_probability - w[s.cell.1 * 4 + s.cell.0] / total).abs() < 1e-12);
            assert!((d.pdf(s.uv) - s.cell_probability * 12.0).abs() < 1e-9);
        }
        assert_eq!(counts[2], 0);
        let chi2: f64 = (0..12)
            .filter(|&k| w[k] > 0.0)
            .map(|k| {
                let e = n as f64 * w[k] / total;
                (counts[k] as f64 - e).powi(2) / e
            })
            .sum();
        assert!(chi2 < 29.59, "chi2 {chi2}, counts {counts:?}");
        let integral: f64 = (0..3)
            .flat_map(|j| (0..4).map(move |i| (i, j)))
            .map(|(i, j)| d.pdf(Vec2::new((i as f32 + 0.5) / 4.0, (j as f32 + 0.5) / 3.0)) / 12.0)
            .sum();
        assert!((integral - 1.0).abs() < 1e-12);
        assert!(Distribution2D::new(&[0.0; 4], 2, 2).is_none());
        assert!(Distribution2D::new(&[1.0, -1.0], 2, 1).is_none());
    }

    /// `invert` undoes `sample`: for 10 000 points `u` of a stratified grid over the lopsided
    /// 4 × 3 weights above (a zero cell, probabilities from 0.02 to 0.33), the cell and offset
    /// drawn are mapped back to `u` to 1e-6 (the draw is f64 throughout; the only rounding is
    /// the f32 of `u`, 6e-8, divided by no probability: the inverse multiplies by it); the zero
    /// cell and cells outside the grid have no numbers.
    #[test]
    fn invert_undoes_sample() {
        let w = [1.0, 2.0, 0.0, 4.0, 0.5, 0.5, 3.0, 1.0, 8.0, 1.0, 1.0, 2.0];
        let d = Distribution2D::new(&w, 4, 3).unwrap();
        let n = 100;
        let mut worst = 0.0f32;
        for a in 0..n {
            for b in 0..n {
                let u = Vec2::new((a as f32 + 0.37) / n as f32, (b as f32 + 0.61) / n as f32);
                let s = d.sample(u);
                let back = d.invert(s.cell, s.offset).unwrap();
                worst = worst.max((back - u).abs().max_element());
            }
        }
        assert!(worst < 1e-6, "largest round-trip error {worst}");
        assert!(d.invert((2, 0), (0.5, 0.5)).is_none());
        assert!(d.invert((4, 0), (0.5, 0.5)).is_none());
        assert!(d.invert((0, 3), (0.5, 0.5)).is_none());
        assert!(Distribution2D::new(&[1.0, -1.0], 2, 1).is_none());
    }
}
