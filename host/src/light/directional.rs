//! A directional (distant) light: parallel light of given irradiance from one direction, like
//! the sun. Its power depends on the scene size, so it is specified by irradiance.

use super::scene_sphere::SceneSphere;
use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::{Aabb, Ray};
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// Directional light: irradiance `E·S(λ)` W/(m²·nm) on surfaces facing it.
#[derive(Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    direction: Vec3A,
    spd: Arc<dyn Spd>,
    irradiance: f32,
    /// Scene bounding sphere (centre, radius), set by `preprocess`.
    bounds: SceneSphere,
}

impl DirectionalLight {
    /// Light travelling along `direction` with irradiance `irradiance_w_m2` (W/m², normal incidence).
    pub fn new(direction: Vec3A, spd: Arc<dyn Spd>, irradiance_w_m2: f32) -> Result<Self, String> {
        if !(direction.length() > 0.0) {
            return Err("directional light needs a non-zero direction".into());
        }
        Ok(Self {
            direction: direction.normalize(),
            spd,
            irradiance: irradiance_w_m2,
            bounds: SceneSphere::new(),
        })
    }
}

impl Light for DirectionalLight {
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
        _u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let radiance = spd_at(self.spd.as_ref(), lambda) * self.irradiance;
        Some(self.bounds.incident(ctx, -self.direction, radiance))
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

    fn sample_le(&self, u1: Vec2, _u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        // Origin on a disk of the scene's radius, perpendicular to the direction, outside the scene.
        Some(LightLeSample {
            ray: self.bounds.emitted_ray(u1, self.direction),
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
}
