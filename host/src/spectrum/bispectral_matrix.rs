//! A measured bispectral (Donaldson) matrix as [`Reradiation`] data.
//!
//! # Cleaning rule
//! Measured matrices are noisy (see `host/data/fluorescence/README.md`). On reading:
//! - the diagonal (λₒ = λᵢ) is the reflectance; negative entries become 0;
//! - an off-diagonal entry is kept only where the emission wavelength is longer than the
//!   excitation wavelength (λₒ > λᵢ: no anti-Stokes emission) and the value is positive;
//!   every other off-diagonal entry becomes 0.
//!
//! What was removed is counted in [`CleaningReport`] (`spectrace color FILE.BFC` prints it).
//!
//! # Continuous model
//! The file samples D(λₒ, λᵢ) on a grid with steps Δλₒ (rows) and Δλᵢ (columns); a column is
//! the response to the light received in an excitation band of width Δλᵢ around λᵢ, so under
//! an illuminant E: `S(λₒ) = Σᵢ D(λₒ, λᵢ)·E(λᵢ)`. Here:
//! - ρ(λ) is the cleaned diagonal, linearly interpolated, 0 outside the rows' range;
//! - r(λᵢ → λₒ) = D(row of λₒ, column of λᵢ) / Δλᵢ (1/nm), constant over each cell
//!   `[λ − Δ/2, λ + Δ/2)` around the grid nodes, and 0 in a cell whose row and column are the
//!   same wavelength (that cell is the reflectance). Then ∫E(λᵢ)r dλᵢ reproduces the sum above
//!   for an illuminant constant over each band, and ∫ r dλₒ = Σₒ D(λₒ, λᵢ)·Δλₒ/Δλᵢ.
//!
//! # Energy
//! [`BispectralMatrix::max_albedo`] is the largest ρ(λᵢ) + ∫ r dλₒ over the columns after
//! cleaning. A matrix above 1 would create energy; it is refused with the excess named, since
//! no renormalisation is right for every use and the bundled files do not need one (their
//! largest albedo is 0.958: HERPICER.BFC at 760 nm, where the red pigment reflects most).

use super::bfc::BfcFile;
use super::error::SpectrumError;
use super::reradiation::Reradiation;

/// What the cleaning rule removed from a matrix.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CleaningReport {
    /// Negative diagonal entries set to 0.
    pub negative_reflectance: usize,
    /// Off-diagonal entries with λₒ > λᵢ that were negative (set to 0).
    pub negative_fluorescence: usize,
    /// Non-zero entries with λₒ < λᵢ (set to 0).
    pub anti_stokes: usize,
    /// Sum of the positive values among the anti-Stokes entries removed.
    pub anti_stokes_sum: f64,
}

/// A cleaned bispectral matrix (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BispectralMatrix {
    label: String,
    sample: String,
    emission_nm: Vec<f64>,
    excitation_nm: Vec<f64>,
    step_o: f64,
    step_i: f64,
    /// Off-diagonal fluorescence D(λₒ, λᵢ), cleaned; row-major (rows = emission).
    fluo: Vec<f64>,
    /// Cleaned diagonal per emission row (0 where the row has no matching column).
    reflectance: Vec<f64>,
    /// Per column: Σₒ fluo·Δλₒ/Δλᵢ = ∫ r dλₒ.
    column_fraction: Vec<f64>,
    report: CleaningReport,
}

impl BispectralMatrix {
    /// Read and clean a `.BFC` file.
    pub fn read(path: &std::path::Path) -> Result<Self, SpectrumError> {
        Self::from_bfc(&BfcFile::read(path)?)
    }

