//! [`CieSky`]: the CIE standard general sky ([`super::cie_sky_model`]) as the radiance of an
//! environment light. Luminance `Lz · L/Lz(direction)` cd/m² above the horizon, 0 below; the
//! spectrum is one normalised SPD `S(λ)` everywhere (a CIE daylight spectrum by default), so the
//! spectral radiance is `Lv / K · S(λ)` W/(m²·sr·nm) with `K = 683 lm/W · ∫ S V dλ`.
//! Next-event estimation draws directions from a table of the luminance distribution
//! ([`super::sky_sampler`], 64 × 256 cells over the hemisphere), and so do light subpaths
//! ([`EnvironmentRadiance::samples_emission`]): the bright circumsolar region starts as many
//! light paths as it deserves, and no light path starts below the horizon, where the sky is
//! black.

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

    fn direction_coords(&self, _p: Vec3A, dir: Vec3A) -> Option<Vec2> {
        let (mu, a, _) = self.local(dir);
        let (u0, u1) = self.sampler.coords(mu, a)?;
        let below_one = |v: f64| (v as f32).min(1.0 - f32::EPSILON / 2.0);
        Some(Vec2::new(below_one(u0), below_one(u1)))
    }

    fn samples_emission(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Aabb;
    use crate::light::{EnvironmentLight, Light};

    /// The CIE clear sky (type 12) with the sun at 40° altitude, 200° azimuth, +y up.
    fn clear_sky() -> CieSky {
        let ty = super::super::cie_sky_model::sky_type(12).unwrap();
        let frame = super::super::sky_frame([0.0, 1.0, 0.0], [0.0, 0.0, -1.0]).unwrap();
        let spd = super::super::daylight_spd(6500.0).unwrap();
        let k = crate::photometry::efficacy::luminous_efficacy_lm_per_w(spd.as_ref());
        CieSky::new(
            ty,
            50f64.to_radians(),
            200f64.to_radians(),
            frame,
            SkyBrightness::HorizontalIlluminance(10_000.0),
            spd,
            k,
        )
        .unwrap()
    }

    /// Light subpaths start by the sky's luminance table: chi-square of the directions
    /// `sample_le` emits (`−ray.dir`, towards the sky) against the table's density, in 16 × 32
    /// bins of (cos Z, azimuth), each 4 × 8 of the table's equal-solid-angle cells, whose
    /// expected counts are exact (the density is constant per cell); 400k rays, 99.9% quantile
    /// (Wilson–Hilferty). Uniform emission cannot pass (the circumsolar bins hold several times
    /// their solid angle's share), and none starts below the horizon. Also per ray: `pdf_le`
    /// gives back `sample_le`'s densities (1e-3 relative, f32) and their product is the table's
    /// density × cos θ/(πR²).
    #[test]
    fn emitted_directions_follow_the_sky() {
        let sky = Arc::new(clear_sky());
        let light = EnvironmentLight::new(sky.clone());
        let bounds = Aabb::from_point(Vec3A::new(-1.0, 0.0, -1.0)).grow(Vec3A::new(1.0, 0.5, 1.0));
        light.preprocess(&bounds);
        light.preprocess_view(&bounds);
        let (c, r) = light.sphere();
        let lambda = SampledWavelengths::sample_visible(0.4);
        let (bu, ba) = (TABLE.0 / 4, TABLE.1 / 8);
        let n = 400_000usize;
        let mut counts = vec![0usize; bu * ba];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            (crate::sampler::mix64(state) >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut mismatches, mut below, mut drawn) = (0, 0, 0usize);
        for _ in 0..n {
            let (u1, u2) = (Vec2::new(rnd(), rnd()), Vec2::new(rnd(), rnd()));
            let Some(s) = light.sample_le(u1, u2, &lambda) else {
                continue;
            };
            let w = -s.ray.dir;
            let (mu, a, _) = sky.local(w);
            if !(mu > 0.0) {
                below += 1;
                continue;
            }
            let cos = s.normal.dot(s.ray.dir) as f64;
            let joint =
                sky.direction_pdf(c, w) as f64 * cos / (std::f64::consts::PI * (r * r) as f64);
            let (pp, pd) = light.pdf_le(&s.ray, s.normal);
            if ((s.pdf_pos * s.pdf_dir) as f64 / joint - 1.0).abs() > 1e-3
                || ((pp * pd) as f64 / joint - 1.0).abs() > 1e-3
            {
                mismatches += 1;
            }
            let i = ((mu * TABLE.0 as f64) as usize).min(TABLE.0 - 1) / 4;
            let j = ((a.rem_euclid(2.0 * PI) / (2.0 * PI) * TABLE.1 as f64) as usize)
                .min(TABLE.1 - 1)
                / 8;
            counts[i * ba + j] += 1;
            drawn += 1;
        }
        assert_eq!(below, 0, "rays started below the horizon");
        // (Directions on a cell edge may land in the neighbouring cell in f32.)
        assert!(mismatches < n / 1000, "{mismatches} density mismatches");
        assert!(drawn > n - n / 1000, "only {drawn} of {n} rays");
        let cell = 2.0 * PI / (TABLE.0 * TABLE.1) as f64;
        let (mut chi2, mut dof, mut sun_ratio) = (0.0, 0usize, 0.0f64);
        for bi in 0..bu {
            for bj in 0..ba {
                let mut p = 0.0;
                for i in bi * 4..bi * 4 + 4 {
                    for j in bj * 8..bj * 8 + 8 {
                        let mu = (i as f64 + 0.5) / TABLE.0 as f64;
                        let a = 2.0 * PI * (j as f64 + 0.5) / TABLE.1 as f64;
                        p += sky.sampler.pdf(mu, a) * cell;
                    }
                }
                let uniform = 4.0 * 8.0 * cell / (2.0 * PI);
                sun_ratio = sun_ratio.max(p / uniform);
                let e = p * drawn as f64;
                if e >= 5.0 {
                    chi2 += (counts[bi * ba + bj] as f64 - e).powi(2) / e;
                    dof += 1;
                }
            }
        }
        let dof = (dof - 1) as f64;
        let q = dof * (1.0 - 2.0 / (9.0 * dof) + 3.09 * (2.0 / (9.0 * dof)).sqrt()).powi(3);
        println!(
            "sky emission: chi-square {chi2:.1} < {q:.1} ({dof} dof); brightest bin {sun_ratio:.1}× \
             its uniform share"
        );
        assert!(sun_ratio > 3.0, "the table is nearly uniform: {sun_ratio}");
        assert!(
            chi2 < q,
            "emitted directions: chi2 {chi2:.1} > {q:.1} ({dof} dof)"
        );
    }
}
