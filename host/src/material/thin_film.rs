//! Thin-film interference: one dielectric layer of thickness `d` on a dielectric or a
//! conductor base, in air, with smooth interfaces (soap film on water, oxide on metal).
//!
//! | parameter      | unit        | meaning                                                  |
//! |----------------|-------------|----------------------------------------------------------|
//! | `thickness_nm` | nm, ≥ 0     | film thickness d                                         |
//! | `film`         | IOR         | film index n₁(λ) (constant, Cauchy or Sellmeier)         |
//! | `base`         | IOR or n+ik | dielectric base n₂(λ) (reflects and transmits) or metal  |
//!
//! Per wavelength and polarisation (s, p), the reflected amplitude is the Airy sum of the
//! multiply reflected waves in the film (Born & Wolf, *Principles of Optics*, §1.6;
//! Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of
//! Varying Iridescence", use the same sum, which OpenPBR and MaterialX follow):
//!
//! `r = (r₀₁ + r₁₂ e^{2iδ}) / (1 + r₀₁ r₁₂ e^{2iδ})`, `t = t₀₁ t₁₂ e^{iδ} / (1 + r₀₁ r₁₂ e^{2iδ})`,
//! `δ = 2π n₁ d cos θ₁ / λ`,
//!
//! with the Fresnel amplitude coefficients r_jk, t_jk of each interface, which carry the
//! phase shifts at both interfaces (π for s on reflection off a denser medium, the complex
//! phase of a metal). Complex indices are `n + i·k` with time dependence e^{−iωt}, so cos θ in
//! an absorbing or totally reflecting medium takes the branch that decays away from the
//! interface. R = |r|²; T = Re(n₂ cos θ₂)/(n₀ cos θ₀)·|t|² (s), with n̄₂ for p; unpolarised
//! light averages s and p. Being per wavelength, this is exact for a spectral renderer (the
//! Fourier-domain antialiasing of Belcour & Barla is for RGB renderers and is not needed).
//!
//! The material reflects specularly and, on a dielectric base, transmits (refracted by the
//! base's index alone: parallel film faces do not change the final direction). A lobe is
//! chosen with the lanes' mean reflectance; each lane is weighted by its own R or T, so the
//! interference colours come out of one path. Only a dispersive *base* makes transmission
//! dispersive; the film's dispersion changes weights, not directions.

use super::complex::Complex;
use super::metals::ComplexIorTable;
use super::{
    refract, BsdfSample, EffectsOff, Material, MaterialFlags, ShadingContext, SpectralIor,
    TransportMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// Reflectance and transmittance of a film stack for unpolarised light (each in [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmResponse {
    /// (R_s + R_p)/2.
    pub reflectance: f64,
    /// (T_s + T_p)/2; 0 into an absorbing base (the light is absorbed there).
    pub transmittance: f64,
    /// s-polarised reflectance.
    pub r_s: f64,
    /// p-polarised reflectance.
    pub r_p: f64,
}

/// cos θ in a medium of index `n` for light entering from a real index `n0` at `sin²θ₀`:
/// the root whose wave `e^{i n cosθ k z}` decays (Im(n cos θ) ≥ 0) or propagates forward.
fn cos_in(n: Complex, n0: f64, sin2_0: f64) -> Complex {
    let s = Complex::real(n0 * n0 * sin2_0) / (n * n);
    let c = (Complex::real(1.0) - s).sqrt();
    let nc = n * c;
    if nc.im < 0.0 || (nc.im == 0.0 && nc.re < 0.0) {
        -c
    } else {
        c
    }
}

/// Amplitude coefficients (r_s, r_p, t_s, t_p) of the interface j → k.
fn interface(nj: Complex, cj: Complex, nk: Complex, ck: Complex) -> [Complex; 4] {
    let (a, b) = (nj * cj, nk * ck);
    let (pa, pb) = (nk * cj, nj * ck);
    let two_a = a * 2.0;
    [
        (a - b) / (a + b),
        (pa - pb) / (pa + pb),
        two_a / (a + b),
        two_a / (pa + pb),
    ]
}

