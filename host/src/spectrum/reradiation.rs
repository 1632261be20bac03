//! [`Reradiation`]: what a fluorescent surface does to wavelengths, independent of directions.
//! Light of power 1 arriving at λᵢ leaves as the reflectance ρ(λᵢ) at the same wavelength plus
//! a re-radiated spectrum r(λᵢ → λₒ) (1/nm over λₒ) at other, longer wavelengths. Under an
//! illuminant E(λ) the light leaving is `S(λₒ) = ρ(λₒ)E(λₒ) + ∫ E(λᵢ) r(λᵢ → λₒ) dλᵢ`.
//! Implemented by a measured [`super::bispectral_matrix::BispectralMatrix`] and by the
//! parametric [`super::fluorescence_model::FluorescenceModel`].
//!
//! Energy is never created: `ρ(λᵢ) + ∫ r(λᵢ → λₒ) dλₒ ≤ 1` for every λᵢ
//! ([`Reradiation::albedo`]), which every implementation guarantees at construction.

/// Wavelength-shifting scattering data (see the module docs). Wavelengths in nm.
pub trait Reradiation: Send + Sync + std::fmt::Debug {
    /// Ordinary reflectance ρ(λ) (unitless, in [0, 1]): light leaving at the wavelength it
    /// arrived with.
    fn reflectance(&self, lambda_nm: f64) -> f64;

    /// Re-radiation density r(λᵢ → λₒ) in 1/nm (over λₒ): spectral power leaving at λₒ per
    /// unit power arriving at λᵢ. Zero for λₒ ≤ λᵢ (no anti-Stokes emission).
    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64;

    /// ∫ r(λᵢ → λₒ) dλₒ: the fraction of the power arriving at λᵢ that leaves at other
    /// wavelengths (unitless).
    fn reradiated_fraction(&self, lambda_i_nm: f64) -> f64;

    /// Draw an emission wavelength for excitation λᵢ with `u ∈ [0,1)`, with density
    /// proportional to r(λᵢ → ·): `(λₒ nm, pdf 1/nm)`, or `None` where nothing is re-radiated.
    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> Option<(f64, f64)>;

    /// Density (1/nm) with which [`sample_emission`](Self::sample_emission) produces λₒ.
    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64;

    /// ∫ r(λᵢ → λₒ) dλᵢ: how much light re-radiated at λₒ a unit illuminant at every
    /// excitation wavelength produces (unitless; may exceed 1, since many excitation
    /// wavelengths feed one emission wavelength). Camera paths read it as the weight of the
    /// re-radiated part. It need only be an estimate: samplers use it to choose between
    /// reflection and re-radiation, and weights use [`reradiation`](Self::reradiation) and
    /// [`sample_excitation`](Self::sample_excitation)'s density.
    fn excitation_fraction(&self, lambda_o_nm: f64) -> f64;

    /// Draw an excitation wavelength for emission λₒ with `u ∈ [0,1)` (camera paths follow
    /// light backwards): `(λᵢ nm, pdf 1/nm)` with a density that is positive wherever
    /// r(· → λₒ) is, or `None` where nothing re-radiates into λₒ.
    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> Option<(f64, f64)>;

    /// Density (1/nm) with which [`sample_excitation`](Self::sample_excitation) produces λᵢ
    /// for emission λₒ.
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> f64;

    /// Range of wavelengths (nm) over which excitation or emission is non-zero.
    fn range(&self) -> (f64, f64);

    /// Total power leaving per unit arriving at λᵢ: ρ(λᵢ) + ∫ r dλₒ (≤ 1).
    fn albedo(&self, lambda_i_nm: f64) -> f64 {
        self.reflectance(lambda_i_nm) + self.reradiated_fraction(lambda_i_nm)
    }
}
