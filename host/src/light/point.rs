//! An isotropic point light of given power.

use super::{
    incident_from_point, incident_from_point_into, sample_uniform_sphere, Light, LightFlags,
    LightLeSample, LightLiSample, LightSampleContext,
};
use crate::geometry::Ray;
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// Point light: intensity `I(λ) = P/(4π) · S(λ)` W/(sr·nm) in every direction.
#[derive(Debug, Clone)]
pub struct PointLight {
    position: Vec3A,
    spd: Arc<dyn Spd>,
    power: f32,
}

impl PointLight {
    /// A light at `position` emitting `power_w` watts with normalised SPD `spd`.
    pub fn new(position: Vec3A, spd: Arc<dyn Spd>, power_w: f32) -> Self {
        Self {
            position,
            spd,
            power: power_w,
        }
    }

    fn intensity(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        spd_at(self.spd.as_ref(), lambda) * (self.power / (4.0 * PI))
    }
}

impl Light for PointLight {
    fn flags(&self) -> LightFlags {
        LightFlags::DELTA_POSITION
    }

    fn power(&self) -> f64 {
        self.power as f64
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
        incident_from_point(self.position, ctx, |_| self.intensity(lambda))
    }

    fn sample_li_into(
        &self,
        ctx: &LightSampleContext,
        _u: Vec2,
        lambda: &SampledWavelengths,
        out: &mut LightLiSample,
    ) -> bool {
        incident_from_point_into(self.position, ctx, |_| self.intensity(lambda), out)
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

    fn sample_le(&self, _u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        Some(LightLeSample {
            ray: Ray::new(self.position, sample_uniform_sphere(u2)),
            radiance: self.intensity(lambda),
            pdf_pos: 1.0,
            pdf_dir: 1.0 / (4.0 * PI),
            normal: Vec3A::ZERO,
        })
    }

    fn pdf_le(&self, _ray: &Ray, _n: Vec3A) -> (f32, f32) {
        (0.0, 1.0 / (4.0 * PI))
    }
}