/// Response of ambient (real index `n0`) | film (`n1`, `thickness_nm`) | base (`n2`) at
/// `cos0` = cos θ in the ambient (> 0) and vacuum wavelength `lambda_nm`.
pub fn film_response(
    n0: f64,
    n1: Complex,
    n2: Complex,
    thickness_nm: f64,
    cos0: f64,
    lambda_nm: f64,
) -> FilmResponse {
    let cos0 = cos0.clamp(0.0, 1.0);
    let sin2_0 = 1.0 - cos0 * cos0;
    let a0 = Complex::real(n0);
    let c0 = Complex::real(cos0);
    let c1 = cos_in(n1, n0, sin2_0);
    let c2 = cos_in(n2, n0, sin2_0);
    let [r01s, r01p, t01s, t01p] = interface(a0, c0, n1, c1);
    let [r12s, r12p, t12s, t12p] = interface(n1, c1, n2, c2);
    let delta = n1 * c1 * (2.0 * std::f64::consts::PI * thickness_nm / lambda_nm);
    // e^{iδ} and e^{2iδ} for complex δ.
    let e1 = Complex::new(-delta.im, delta.re).exp();
    let e2 = e1 * e1;
    let one = Complex::real(1.0);
    let rs = (r01s + r12s * e2) / (one + r01s * r12s * e2);
    let rp = (r01p + r12p * e2) / (one + r01p * r12p * e2);
    let ts = t01s * t12s * e1 / (one + r01s * r12s * e2);
    let tp = t01p * t12p * e1 / (one + r01p * r12p * e2);
    let (r_s, r_p) = (rs.norm_sqr(), rp.norm_sqr());
    let absorbing = n2.im != 0.0;
    let transmittance = if absorbing || cos0 == 0.0 {
        0.0
    } else {
        let denom = n0 * cos0;
        let t_s = (n2 * c2).re / denom * ts.norm_sqr();
        let t_p = (n2.conj() * c2).re / denom * tp.norm_sqr();
        0.5 * (t_s + t_p)
    };
    FilmResponse {
        reflectance: 0.5 * (r_s + r_p),
        transmittance,
        r_s,
        r_p,
    }
}

/// What the film sits on.
#[derive(Clone, Debug)]
pub enum ThinFilmBase {
    /// A dielectric: the surface reflects and transmits (outside is the normal's side).
    Dielectric(SpectralIor),
    /// A metal with complex index `n + i·k`: reflects only, one-sided.
    Conductor(ComplexIorTable),
}

/// A smooth surface coated with one thin film (see the module docs).
#[derive(Clone, Debug)]
pub struct ThinFilm {
    thickness_nm: f32,
    film: SpectralIor,
    base: ThinFilmBase,
}

impl ThinFilm {
    /// A film of `thickness_nm` (≥ 0, finite) and index `film` on `base`; the error names the
    /// bad value.
    pub fn new(thickness_nm: f32, film: SpectralIor, base: ThinFilmBase) -> Result<Self, String> {
        if !(thickness_nm >= 0.0 && thickness_nm.is_finite()) {
            return Err(format!(
                "thin film: thickness_nm must be a finite number ≥ 0, got {thickness_nm}"
            ));
        }
        if !(film.eval(550.0) >= 1.0) {
            return Err(format!(
                "thin film: film index {} at 550 nm is below 1",
                film.eval(550.0)
            ));
        }
        Ok(Self {
            thickness_nm,
            film,
            base,
        })
    }

    /// The material from scene-file style values, for registration in the scene registry:
    /// `film` is a number or a glass name (`N-BK7`, …), `base` is a number or glass name (a
    /// dielectric base) or a metal name (`au`, `ag`, `cu`, `al`: a conductor base). Errors
    /// name the parameter and the bad value.
    pub fn from_specs(thickness_nm: f32, film: &str, base: &str) -> Result<Self, String> {
        let ior = |what: &str, spec: &str| -> Result<SpectralIor, String> {
            match spec.trim().parse::<f32>() {
                Ok(n) if n >= 1.0 && n.is_finite() => Ok(SpectralIor::Constant(n)),
                Ok(n) => Err(format!("thin film: {what} index {n} must be ≥ 1")),
                Err(_) => SpectralIor::glass(spec).map_err(|e| format!("thin film: {what}: {e}")),
            }
        };
        let film = ior("film", film)?;
        let base =
            match ComplexIorTable::builtin(base) {
                Ok(metal) => ThinFilmBase::Conductor(metal),
                Err(_) => ThinFilmBase::Dielectric(ior("base", base).map_err(|e| {
                    format!("{e} (nor is `{base}` a built-in metal: au, ag, cu, al)")
                })?),
            };
        Self::new(thickness_nm, film, base)
    }

    /// (R, T) of lane `i` for light arriving at |cos θ| = `cos` from the side `outside`.
    fn lane(&self, cos: f32, outside: bool, lambda_nm: f32) -> (f32, f32) {
        let n1 = Complex::real(self.film.eval(lambda_nm) as f64);
        let (n0, n2) = match (&self.base, outside) {
            (ThinFilmBase::Dielectric(ior), true) => {
                (1.0, Complex::real(ior.eval(lambda_nm) as f64))
            }
            // From inside the base: base | film | air.
            (ThinFilmBase::Dielectric(ior), false) => {
                (ior.eval(lambda_nm) as f64, Complex::real(1.0))
            }
            (ThinFilmBase::Conductor(t), _) => {
                let (n, k) = t.eval(lambda_nm);
                (1.0, Complex::new(n as f64, k as f64))
            }
        };
        let r = film_response(
            n0,
            n1,
            n2,
            self.thickness_nm as f64,
            cos.abs() as f64,
            lambda_nm as f64,
        );
        (r.reflectance as f32, r.transmittance as f32)
    }