    /// Clean a parsed file. Fails when the grid is not usable or the cleaned matrix would
    /// create energy (see the module docs).
    pub fn from_bfc(f: &BfcFile) -> Result<Self, SpectrumError> {
        let invalid = |what: String| SpectrumError::Invalid {
            file: f.label.clone(),
            what,
        };
        let (no, ni) = (f.emission_nm.len(), f.excitation_nm.len());
        if no < 2 || ni < 1 || f.values.len() != no * ni {
            return Err(invalid(format!("a {no}×{ni} grid is too small")));
        }
        let step_o = f.emission_nm[1] - f.emission_nm[0];
        let step_i = if ni > 1 {
            f.excitation_nm[1] - f.excitation_nm[0]
        } else {
            step_o
        };
        let mut report = CleaningReport::default();
        let mut fluo = vec![0.0; no * ni];
        let mut reflectance = vec![0.0; no];
        for (o, &lo) in f.emission_nm.iter().enumerate() {
            for (i, &li) in f.excitation_nm.iter().enumerate() {
                let d = f.values[o * ni + i];
                if (lo - li).abs() < 1e-6 {
                    if d < 0.0 {
                        report.negative_reflectance += 1;
                    }
                    reflectance[o] = d.max(0.0);
                } else if lo > li {
                    if d > 0.0 {
                        fluo[o * ni + i] = d;
                    } else if d < 0.0 {
                        report.negative_fluorescence += 1;
                    }
                } else if d != 0.0 {
                    report.anti_stokes += 1;
                    report.anti_stokes_sum += d.max(0.0);
                }
            }
        }
        let column_fraction: Vec<f64> = (0..ni)
            .map(|i| (0..no).map(|o| fluo[o * ni + i]).sum::<f64>() * step_o / step_i)
            .collect();
        let m = Self {
            label: f.label.clone(),
            sample: f.sample.clone(),
            emission_nm: f.emission_nm.clone(),
            excitation_nm: f.excitation_nm.clone(),
            step_o,
            step_i,
            fluo,
            reflectance,
            column_fraction,
            report,
        };
        let (worst, at) = m.max_albedo();
        if worst > 1.0 {
            return Err(invalid(format!(
                "after cleaning, excitation at {at} nm returns {worst:.4} of the incident power \
                 (reflected + re-radiated), {:.4} more than it receives: the matrix would create energy",
                worst - 1.0
            )));
        }
        Ok(m)
    }

    /// The sample's description from the file.
    pub fn sample(&self) -> &str {
        &self.sample
    }

    /// What the cleaning removed.
    pub fn cleaning(&self) -> CleaningReport {
        self.report
    }

    /// Emission (row) wavelengths in nm.
    pub fn emission_nm(&self) -> &[f64] {
        &self.emission_nm
    }

    /// Excitation (column) wavelengths in nm.
    pub fn excitation_nm(&self) -> &[f64] {
        &self.excitation_nm
    }

    /// The largest albedo ρ(λᵢ) + ∫ r dλₒ over the excitation columns, and its λᵢ (nm).
    pub fn max_albedo(&self) -> (f64, f64) {
        self.excitation_nm
            .iter()
            .map(|&l| (self.albedo(l), l))
            .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
    }

    /// Cell index of `lambda` on a grid starting at `first` with `step`, `n` cells.
    fn cell(lambda: f64, first: f64, step: f64, n: usize) -> Option<usize> {
        let x = (lambda - first) / step + 0.5;
        (x >= 0.0 && x < n as f64).then_some(x as usize)
    }

    fn column(&self, lambda_i: f64) -> Option<usize> {
        Self::cell(
            lambda_i,
            self.excitation_nm[0],
            self.step_i,
            self.excitation_nm.len(),
        )
    }

    fn row(&self, lambda_o: f64) -> Option<usize> {
        Self::cell(
            lambda_o,
            self.emission_nm[0],
            self.step_o,
            self.emission_nm.len(),
        )
    }
}

