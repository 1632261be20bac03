//! Spectral index of refraction for dielectrics: constant, Cauchy or Sellmeier.
//!
//! The Sellmeier catalogue is embedded from `host/data/glass/sellmeier.csv` (SCHOTT data sheets
//! for N-BK7, N-SF11, F2; Malitson 1965 for fused silica).

/// Embedded Sellmeier table. Source: host/data/glass/sellmeier.csv (SCHOTT data sheets; Malitson 1965).
const SELLMEIER_CSV: &str = include_str!("../../data/glass/sellmeier.csv");

/// Index of refraction as a function of vacuum wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpectralIor {
    /// The same index at every wavelength (no dispersion).
    Constant(f32),
    /// Cauchy's law `n(λ) = a + b/λ²` with λ in µm (`b` in µm²).
    Cauchy {
        /// Constant term.
        a: f32,
        /// Coefficient of 1/λ², µm².
        b: f32,
    },
    /// Sellmeier's law `n² = 1 + Σ Bᵢ λ²/(λ² − Cᵢ)`, λ in µm, `Cᵢ` in µm².
    Sellmeier {
        /// Bᵢ (unitless).
        b: [f32; 3],
        /// Cᵢ in µm².
        c: [f32; 3],
    },
}

impl SpectralIor {
    /// Index at wavelength `lambda_nm` (nm).
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        match *self {
            SpectralIor::Constant(n) => n,
            SpectralIor::Cauchy { a, b } => {
                let l = lambda_nm * 1e-3;
                a + b / (l * l)
            }
            SpectralIor::Sellmeier { b, c } => {
                let l2 = (lambda_nm * 1e-3).powi(2);
                let mut n2 = 1.0;
                for i in 0..3 {
                    n2 += b[i] * l2 / (l2 - c[i]);
                }
                n2.max(1e-4).sqrt()
            }
        }
    }

    /// True when the index varies with wavelength (refraction then disperses light).
    pub fn is_dispersive(&self) -> bool {
        !matches!(self, SpectralIor::Constant(_))
    }

    /// The constant index this IOR has at `lambda_nm` (dispersion switched off).
    pub fn frozen_at(&self, lambda_nm: f32) -> Self {
        SpectralIor::Constant(self.eval(lambda_nm))
    }

    /// A glass from the embedded Sellmeier catalogue by name (case-insensitive: `N-BK7`,
    /// `N-SF11`, `F2`, `fused-silica`). The error lists the known names.
    pub fn glass(name: &str) -> Result<Self, String> {
        let mut known = Vec::new();
        for (lineno, line) in SELLMEIER_CSV.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with("glass,") {
                continue;
            }
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            if cols.len() < 7 {
                return Err(format!(
                    "host/data/glass/sellmeier.csv line {}: expected 8 columns",
                    lineno + 1
                ));
            }
            known.push(cols[0].to_string());
            if cols[0].eq_ignore_ascii_case(name) {
                let mut v = [0.0f32; 6];
                for (i, slot) in v.iter_mut().enumerate() {
                    *slot = cols[i + 1].parse().map_err(|_| {
                        format!(
                            "host/data/glass/sellmeier.csv line {}: bad number {:?}",
                            lineno + 1,
                            cols[i + 1]
                        )
                    })?;
                }
                return Ok(SpectralIor::Sellmeier {
                    b: [v[0], v[1], v[2]],
                    c: [v[3], v[4], v[5]],
                });
            }
        }
        Err(format!(
            "unknown glass {name:?}; known glasses: {}",
            known.join(", ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// N-BK7 from the embedded catalogue against the data README's check values
    /// (n = 1.5168 at 587.56 nm, 1.5308 at 400 nm, 1.5131 at 700 nm), to 2e-4: the catalogue
    /// rounds to 4 decimals and f32 Sellmeier evaluation adds ~1e-6.
    #[test]
    fn bk7_matches_catalogue() {
        let bk7 = SpectralIor::glass("n-bk7").unwrap();
        assert!((bk7.eval(587.56) - 1.5168).abs() < 2e-4);
        assert!((bk7.eval(400.0) - 1.5308).abs() < 2e-4);
        assert!((bk7.eval(700.0) - 1.5131).abs() < 2e-4);
        assert!(bk7.is_dispersive());
    }

    /// Every catalogue glass reproduces its own n_d column at 587.56 nm to 2e-4.
    #[test]
    fn all_glasses_match_their_nd() {
        for (name, nd) in [
            ("N-SF11", 1.78472),
            ("F2", 1.62004),
            ("fused-silica", 1.4585),
        ] {
            let g = SpectralIor::glass(name).unwrap();
            assert!((g.eval(587.56) - nd).abs() < 2e-4, "{name}");
        }
        assert!(SpectralIor::glass("unobtainium")
            .unwrap_err()
            .contains("N-BK7"));
    }

    /// Cauchy: n(λ) = a + b/λ², checked at λ = 0.5 µm exactly (1e-6).
    #[test]
    fn cauchy_formula() {
        let c = SpectralIor::Cauchy { a: 1.5, b: 0.01 };
        assert!((c.eval(500.0) - 1.54).abs() < 1e-6);
    }
}