    fn base_ior(&self, lambda_nm: f32) -> Option<f32> {
        match &self.base {
            ThinFilmBase::Dielectric(ior) => Some(ior.eval(lambda_nm)),
            ThinFilmBase::Conductor(_) => None,
        }
    }
}

impl Material for ThinFilm {
    fn without_effects(&self, off: &EffectsOff) -> Option<(Arc<dyn Material>, String)> {
        let mut m = self.clone();
        let mut said = Vec::new();
        if off.thin_film && self.thickness_nm > 0.0 {
            m.thickness_nm = 0.0;
            said.push("thin film off: the bare base (film thickness 0 nm)".to_string());
        }
        if off.dispersion {
            let frozen = |i: &SpectralIor| i.frozen_at(off.reference_nm);
            if self.film.is_dispersive() && m.thickness_nm > 0.0 {
                m.film = frozen(&self.film);
                said.push(format!(
                    "dispersion off: film IOR {:.4} (its value at {} nm)",
                    m.film.eval(off.reference_nm),
                    off.reference_nm
                ));
            }
            if let ThinFilmBase::Dielectric(ior) = &self.base {
                if ior.is_dispersive() {
                    m.base = ThinFilmBase::Dielectric(frozen(ior));
                    said.push(format!(
                        "dispersion off: base IOR {:.4} (its value at {} nm)",
                        frozen(ior).eval(off.reference_nm),
                        off.reference_nm
                    ));
                }
            }
        }
        if said.is_empty() {
            return None;
        }
        Some((Arc::new(m), said.join("; ")))
    }

    fn flags(&self) -> MaterialFlags {
        let mut f = MaterialFlags::SPECULAR | MaterialFlags::REFLECTION | MaterialFlags::THIN_FILM;
        if let ThinFilmBase::Dielectric(ior) = &self.base {
            f |= MaterialFlags::TRANSMISSION;
            if ior.is_dispersive() {
                f |= MaterialFlags::DISPERSIVE;
            }
        }
        f
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        _ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        _u: Vec2,
        mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let outside = wo.z > 0.0;
        if !outside && matches!(self.base, ThinFilmBase::Conductor(_)) {
            return None;
        }
        let mut r = [0.0f32; LANES];
        let mut t = [0.0f32; LANES];
        let (mut r_mean, mut t_mean, mut n) = (0.0f32, 0.0f32, 0.0f32);
        for i in 0..LANES {
            (r[i], t[i]) = self.lane(wo.z, outside, lambda.lambda[i]);
            if lambda.pdf[i] > 0.0 || i == 0 {
                r_mean += r[i];
                t_mean += t[i];
                n += 1.0;
            }
        }
        let (r_mean, t_mean) = (r_mean / n, t_mean / n);
        let total = r_mean + t_mean;
        if !(total > 0.0) {
            return None;
        }
        let p_r = r_mean / total;
        if u_lobe < p_r || t_mean <= 0.0 {
            let wi = Vec3A::new(-wo.x, -wo.y, wo.z);
            return Some(out.write(BsdfSample {
                wi,
                f: SampledSpectrum(r) * (1.0 / wi.z.abs()),
                pdf: p_r,
                flags: MaterialFlags::SPECULAR | MaterialFlags::REFLECTION,
                eta: 1.0,
            }));
        }
        let eta = self.base_ior(lambda.lambda[0])?;
        let (nrm, etap) = if outside {
            (Vec3A::Z, eta)
        } else {
            (-Vec3A::Z, 1.0 / eta)
        };
        let wi = refract(wo, nrm, etap)?;
        let mut scale = 1.0 / wi.z.abs();
        if mode == TransportMode::Radiance {
            scale /= etap * etap;
        }
        let dispersive = if self.flags().contains(MaterialFlags::DISPERSIVE) {
            MaterialFlags::DISPERSIVE
        } else {
            MaterialFlags::NONE
        };
        Some(out.write(BsdfSample {
            wi,
            f: SampledSpectrum(t) * scale,
            pdf: 1.0 - p_r,
            flags: MaterialFlags::SPECULAR | MaterialFlags::TRANSMISSION | dispersive,
            eta: etap,
        }))
    }

    fn eval(
        &self,
        _wo: Vec3A,
        _wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn pdf(
        &self,
        _wo: Vec3A,
        _wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        0.0
    }
}
