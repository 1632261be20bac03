//! A parametric fluorescent surface as [`Reradiation`] data: an absorption (excitation)
//! spectrum × a normalised emission spectrum × a quantum yield, beside an ordinary reflectance.
//!
//! | parameter       | unit / range          | meaning                                             |
//! |-----------------|-----------------------|-----------------------------------------------------|
//! | `reflectance`   | [0, 1] per nm         | non-fluorescent reflectance ρ(λ)                   |
//! | `absorption`    | [0, 1] per nm         | fraction a(λᵢ) of the light at λᵢ the dye absorbs |
//! | `emission`      | normalised SPD (1/nm) | shape e(λₒ) of the emitted light, ∫ e = 1          |
//! | `quantum_yield` | [0, 1]                | photons emitted per photon absorbed                |
//!
//! Re-radiation (power): `r(λᵢ → λₒ) = a(λᵢ)·Q·(λᵢ/λₒ)·e(λₒ)` for λₒ > λᵢ, 0 otherwise. The
//! factor λᵢ/λₒ converts the photon yield to power (a photon at λₒ carries λᵢ/λₒ of the energy
//! of one at λᵢ); emission the Stokes rule forbids (λₒ ≤ λᵢ) is lost, not moved. Energy: the
//! re-radiated fraction is at most a(λᵢ)·Q, and the constructor requires ρ + a ≤ 1 everywhere,
//! so the albedo never exceeds 1.

use super::error::SpectrumError;
use super::reradiation::Reradiation;
use super::spd::Spd;
use super::SpectralCurve;
use std::sync::Arc;

/// Grid (nm) on which the per-excitation emission CDFs are tabulated.
const GRID_STEP_NM: f64 = 1.0;

/// Excitation × emission × quantum yield (see the module docs).
#[derive(Debug, Clone)]
pub struct FluorescenceModel {
    reflectance: SpectralCurve,
    absorption: SpectralCurve,
    emission: Arc<dyn Spd>,
    quantum_yield: f64,
    /// Emission grid nodes (nm) and the cumulative integral of (λ₀/λ)·e(λ) from the top
    /// down, so the Stokes-truncated integral for any λᵢ is one lookup.
    grid: Vec<f64>,
    tail: Vec<f64>,
    /// Excitation sampling for camera paths: 1 nm cells from `excitation_start` (nm), each
    /// with the largest a(λ)·λ at its ends and middle (so a cell is never 0 where r is not,
    /// short of sub-nm spikes in a), and their cumulative sums (nm², prefixed by 0).
    excitation_start: f64,
    excitation_cells: Vec<f64>,
    excitation_cdf: Vec<f64>,
}

impl FluorescenceModel {
    /// Build and check the model: `quantum_yield` in [0, 1], `absorption` in [0, 1] and
    /// ρ + a ≤ 1 (checked on a 1 nm grid over both curves' ranges). `label` names it in errors.
    pub fn new(
        label: &str,
        reflectance: SpectralCurve,
        absorption: SpectralCurve,
        emission: Arc<dyn Spd>,
        quantum_yield: f64,
    ) -> Result<Self, SpectrumError> {
        let invalid = |what: String| SpectrumError::Invalid {
            file: label.to_string(),
            what,
        };
        if !(0.0..=1.0).contains(&quantum_yield) {
            return Err(invalid(format!(
                "quantum_yield {quantum_yield} is outside [0, 1]"
            )));
        }
        let (lo, hi) = (
            reflectance.range().0.min(absorption.range().0).max(200.0),
            reflectance.range().1.max(absorption.range().1).min(2000.0),
        );
        let mut l = lo;
        while l <= hi {
            let (r, a) = (reflectance.value(l), absorption.value(l));
            if !(0.0..=1.0).contains(&a) || !(r >= 0.0) || r + a > 1.0 + 1e-9 {
                return Err(invalid(format!(
                    "at {l} nm reflectance {r} and absorption {a}: need 0 ≤ a ≤ 1, ρ ≥ 0 and ρ + a ≤ 1 (energy is never created)"
                )));
            }
            l += 1.0;
        }
        let (e0, e1) = emission.range();
        let n = (((e1 - e0) / GRID_STEP_NM).ceil() as usize).clamp(1, 100_000);
        let grid: Vec<f64> = (0..=n)
            .map(|k| e0 + (e1 - e0) * k as f64 / n as f64)
            .collect();
        // tail[k] = ∫_{grid[k]}^{e1} e(λ)/λ dλ (trapezoids); times λᵢ it is the power fraction.
        let mut tail = vec![0.0; n + 1];
        for k in (0..n).rev() {
            let f = |l: f64| emission.value(l) / l;
            tail[k] = tail[k + 1] + 0.5 * (f(grid[k]) + f(grid[k + 1])) * (grid[k + 1] - grid[k]);
        }
        let (a0, a1) = absorption.range();
        let excitation_start = a0.max(200.0).floor();
        let cells = ((a1.min(2000.0) - excitation_start).ceil().max(1.0)) as usize;
        let excitation_cells: Vec<f64> = (0..cells)
            .map(|k| {
                let l = excitation_start + k as f64;
                [l, l + 0.5, l + 1.0]
                    .iter()
                    .map(|&x| absorption.value(x).max(0.0) * x)
                    .fold(0.0, f64::max)
            })
            .collect();
        let mut excitation_cdf = Vec::with_capacity(cells + 1);
        excitation_cdf.push(0.0);
        for c in &excitation_cells {
            excitation_cdf.push(excitation_cdf.last().copied().unwrap_or(0.0) + c);
        }
        Ok(Self {
            reflectance,
            absorption,
            emission,
            quantum_yield,
            grid,
            tail,
            excitation_start,
            excitation_cells,
            excitation_cdf,
        })
    }

