//! A piecewise-constant importance sampler of directions over a hemisphere, tabulated on a
//! grid of `nu` bands in μ = cos Z (equal solid angle each: dω = dμ dα) by `na` sectors in
//! azimuth α. Kept small and on its own so it can later be unified with the latitude–longitude
//! sampler of image-based environment lights.
//!
//! Each cell's weight is the function at its centre plus 2 % of the mean (so a cell whose
//! centre happens to be dark still gets samples: the estimator stays unbiased wherever the
//! function is positive). The density per solid angle is `P(cell) / ω_cell`, ω_cell = 2π/(nu·na).

use std::f64::consts::PI;

/// The sampler (see the module docs).
#[derive(Clone, Debug)]
pub struct HemisphereSampler {
    nu: usize,
    na: usize,
    /// Row marginal CDF (nu + 1 entries, last = 1).
    row_cdf: Vec<f64>,
    /// Per row, the conditional CDF over its sectors (na + 1 entries each).
    col_cdf: Vec<f64>,
    /// Cell probabilities, row-major.
    prob: Vec<f64>,
}

impl HemisphereSampler {
    /// Tabulate `f(μ, α)` ≥ 0 on `nu × na` cells. `None` when `f` is zero everywhere.
    pub fn new(nu: usize, na: usize, f: impl Fn(f64, f64) -> f64) -> Option<Self> {
        let (nu, na) = (nu.max(1), na.max(1));
        let mut w = vec![0.0; nu * na];
        for i in 0..nu {
            let mu = (i as f64 + 0.5) / nu as f64;
            for j in 0..na {
                let a = 2.0 * PI * (j as f64 + 0.5) / na as f64;
                let v = f(mu, a);
                w[i * na + j] = if v.is_finite() { v.max(0.0) } else { 0.0 };
            }
        }
        let total: f64 = w.iter().sum();
        if !(total > 0.0) {
            return None;
        }
        let floor = 0.02 * total / w.len() as f64;
        w.iter_mut().for_each(|x| *x += floor);
        let total: f64 = w.iter().sum();
        let prob: Vec<f64> = w.iter().map(|x| x / total).collect();
        let mut row_cdf = vec![0.0; nu + 1];
        let mut col_cdf = vec![0.0; nu * (na + 1)];
        for i in 0..nu {
            let row = &prob[i * na..(i + 1) * na];
            let rs: f64 = row.iter().sum();
            row_cdf[i + 1] = row_cdf[i] + rs;
            let c = &mut col_cdf[i * (na + 1)..(i + 1) * (na + 1)];
            for j in 0..na {
                c[j + 1] = c[j] + row[j] / rs;
            }
            c[na] = 1.0;
        }
        row_cdf[nu] = 1.0;
        Some(Self {
            nu,
            na,
            row_cdf,
            col_cdf,
            prob,
        })
    }

    /// Draw (μ, α) from two uniform numbers; returns them with the solid-angle density (1/sr).
    pub fn sample(&self, u0: f64, u1: f64) -> (f64, f64, f64) {
        let pick = |cdf: &[f64], u: f64| -> (usize, f64) {
            let n = cdf.len() - 1;
            let k = cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
            let width = cdf[k + 1] - cdf[k];
            let t = if width > 0.0 {
                (u - cdf[k]) / width
            } else {
                0.5
            };
            (k, t.clamp(1e-9, 1.0 - 1e-9))
        };
        let (i, ti) = pick(&self.row_cdf, u0);
        let (j, tj) = pick(
            &self.col_cdf[i * (self.na + 1)..(i + 1) * (self.na + 1)],
            u1,
        );
        let mu = (i as f64 + ti) / self.nu as f64;
        let a = 2.0 * PI * (j as f64 + tj) / self.na as f64;
        (mu, a, self.pdf_cell(i, j))
    }

    /// The numbers `(u0, u1)` with which [`sample`](Self::sample) draws (μ, α): the row's
    /// cumulative probability plus the offset in the band times its probability, likewise for
    /// the sector in the row. `None` below the horizon (μ ≤ 0, never drawn).
    pub fn coords(&self, mu: f64, a: f64) -> Option<(f64, f64)> {
        if !(mu > 0.0 && mu <= 1.0) {
            return None;
        }
        let gi = mu * self.nu as f64;
        let i = (gi as usize).min(self.nu - 1);
        let ga = a.rem_euclid(2.0 * PI) / (2.0 * PI) * self.na as f64;
        let j = (ga as usize).min(self.na - 1);
        let along =
            |cdf: &[f64], k: usize, t: f64| cdf[k] + t.clamp(0.0, 1.0) * (cdf[k + 1] - cdf[k]);
        let col = &self.col_cdf[i * (self.na + 1)..(i + 1) * (self.na + 1)];
        Some((
            along(&self.row_cdf, i, gi - i as f64),
            along(col, j, ga - j as f64),
        ))
    }

    fn pdf_cell(&self, i: usize, j: usize) -> f64 {
        self.prob[i * self.na + j] * (self.nu * self.na) as f64 / (2.0 * PI)
    }

    /// The solid-angle density (1/sr) of the direction (μ, α); 0 below the horizon (μ ≤ 0).
    pub fn pdf(&self, mu: f64, a: f64) -> f64 {
        if !(mu > 0.0 && mu <= 1.0) {
            return 0.0;
        }
        let i = ((mu * self.nu as f64) as usize).min(self.nu - 1);
        let a = a.rem_euclid(2.0 * PI);
        let j = ((a / (2.0 * PI) * self.na as f64) as usize).min(self.na - 1);
        self.pdf_cell(i, j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The density integrates to 1 over the hemisphere (midpoint sum, exact for a piecewise
    /// constant density up to rounding: 1e-9), and a sample's reported density is `pdf` at it.
    #[test]
    fn density_is_normalised_and_consistent() {
        let s = HemisphereSampler::new(16, 64, |mu, a| mu * mu + 0.3 * a.cos().max(0.0)).unwrap();
        let (n, m) = (160, 640);
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..m {
                let mu = (i as f64 + 0.5) / n as f64;
                let a = 2.0 * PI * (j as f64 + 0.5) / m as f64;
                sum += s.pdf(mu, a);
            }
        }
        let integral = sum * (1.0 / n as f64) * (2.0 * PI / m as f64);
        assert!((integral - 1.0).abs() < 1e-9, "{integral}");
        for k in 0..500 {
            let u0 = (k as f64 * 0.618_034).fract();
            let u1 = (k as f64 * 0.414_214 + 0.2).fract();
            let (mu, a, p) = s.sample(u0, u1);
            assert!((s.pdf(mu, a) / p - 1.0).abs() < 1e-12);
        }
        assert!(HemisphereSampler::new(4, 4, |_, _| 0.0).is_none());
    }
}
