//! [`SunLight`]: the sun as a distant disc of angular diameter 0.533° (its mean apparent size;
//! solid angle Ω = 2π(1 − cos 0.2665°) = 6.797e-5 sr) and uniform radiance, lighting the scene
//! with normal irradiance `E` W/m² (luminance `E·K/Ω` cd/m²).
//!
//! The disc is small enough to treat like a directional light for the estimators: next-event
//! estimation picks a direction uniformly over the disc and weights it `E·S(λ)` (pdf 1, a delta
//! in the sense of [`LightFlags::DELTA_DIRECTION`]), which is an unbiased estimate of the
//! disc's irradiance `∫ L cos θ dω` on any receiver and gives soft shadow edges of the right
//! width. Like a directional light, the sun is not seen by rays that escape the scene (a camera
//! looking at the sun, or a mirror reflecting it, shows the sky behind; see `docs/daylight.md`).

use crate::geometry::{Aabb, Ray};
use crate::light::scene_sphere::SceneSphere;
use crate::light::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::material::Frame;
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// The sun's mean angular diameter, degrees.
pub const SUN_DIAMETER_DEG: f64 = 0.533;

/// Solid angle of a disc of angular diameter `diameter_deg`, sr.
pub fn disc_solid_angle(diameter_deg: f64) -> f64 {
    2.0 * std::f64::consts::PI * (1.0 - (0.5 * diameter_deg).to_radians().cos())
}

/// The sun (see the module docs).
#[derive(Debug)]
pub struct SunLight {
    /// Unit direction towards the sun.
    to_sun: Vec3A,
    frame: Frame,
    cos_max: f32,
    spd: Arc<dyn Spd>,
    /// Normal irradiance, W/m².
    irradiance: f32,
    /// Why it gives no light, if it does not (below the horizon).
    note: Option<String>,
    bounds: SceneSphere,
}

impl SunLight {
    /// A sun towards unit `to_sun` of angular diameter `diameter_deg` and normal irradiance
    /// `irradiance_w_m2`; `note` is a warning for the render summary.
    pub fn new(
        to_sun: Vec3A,
        diameter_deg: f64,
        spd: Arc<dyn Spd>,
        irradiance_w_m2: f32,
        note: Option<String>,
    ) -> Result<Self, String> {
        if !(to_sun.length() > 0.0 && to_sun.is_finite()) {
            return Err("the sun needs a non-zero direction".into());
        }
        if !(diameter_deg.is_finite() && diameter_deg > 0.0 && diameter_deg < 90.0) {
            return Err(format!(
                "angular diameter {diameter_deg}° must be in (0°, 90°)"
            ));
        }
        let to_sun = to_sun.normalize();
        Ok(Self {
            to_sun,
            frame: Frame::from_normal(to_sun),
            cos_max: (0.5 * diameter_deg).to_radians().cos() as f32,
            spd,
            irradiance: irradiance_w_m2,
            note,
            bounds: SceneSphere::new(),
        })
    }

    /// A direction towards a point of the disc, uniform over its solid angle.
    fn disc_direction(&self, u: Vec2) -> Vec3A {
        let cos = 1.0 - u.x * (1.0 - self.cos_max);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        self.frame
            .to_world(Vec3A::new(sin * phi.cos(), sin * phi.sin(), cos))
            .normalize()
    }

    /// Normal irradiance, W/m².
    pub fn irradiance(&self) -> f32 {
        self.irradiance
    }

    /// Unit direction towards the sun.
    pub fn to_sun(&self) -> Vec3A {
        self.to_sun
    }
}

impl Light for SunLight {
    fn flags(&self) -> LightFlags {
        LightFlags::DELTA_DIRECTION
    }

    fn power(&self) -> f64 {
        let (_, r) = self.bounds.get();
        (self.irradiance * PI * r * r) as f64
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        if self.irradiance <= 0.0 {
            return None;
        }
        let radiance = spd_at(self.spd.as_ref(), lambda) * self.irradiance;
        Some(self.bounds.incident(ctx, self.disc_direction(u), radiance))
    }

    fn pdf_li(&self, _ctx: &LightSampleContext, _p: Vec3A, _n: Vec3A) -> f32 {
        0.0
    }

    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _l: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        if self.irradiance <= 0.0 {
            return None;
        }
        let dir = -self.disc_direction(u2);
        Some(LightLeSample {
            ray: self.bounds.emitted_ray(u1, dir),
            radiance: spd_at(self.spd.as_ref(), lambda) * self.irradiance,
            pdf_pos: self.bounds.disc_pdf(),
            pdf_dir: 1.0,
            normal: Vec3A::ZERO,
        })
    }

    fn pdf_le(&self, _ray: &Ray, _n: Vec3A) -> (f32, f32) {
        (self.bounds.disc_pdf(), 0.0)
    }

    fn preprocess(&self, scene_bounds: &Aabb) {
        self.bounds.set(scene_bounds);
    }

    fn build_warning(&self) -> Option<String> {
        self.note.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The disc's solid angle: 6.797e-5 sr for 0.533° (2π(1 − cos 0.2665°) against the
    /// small-angle π(0.2665°)², equal to 1e-5 relative); directions drawn stay within the disc.
    #[test]
    fn disc() {
        let o = disc_solid_angle(SUN_DIAMETER_DEG);
        let small = std::f64::consts::PI * (0.2665f64.to_radians()).powi(2);
        assert!((o / small - 1.0).abs() < 1e-5, "{o} vs {small}");
        let spd: Arc<dyn Spd> = Arc::new(crate::spectrum::parse_spd_spec("e").unwrap());
        let s = SunLight::new(
            Vec3A::new(0.3, 1.0, -0.2),
            SUN_DIAMETER_DEG,
            spd,
            100.0,
            None,
        )
        .unwrap();
        for k in 0..100 {
            let u = Vec2::new((k as f32 * 0.618).fract(), (k as f32 * 0.414).fract());
            let d = s.disc_direction(u);
            assert!(d.dot(s.to_sun) >= s.cos_max - 1e-6);
        }
    }
}