    /// ∫_{λᵢ}^{∞} e(λ)/λ dλ, interpolated on the grid.
    fn tail_above(&self, lambda_i: f64) -> f64 {
        let (g0, g1) = (self.grid[0], self.grid[self.grid.len() - 1]);
        if lambda_i <= g0 {
            return self.tail[0];
        }
        if lambda_i >= g1 {
            return 0.0;
        }
        let x = (lambda_i - g0) / (g1 - g0) * (self.grid.len() - 1) as f64;
        let k = (x as usize).min(self.grid.len() - 2);
        let t = x - k as f64;
        self.tail[k] * (1.0 - t) + self.tail[k + 1] * t
    }
}

impl Reradiation for FluorescenceModel {
    fn reflectance(&self, lambda_nm: f64) -> f64 {
        self.reflectance.value(lambda_nm)
    }

    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        if !(lambda_o_nm > lambda_i_nm) {
            return 0.0;
        }
        self.absorption.value(lambda_i_nm)
            * self.quantum_yield
            * (lambda_i_nm / lambda_o_nm)
            * self.emission.value(lambda_o_nm)
    }

    fn reradiated_fraction(&self, lambda_i_nm: f64) -> f64 {
        self.absorption.value(lambda_i_nm)
            * self.quantum_yield
            * lambda_i_nm
            * self.tail_above(lambda_i_nm)
    }

    /// Draws λₒ from the emission SPD restricted to λₒ > λᵢ by rejection-free inversion of
    /// the SPD's own sampler over the allowed quantiles; the density is that of the emission
    /// SPD renormalised to the allowed part (the λᵢ/λₒ factor is left to the weight: it is
    /// within a few percent of constant over an emission band).
    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> Option<(f64, f64)> {
        if !(self.reradiated_fraction(lambda_i_nm) > 0.0) {
            return None;
        }
        let allowed = self.allowed_mass(lambda_i_nm);
        if !(allowed > 0.0) {
            return None;
        }
        // Quantiles of e above λᵢ are [1 − allowed, 1).
        let s = self
            .emission
            .sample(1.0 - allowed + u.clamp(0.0, 1.0) * allowed);
        if !(s.lambda > lambda_i_nm) || s.is_delta {
            return None;
        }
        Some((s.lambda, self.emission.pdf(s.lambda) / allowed))
    }

    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        if !(lambda_o_nm > lambda_i_nm) || !(self.reradiated_fraction(lambda_i_nm) > 0.0) {
            return 0.0;
        }
        let allowed = self.allowed_mass(lambda_i_nm);
        if allowed > 0.0 {
            self.emission.pdf(lambda_o_nm) / allowed
        } else {
            0.0
        }
    }

    /// Q·e(λₒ)/λₒ · ∫_{λ<λₒ} a(λ)·λ dλ, the integral taken on the sampling cells (an
    /// overestimate of at most the cells' rounding; it only steers the choice).
    fn excitation_fraction(&self, lambda_o_nm: f64) -> f64 {
        let e = self.emission.value(lambda_o_nm);
        if !(e > 0.0) || !(lambda_o_nm > 0.0) {
            return 0.0;
        }
        self.quantum_yield * e / lambda_o_nm * self.excitation_mass_below(lambda_o_nm)
    }

    /// λᵢ < λₒ from the cells' a·λ (piecewise constant, the cell holding λₒ cut there); the
    /// density is that of the cells, so weights r/pdf are exact.
    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> Option<(f64, f64)> {
        if !(self.emission.value(lambda_o_nm) > 0.0) || !(self.quantum_yield > 0.0) {
            return None;
        }
        let total = self.excitation_mass_below(lambda_o_nm);
        if !(total > 0.0) {
            return None;
        }
        let target = u.clamp(0.0, 1.0 - f64::EPSILON) * total;
        // First cell whose cumulative end exceeds the target.
        let k = self
            .excitation_cdf
            .partition_point(|&c| c <= target)
            .saturating_sub(1)
            .min(self.excitation_cells.len() - 1);
        let c = self.excitation_cells[k];
        if !(c > 0.0) {
            return None;
        }
        let lambda_i = (self.excitation_start + k as f64 + (target - self.excitation_cdf[k]) / c)
            .min(lambda_o_nm);
        if !(lambda_i < lambda_o_nm) {
            return None;
        }
        Some((lambda_i, c / total))
    }

    /// The density of the cell holding λᵢ (cut at λₒ), as drawn above.
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> f64 {
        if !(lambda_i_nm < lambda_o_nm)
            || !(self.emission.value(lambda_o_nm) > 0.0)
            || !(self.quantum_yield > 0.0)
        {
            return 0.0;
        }
        let total = self.excitation_mass_below(lambda_o_nm);
        let x = lambda_i_nm - self.excitation_start;
        if !(total > 0.0) || !(x >= 0.0) {
            return 0.0;
        }
        self.excitation_cells
            .get(x.floor() as usize)
            .map_or(0.0, |c| c / total)
    }

    fn range(&self) -> (f64, f64) {
        let (a0, a1) = self.absorption.range();
        let (e0, e1) = self.emission.range();
        (a0.min(e0), a1.max(e1))
    }
}

