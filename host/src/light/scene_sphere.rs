//! What lights at infinity share (the directional light and the sun): the sphere bounding the
//! scene, known once the scene is built; their incident sample placed beyond it; their
//! emitted rays started on a disc of its radius outside it.

use super::{LightLiSample, LightSampleContext};
use crate::geometry::{Aabb, Ray};
use crate::material::{sample_concentric_disk, Frame};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::OnceLock;

/// The scene's bounding sphere (centre, radius), set by the light's `preprocess`.
#[derive(Debug, Default)]
pub struct SceneSphere(OnceLock<(Vec3A, f32)>);

impl SceneSphere {
    /// Not yet known.
    pub fn new() -> Self {
        Self(OnceLock::new())
    }

    /// Centre and radius (the unit sphere at the origin until [`set`](Self::set)).
    pub fn get(&self) -> (Vec3A, f32) {
        *self.0.get().unwrap_or(&(Vec3A::ZERO, 1.0))
    }

    /// The sphere around `scene_bounds` (radius at least 1 mm); the first call sets it.
    pub fn set(&self, scene_bounds: &Aabb) {
        let c = (scene_bounds.min + scene_bounds.max) * 0.5;
        let r = ((scene_bounds.max - scene_bounds.min).length() * 0.5).max(1e-3);
        let _ = self.0.set((c, r));
    }

    /// The delta sample of light arriving at `ctx` from direction `wi` (towards the light)
    /// with `radiance`: pdf 1, the light's point beyond the scene (twice the radius away).
    pub fn incident(
        &self,
        ctx: &LightSampleContext,
        wi: Vec3A,
        radiance: SampledSpectrum,
    ) -> LightLiSample {
        let (_, r) = self.get();
        LightLiSample {
            radiance,
            wi,
            pdf: 1.0,
            p_light: ctx.p + wi * (2.0 * r),
            p_light_error: Vec3A::ZERO,
            n_light: Vec3A::ZERO,
        }
    }

    /// A ray travelling along unit `dir`, started uniformly (`u`) on the disc of the sphere's
    /// radius perpendicular to `dir`, outside the scene.
    pub fn emitted_ray(&self, u: Vec2, dir: Vec3A) -> Ray {
        let (c, r) = self.get();
        let frame = Frame::from_normal(dir);
        let d = sample_concentric_disk(u) * r;
        let origin = c + frame.to_world(Vec3A::new(d.x, d.y, 0.0)) - dir * r;
        Ray::new(origin, dir)
    }

    /// The density of [`emitted_ray`](Self::emitted_ray)'s start, 1/(π r²) per m².
    pub fn disc_pdf(&self) -> f32 {
        let (_, r) = self.get();
        1.0 / (PI * r * r)
    }
}
