//! A directional (distant) light: parallel light of given irradiance from one direction, like
//! the sun. Its power depends on the scene size, so it is specified by irradiance.

use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::{Aabb, Ray};
use crate::material::{sample_concentric_disk, Frame};
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::{Arc, OnceLock};

/// Directional light: irradiance `E·S(λ)` W/(m²·nm) on surfaces facing it.
#[derive(Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    direction: Vec3A,
    spd: Arc<dyn Spd>,
    irradiance: f32,
    /// Scene bounding sphere (centre, radius), set by `preprocess`.
    bounds: OnceLock<(Vec3A, f32)>,
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
            bounds: OnceLock::new(),
        })
    }

    fn sphere(&self) -> (Vec3A, f32) {
        *self.bounds.get().unwrap_or(&(Vec3A::ZERO, 1.0))
    }
}

impl Light for DirectionalLight {
    fn flags(&self) -> LightFlags {
        LightFlags::DELTA_DIRECTION
    }

    fn power(&self) -> f64 {
        let (_, r) = self.sphere();
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
        let (_, r) = self.sphere();
        let wi = -self.direction;
        Some(LightLiSample {
            radiance: spd_at(self.spd.as_ref(), lambda) * self.irradiance,
            wi,
            pdf: 1.0,
            p_light: ctx.p + wi * (2.0 * r),
            p_light_error: Vec3A::ZERO,
            n_light: Vec3A::ZERO,
        })
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
        let (c, r) = self.sphere();
        let frame = Frame::from_normal(self.direction);
        let d = sample_concentric_disk(u1) * r;
        let origin = c + frame.to_world(Vec3A::new(d.x, d.y, 0.0)) - self.direction * r;
        Some(LightLeSample {
            ray: Ray::new(origin, self.direction),
            radiance: spd_at(self.spd.as_ref(), lambda) * self.irradiance,
            pdf_pos: 1.0 / (PI * r * r),
            pdf_dir: 1.0,
            normal: Vec3A::ZERO,
        })
    }

    fn pdf_le(&self, _ray: &Ray, _n: Vec3A) -> (f32, f32) {
        let (_, r) = self.sphere();
        (1.0 / (PI * r * r), 0.0)
    }

    fn preprocess(&self, scene_bounds: &Aabb) {
        let c = (scene_bounds.min + scene_bounds.max) * 0.5;
        let r = ((scene_bounds.max - scene_bounds.min).length() * 0.5).max(1e-3);
        let _ = self.bounds.set((c, r));
    }
}
