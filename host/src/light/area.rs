//! An area light: a scene object whose material is emissive. Radiance `scale·S(λ)`, uniform,
//! from the front side (or both). Sampled by solid angle from the receiver (exact cone sampling
//! for spheres, area sampling converted to solid angle otherwise; see `Geometry`).

use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::{spawn_ray, Geometry, Ray, WorldShape};
use crate::material::{sample_cosine_hemisphere, EmissionProfile, Frame};
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// The emitting surface of scene object `object`.
#[derive(Debug, Clone)]
pub struct AreaLight {
    geometry: Arc<Geometry>,
    object: u32,
    emission: EmissionProfile,
    area: f32,
    radiance: DenseSpectrum,
}

impl AreaLight {
    /// An area light on `object` of `geometry` with the emissive material's profile.
    pub fn new(geometry: Arc<Geometry>, object: u32, emission: EmissionProfile) -> Self {
        let area = geometry.object_area(object);
        Self {
            radiance: DenseSpectrum::from_spd(emission.spd.clone(), emission.scale),
            geometry,
            object,
            emission,
            area,
        }
    }

    fn emits_towards(&self, n: Vec3A, w: Vec3A) -> bool {
        let c = n.dot(w);
        c > 0.0 || (self.emission.two_sided && c < 0.0)
    }

    fn le(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.eval(lambda)
    }
}

impl Light for AreaLight {
    fn flags(&self) -> LightFlags {
        LightFlags::AREA
    }

    // Radiance is `scale · S(λ)` wherever it emits (see `radiance`).
    fn uniform_spectral_shape(&self) -> bool {
        true
    }

    fn power(&self) -> f64 {
        let sides = if self.emission.two_sided { 2.0 } else { 1.0 };
        (PI * self.area * self.emission.scale) as f64 * sides
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.emission.spd.clone()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let t = self.geometry.sample_towards(self.object, ctx.p, u)?;
        let s = t.sample;
        if !(s.pdf > 0.0) || !s.pdf.is_finite() {
            return None;
        }
        let (d, dist) = (t.d, t.dist);
        if !(dist > 0.0) {
            return None;
        }
        let wi = d / dist;
        if !self.emits_towards(s.normal, -wi) {
            return None;
        }
        Some(LightLiSample {
            radiance: self.le(lambda),
            wi,
            pdf: s.pdf,
            p_light: s.point,
            p_light_error: s.point_error,
            n_light: s.normal,
        })
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32 {
        self.geometry
            .pdf_solid_angle(self.object, ctx.p, p_light, n_light)
    }

    // Spheres are sampled by their cone from outside; every other shape by area, as `sample_le`.
    fn li_points_as_le(&self) -> bool {
        !matches!(
            self.geometry.shape(self.object),
            Some(WorldShape::Sphere(_))
        )
    }

    // Quads (through their chart) and meshes (area CDF, then barycentrics) map u to the same
    // point from every receiver (`Geometry::sample_area`); `Geometry::sample_coords` inverts
    // the map for quads and small meshes.
    fn sample_coords(&self, _receiver: Vec3A, p_light: Vec3A) -> Option<Vec2> {
        self.geometry.sample_coords(self.object, p_light)
    }

    fn radiance(
        &self,
        _p: Vec3A,
        n: Vec3A,
        _uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.emits_towards(n, w) {
            self.le(lambda)
        } else {
            SampledSpectrum::zero()
        }
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        let s = self.geometry.sample_area(self.object, u1)?;
        // Two-sided lights pick a side with probability ½ (reusing u2.x).
        let (mut u2, mut n, mut side_pdf) = (u2, s.normal, 1.0);
        if self.emission.two_sided {
            side_pdf = 0.5;
            if u2.x < 0.5 {
                u2.x *= 2.0;
            } else {
                u2.x = (u2.x - 0.5) * 2.0;
                n = -n;
            }
        }
        let local = sample_cosine_hemisphere(u2);
        let w = Frame::from_normal(n).to_world(local);
        let pdf_dir = local.z / PI * side_pdf;
        if !(pdf_dir > 0.0) {
            return None;
        }
        Some(LightLeSample {
            ray: spawn_ray(s.point, s.point_error, n, w),
            radiance: self.le(lambda),
            pdf_pos: s.pdf,
            pdf_dir,
            normal: n,
        })
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        let cos = n.dot(ray.dir.normalize());
        let side = if self.emission.two_sided { 0.5 } else { 1.0 };
        let pdf_dir = if cos > 0.0 || (self.emission.two_sided && cos < 0.0) {
            cos.abs() / PI * side
        } else {
            0.0
        };
        (self.geometry.pdf_area(self.object), pdf_dir)
    }

    fn object(&self) -> Option<u32> {
        Some(self.object)
    }
}