impl Reradiation for BispectralMatrix {
    fn reflectance(&self, lambda_nm: f64) -> f64 {
        let (first, n) = (self.emission_nm[0], self.emission_nm.len());
        let x = (lambda_nm - first) / self.step_o;
        if !(x >= 0.0 && x <= (n - 1) as f64) {
            return 0.0;
        }
        let k = (x as usize).min(n - 2);
        let t = x - k as f64;
        self.reflectance[k] * (1.0 - t) + self.reflectance[k + 1] * t
    }

    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        match (self.column(lambda_i_nm), self.row(lambda_o_nm)) {
            (Some(i), Some(o)) => self.fluo[o * self.excitation_nm.len() + i] / self.step_i,
            _ => 0.0,
        }
    }

    fn reradiated_fraction(&self, lambda_i_nm: f64) -> f64 {
        self.column(lambda_i_nm)
            .map_or(0.0, |i| self.column_fraction[i])
    }

    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> Option<(f64, f64)> {
        let i = self.column(lambda_i_nm)?;
        let ni = self.excitation_nm.len();
        let total: f64 = (0..self.emission_nm.len())
            .map(|o| self.fluo[o * ni + i])
            .sum();
        if !(total > 0.0) {
            return None;
        }
        // Row by weight, then uniform within the row's band.
        let target = u.clamp(0.0, 1.0) * total;
        let mut acc = 0.0;
        let mut chosen = None;
        for o in 0..self.emission_nm.len() {
            let w = self.fluo[o * ni + i];
            if w > 0.0 {
                chosen = Some((o, acc, w));
                if acc + w > target {
                    break;
                }
            }
            acc += w;
        }
        let (o, start, w) = chosen?;
        let t = ((target - start) / w).clamp(0.0, 1.0 - f64::EPSILON);
        let lambda_o = self.emission_nm[o] + (t - 0.5) * self.step_o;
        Some((lambda_o, w / (total * self.step_o)))
    }

    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        let f = self.reradiated_fraction(lambda_i_nm);
        if !(f > 0.0) {
            return 0.0;
        }
        // r integrates to f over λₒ, so r/f is the sampling density.
        self.reradiation(lambda_i_nm, lambda_o_nm) / f
    }

    /// Σᵢ D(row of λₒ, i): r is D/Δλᵢ over each column cell of width Δλᵢ.
    fn excitation_fraction(&self, lambda_o_nm: f64) -> f64 {
        let Some(o) = self.row(lambda_o_nm) else {
            return 0.0;
        };
        let ni = self.excitation_nm.len();
        self.fluo[o * ni..(o + 1) * ni].iter().sum()
    }

    /// Column by weight D(row, i), then uniform within the column's band: density exactly
    /// r(λᵢ → λₒ)/∫ r dλᵢ.
    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> Option<(f64, f64)> {
        let o = self.row(lambda_o_nm)?;
        let ni = self.excitation_nm.len();
        let row = &self.fluo[o * ni..(o + 1) * ni];
        let total: f64 = row.iter().sum();
        if !(total > 0.0) {
            return None;
        }
        let target = u.clamp(0.0, 1.0) * total;
        let mut acc = 0.0;
        let mut chosen = None;
        for (i, &w) in row.iter().enumerate() {
            if w > 0.0 {
                chosen = Some((i, acc, w));
                if acc + w > target {
                    break;
                }
            }
            acc += w;
        }
        let (i, start, w) = chosen?;
        let t = ((target - start) / w).clamp(0.0, 1.0 - f64::EPSILON);
        let lambda_i = self.excitation_nm[i] + (t - 0.5) * self.step_i;
        Some((lambda_i, w / (total * self.step_i)))
    }

    /// D(row, column of λᵢ)/(Σᵢ D(row, i)·Δλᵢ) = r(λᵢ → λₒ)/∫ r dλᵢ, computed as the draw
    /// above computes it (the same bits).
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> f64 {
        let (Some(o), Some(i)) = (self.row(lambda_o_nm), self.column(lambda_i_nm)) else {
            return 0.0;
        };
        let ni = self.excitation_nm.len();
        let total: f64 = self.fluo[o * ni..(o + 1) * ni].iter().sum();
        if !(total > 0.0) {
            return 0.0;
        }
        self.fluo[o * ni + i] / (total * self.step_i)
    }

    fn range(&self) -> (f64, f64) {
        let lo = self.excitation_nm[0].min(self.emission_nm[0]);
        let hi = self.excitation_nm[self.excitation_nm.len() - 1]
            .max(self.emission_nm[self.emission_nm.len() - 1]);
        (lo - 0.5 * self.step_i, hi + 0.5 * self.step_o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> BispectralMatrix {
        let text = "BFC-450 Matrix File\n;a\n;b\n400\t420\t10\t3\t390\t10\nr:c:\t390\t400\t410\n\
                    400\t0.2\t-0.1\t0.05\n410\t0.3\t0.1\t0.5\n420\t0.1\t0.2\t-0.3\nEOD\n";
        BispectralMatrix::from_bfc(&BfcFile::parse(text, "t.BFC").unwrap()).unwrap()
    }

    // The cleaning rule, entry by entry (exact: values are copied or zeroed).
    #[test]
    fn cleaning_rule() {
        let m = small();
        // Diagonal: 400 nm −0.1 → 0, 410 nm 0.5.
        assert_eq!(m.reflectance(400.0), 0.0);
        assert_eq!(m.reflectance(410.0), 0.5);
        // Kept: (400 ← 390) 0.2, (410 ← 390) 0.3, (410 ← 400) 0.1, (420 ← 390) 0.1, (420 ← 400) 0.2.
        assert_eq!(m.reradiation(390.0, 400.0), 0.02);
        assert_eq!(m.reradiation(400.0, 420.0), 0.02);
        // Anti-Stokes (400 ← 410) 0.05 dropped; the negative (420 ← 410) dropped.
        assert_eq!(m.reradiation(410.0, 400.0), 0.0);
        assert_eq!(m.reradiation(410.0, 420.0), 0.0);
        let r = m.cleaning();
        assert_eq!(
            (
                r.negative_reflectance,
                r.negative_fluorescence,
                r.anti_stokes
            ),
            (1, 1, 1)
        );
        assert_eq!(r.anti_stokes_sum, 0.05);
        // Column 390: 0.2 + 0.3 + 0.1 re-radiated, no reflectance at 390 nm (outside rows).
        assert!((m.albedo(390.0) - 0.6).abs() < 1e-12);
    }

    // Sampling λₒ for a given λᵢ: the density integrates to 1 over λₒ and matches the
    // frequencies of draws (each row's share within 0.01 over 20 000 stratified draws, which
    // are exact up to 1/20 000 for stratified u).
    #[test]
    fn emission_sampling_matches_its_pdf() {
        let m = small();
        let n = 20_000;
        let mut counts = [0usize; 3];
        for k in 0..n {
            let (l, p) = m
                .sample_emission(390.0, (k as f64 + 0.5) / n as f64)
                .unwrap();
            assert!((p - m.emission_pdf(390.0, l)).abs() < 1e-12);
            counts[((l - 395.0) / 10.0) as usize] += 1;
        }
        let share: Vec<f64> = counts.iter().map(|&c| c as f64 / n as f64).collect();
        for (s, want) in share.iter().zip([0.2 / 0.6, 0.3 / 0.6, 0.1 / 0.6]) {
            assert!((s - want).abs() < 0.01, "{share:?}");
        }
        let integral: f64 = (0..600)
            .map(|k| m.emission_pdf(390.0, 390.0 + k as f64 * 0.1))
            .sum::<f64>()
            * 0.1;
        assert!((integral - 1.0).abs() < 1e-9, "{integral}");
        assert!(m.sample_emission(410.0, 0.5).is_none());
    }

    // Sampling λᵢ for a given λₒ (camera paths): the density is r(λᵢ → λₒ)/∫r dλᵢ exactly,
    // so it integrates to 1 (0.1 nm midpoint rule on 10 nm cells: exact to 1e-9), and each
    // column's share of 20 000 stratified draws is its share of the row within 0.01 (stratified
    // u: exact to 1/20 000). Row 420 nm holds (420 ← 390) 0.1 and (420 ← 400) 0.2.
    #[test]
    fn excitation_sampling_matches_the_row() {
        let m = small();
        assert!((m.excitation_fraction(420.0) - 0.3).abs() < 1e-12);
        let n = 20_000;
        let mut low = 0usize;
        for k in 0..n {
            let (l, p) = m
                .sample_excitation(420.0, (k as f64 + 0.5) / n as f64)
                .unwrap();
            assert!(
                (p - m.reradiation(l, 420.0) / m.excitation_fraction(420.0)).abs() < 1e-12,
                "{l}: {p}"
            );
            assert_eq!(m.excitation_pdf(420.0, l), p, "{l}");
            low += (l < 395.0) as usize;
        }
        assert!((low as f64 / n as f64 - 1.0 / 3.0).abs() < 0.01, "{low}");
        let integral: f64 = (0..600)
            .map(|k| m.reradiation(360.0 + (k as f64 + 0.5) * 0.1, 420.0))
            .sum::<f64>()
            * 0.1;
        assert!((integral - 0.3).abs() < 1e-9, "{integral}");
        assert!(m.sample_excitation(400.0, 0.5).is_some());
        assert!(m.sample_excitation(390.0, 0.5).is_none());
    }

    // A matrix that returns more power than it receives is refused, naming the excess.
    #[test]
    fn energy_creating_matrix_is_refused() {
        let text =
            "BFC-450 Matrix File\n400\t410\t10\t1\t400\t10\nr:c:\t400\n400\t0.9\n410\t0.3\nEOD\n";
        let e = BispectralMatrix::from_bfc(&BfcFile::parse(text, "hot.BFC").unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("hot.BFC") && e.contains("1.2000") && e.contains("0.2000"),
            "{e}"
        );
    }
}