impl FluorescenceModel {
    /// Mass (nm²) of the excitation cells below `lambda_o` (the cell holding it cut there).
    fn excitation_mass_below(&self, lambda_o: f64) -> f64 {
        let x = lambda_o - self.excitation_start;
        if !(x > 0.0) {
            return 0.0;
        }
        let n = self.excitation_cells.len();
        let k = x.floor() as usize;
        if k >= n {
            return self.excitation_cdf[n];
        }
        self.excitation_cdf[k] + self.excitation_cells[k] * (x - k as f64)
    }

    /// ∫_{λᵢ}^{∞} e(λ) dλ: the emission SPD's mass above λᵢ (trapezoids on the grid).
    fn allowed_mass(&self, lambda_i: f64) -> f64 {
        let mut m = 0.0;
        for w in self.grid.windows(2) {
            let (a, b) = (w[0].max(lambda_i), w[1]);
            if b > a {
                m += 0.5 * (self.emission.value(a) + self.emission.value(b)) * (b - a);
            }
        }
        m.min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::parse_spd_spec;

    fn model() -> FluorescenceModel {
        // Absorbs 0.6 of 350–450 nm, emits a Gaussian at 520 nm (FWHM 40), Q = 0.8, ρ = 0.3.
        let absorption =
            SpectralCurve::tabulated(vec![340.0, 350.0, 450.0, 460.0], vec![0.0, 0.6, 0.6, 0.0])
                .unwrap();
        FluorescenceModel::new(
            "test",
            SpectralCurve::Constant(0.3),
            absorption,
            Arc::new(parse_spd_spec("gaussian:520:40").unwrap()),
            0.8,
        )
        .unwrap()
    }

    // ∫ r(λᵢ → λₒ) dλₒ (midpoint rule, 0.05 nm) equals reradiated_fraction to 1e-3 relative
    // (the fraction uses 1 nm trapezoids on a smooth Gaussian/λ), and stays below a·Q = 0.48:
    // energy is never created. At 400 nm the whole emission band is allowed, so the fraction
    // is 0.48·400·E[1/λ] ≈ 0.48·400/520 to the Gaussian's spread (2%).
    #[test]
    fn fraction_is_the_integral_of_the_density() {
        let m = model();
        for li in [360.0, 400.0, 440.0] {
            let integral: f64 = (0..12_000)
                .map(|k| m.reradiation(li, 300.0 + (k as f64 + 0.5) * 0.05))
                .sum::<f64>()
                * 0.05;
            let f = m.reradiated_fraction(li);
            assert!((integral / f - 1.0).abs() < 1e-3, "{li}: {integral} vs {f}");
            assert!(m.albedo(li) <= 1.0);
        }
        let f = m.reradiated_fraction(400.0);
        assert!((f / (0.48 * 400.0 / 520.0) - 1.0).abs() < 0.02, "{f}");
    }

    // Emission sampling: the returned density equals emission_pdf and integrates to 1 over
    // λₒ > λᵢ (0.05 nm midpoint rule, 1e-3).
    #[test]
    fn sampling_density_is_consistent() {
        let m = model();
        for li in [400.0, 450.0] {
            for k in 0..50 {
                let (l, p) = m.sample_emission(li, (k as f64 + 0.5) / 50.0).unwrap();
                assert!(l > li);
                assert!((p / m.emission_pdf(li, l) - 1.0).abs() < 1e-9);
            }
            let total: f64 = (0..12_000)
                .map(|k| m.emission_pdf(li, 300.0 + (k as f64 + 0.5) * 0.05))
                .sum::<f64>()
                * 0.05;
            assert!((total - 1.0).abs() < 1e-3, "{li}: {total}");
        }
    }

    // Excitation sampling (camera paths) is unbiased: for λₒ = 520 nm the mean of r/pdf over
    // 20 000 stratified draws equals ∫ r(λᵢ → 520) dλᵢ summed on 0.01 nm cells within 0.1%
    // (the weight varies only with a(λ)·λ inside a 1 nm cell); every draw lies below λₒ, and
    // excitation_fraction (the cells' overestimate, used only for the keep/shift choice) is
    // above the integral by at most 1.5%: each cell takes the largest a·λ of its ends and
    // middle, which on this model's two 10 nm absorption ramps (slope 0.06/nm) exceeds the
    // cell's mean by ≈ 0.03·λ per cell, ≈ 0.9% of the integral, plus ≈ 0.1% from λ's growth
    // across the plateau's cells (measured 1.02%).
    #[test]
    fn excitation_sampling_is_unbiased() {
        let m = model();
        let lo = 520.0;
        let want: f64 = (0..30_000)
            .map(|k| m.reradiation(200.0 + (k as f64 + 0.5) * 0.01, lo))
            .sum::<f64>()
            * 0.01;
        let n = 20_000;
        let mut sum = 0.0;
        for k in 0..n {
            let (l, p) = m
                .sample_excitation(lo, (k as f64 + 0.5) / n as f64)
                .unwrap();
            assert!(l < lo && p > 0.0);
            assert!((m.excitation_pdf(lo, l) / p - 1.0).abs() < 1e-9, "{l}: {p}");
            sum += m.reradiation(l, lo) / p;
        }
        let got = sum / n as f64;
        assert!((got / want - 1.0).abs() < 1e-3, "{got} vs {want}");
        let f = m.excitation_fraction(lo);
        assert!(
            f >= want * (1.0 - 1e-9) && f < want * 1.015,
            "{f} vs {want}"
        );
        assert!(m.sample_excitation(300.0, 0.5).is_none());
    }

    // Parameters that would create energy are refused with the wavelength named.
    #[test]
    fn energy_creating_parameters_are_refused() {
        let e = FluorescenceModel::new(
            "bad",
            SpectralCurve::Constant(0.7),
            SpectralCurve::Constant(0.5),
            Arc::new(parse_spd_spec("gaussian:520:40").unwrap()),
            0.8,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("bad") && e.contains("ρ + a ≤ 1"), "{e}");
    }
}
