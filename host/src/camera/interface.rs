//! What a camera is to the integrators: the [`Camera`] trait and the samples and rays it answers with.

use crate::geometry::Ray;
use glam::{Vec2, Vec3A};
use std::fmt::Debug;

/// Where on the film and on the lens a camera ray starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Continuous raster position in pixels (x right, y down, origin at the top-left corner).
    pub p_film: Vec2,
    /// Lens sample in [0,1)² (ignored by pinholes).
    pub p_lens: Vec2,
}

/// A generated camera ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// World-space ray with unit direction.
    pub ray: Ray,
    /// Importance weight of the ray (1 for the ideal cameras here).
    pub weight: f32,
}

/// A camera vertex sampled towards a scene point (light tracing / BDPT t = 1 strategies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraWiSample {
    /// Importance We towards the point (1/(m²·sr), scene units).
    pub importance: f32,
    /// Unit direction from the scene point to the lens point.
    pub wi: Vec3A,
    /// Density of the lens point in solid angle as seen from the scene point (1/sr).
    pub pdf: f32,
    /// The sampled point on the lens (world).
    pub p_lens: Vec3A,
    /// The lens normal (world; the viewing direction).
    pub n_lens: Vec3A,
    /// Raster position (pixels) the connection lands on.
    pub p_raster: Vec2,
}

/// A camera as integrators see it.
pub trait Camera: Send + Sync + Debug {
    /// Image size in pixels (width, height).
    fn resolution(&self) -> (u32, u32);

    /// The ray through a film/lens sample.
    fn generate_ray(&self, sample: &CameraSample) -> Option<CameraRay>;

    /// Sample a lens point as seen from world point `p`; `None` if `p` projects off the image.
    fn sample_wi(&self, p: Vec3A, u: Vec2) -> Option<CameraWiSample>;

    /// Positional (1/m², per lens area) and directional (1/sr) densities with which
    /// [`generate_ray`](Self::generate_ray) produces `ray` (zero off the image).
    fn pdf_we(&self, ray: &Ray) -> (f32, f32);

    /// Importance of a ray leaving the lens and the raster position it maps to.
    fn we(&self, ray: &Ray) -> (f32, Option<Vec2>);

    /// Centre of the lens (world).
    fn position(&self) -> Vec3A;

    /// Viewing direction (world, unit).
    fn forward(&self) -> Vec3A;

    /// True for a pinhole (every ray leaves [`position`](Self::position)): strategies that
    /// solve a path from the lens point itself need it, and callers skip the lens numbers
    /// ([`CameraSample::p_lens`]), which a pinhole never reads.
    fn pinhole(&self) -> bool {
        false
    }
}
