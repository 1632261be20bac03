//! [`CieSky`]: the CIE standard general sky ([`super::cie_sky_model`]) as the radiance of an
//! environment light. Luminance `Lz · L/Lz(direction)` cd/m² above the horizon, 0 below; the
//! spectrum is one normalised SPD `S(λ)` everywhere (a CIE daylight spectrum by default), so the
//! spectral radiance is `Lv / K · S(λ)` W/(m²·sr·nm) with `K = 683 lm/W · ∫ S V dλ`.
//! Next-event estimation draws directions from a table of the luminance distribution
//! ([`super::sky_sampler`], 64 × 256 cells over the hemisphere).

use super::cie_sky_model::SkyType;
use super::sky_sampler::HemisphereSampler;
use crate::light::EnvironmentRadiance;
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{DVec3, Vec2, Vec3A};
use std::f64::consts::PI;
use std::sync::Arc;

/// Bands in cos Z and sectors in azimuth of the sampling table.
const TABLE: (usize, usize) = (64, 256);

/// Quadrature resolution of the sky's integrals (see [`SkyType::horizontal_factor`]).
const QUADRATURE_N: usize = 256;

/// The sky (see the module docs).
#[derive(Debug)]
pub struct CieSky {
    ty: SkyType,
    /// Sun zenith angle, radians.
    zs: f64,
    /// Unit direction towards the sun.
    sun: DVec3,
    /// up, north, east.
    frame: [DVec3; 3],
    /// Zenith luminance, cd/m².
    lz: f64,
    /// Horizontal illuminance of the unobstructed sky, lx.
    horizontal_lx: f64,
    spd: Arc<dyn Spd>,
    /// `S(λ)/K` per cd/m².
    per_nit: DenseSpectrum,
    /// Mean radiance over all directions, W/(m²·sr).
    mean_w: f64,
    sampler: HemisphereSampler,
}

/// How bright the sky is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyBrightness {
    /// Zenith luminance, cd/m².
    ZenithLuminance(f64),
    /// Horizontal illuminance of the whole unobstructed sky (the diffuse horizontal
    /// illuminance), lx.
    HorizontalIlluminance(f64),
}

impl CieSky {
    /// The sky of type `ty` with the sun at zenith angle `zs` and azimuth `azs` (radians,
    /// from north through east) in `frame` = [up, north, east], of brightness `brightness` and
    /// normalised spectrum `spd` of luminous efficacy `k_lm_w`.
    pub fn new(
        ty: SkyType,
        zs: f64,
        azs: f64,
        frame: [DVec3; 3],
        brightness: SkyBrightness,
        spd: Arc<dyn Spd>,
        k_lm_w: f64,
    ) -> Result<Self, String> {
        if !(k_lm_w > 0.0) {
            return Err("the sky's spectrum has no visible part".into());
        }
        let (h_factor, omega_factor) = integrals(&ty, zs);
        let (lz, horizontal_lx) = match brightness {
            SkyBrightness::ZenithLuminance(l) => (l, l * h_factor),
            SkyBrightness::HorizontalIlluminance(e) => (e / h_factor, e),
        };
        if !(lz.is_finite() && lz >= 0.0) {
            return Err(format!("zenith luminance {lz} cd/m² is not finite and ≥ 0"));
        }
        let sun = super::direction(&frame, zs, azs);
        let sampler = HemisphereSampler::new(TABLE.0, TABLE.1, |mu, a| {
            let z = mu.acos();
            let d = super::direction(&frame, z, a);
            relative(&ty, zs, sun, mu, d)
        })
        .ok_or("the sky is black everywhere")?;
        Ok(Self {
            ty,
            zs,
            sun,
            frame,
            lz,
            horizontal_lx,
            per_nit: DenseSpectrum::from_spd(spd.clone(), (1.0 / k_lm_w) as f32),
            spd,
            mean_w: lz * omega_factor / (4.0 * PI) / k_lm_w,
            sampler,
        })
    }

    /// Zenith luminance, cd/m².
    pub fn zenith_luminance(&self) -> f64 {
        self.lz
    }

    /// Horizontal illuminance of the unobstructed sky, lx.
    pub fn horizontal_illuminance(&self) -> f64 {
        self.horizontal_lx
    }

    /// The sky type.
    pub fn sky_type(&self) -> SkyType {
        self.ty
    }

    /// Luminance (cd/m²) seen along unit direction `dir` (towards the sky).
    pub fn luminance(&self, dir: DVec3) -> f64 {
        let mu = dir.dot(self.frame[0]);
        self.lz * relative(&self.ty, self.zs, self.sun, mu, dir)
    }

    fn local(&self, dir: Vec3A) -> (f64, f64, DVec3) {
        let d = DVec3::new(dir.x as f64, dir.y as f64, dir.z as f64).normalize_or_zero();
        let mu = d.dot(self.frame[0]);
        let a = d.dot(self.frame[2]).atan2(d.dot(self.frame[1]));
        (mu, a, d)
    }
}

/// L/Lz at unit direction `d` with cos Z = `mu` (0 below the horizon).
fn relative(ty: &SkyType, zs: f64, sun: DVec3, mu: f64, d: DVec3) -> f64 {
    if !(mu > 0.0) {
        return 0.0;
    }
    let chi = d.dot(sun).clamp(-1.0, 1.0).acos();
    ty.relative_luminance_chi(mu.min(1.0).acos(), chi, zs)
}

/// (∫ L/Lz cos Z dω, ∫ L/Lz dω) over the hemisphere, sr.
fn integrals(ty: &SkyType, zs: f64) -> (f64, f64) {
    let h = ty.horizontal_factor(zs, QUADRATURE_N);
    let o = ty.solid_angle_factor(zs, QUADRATURE_N);
    (h, o)
}

impl EnvironmentRadiance for CieSky {
    fn radiance(&self, dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        let (mu, _, d) = self.local(dir);
        let r = relative(&self.ty, self.zs, self.sun, mu, d);
        if !(r > 0.0) {
            return SampledSpectrum::zero();
        }
        self.per_nit.eval(lambda) * (self.lz * r) as f32
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn mean_radiance(&self) -> f64 {
        self.mean_w
    }

    fn sample_direction(&self, _p: Vec3A, u: Vec2) -> Option<(Vec3A, f32)> {
        let (mu, a, pdf) = self.sampler.sample(u.x as f64, u.y as f64);
        let d = super::direction(&self.frame, mu.clamp(0.0, 1.0).acos(), a);
        let pdf = pdf as f32;
        (pdf > 0.0).then(|| (Vec3A::new(d.x as f32, d.y as f32, d.z as f32), pdf))
    }

    fn direction_pdf(&self, _p: Vec3A, dir: Vec3A) -> f32 {
        let (mu, a, _) = self.local(dir);
        self.sampler.pdf(mu, a) as f32
    }
}
