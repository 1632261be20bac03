//! A ray in world space. Geometry is single precision (`glam::Vec3A`, 16-byte aligned) for
//! BVH speed; robustness against self-intersection comes from error bounds, not from f64.

use glam::Vec3A;

/// A half-line `origin + t·dir`, `t ∈ [0, t_max)`. `dir` need not be normalised unless a
/// caller says so; intersection routines return `t` in units of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point (scene units).
    pub origin: Vec3A,
    /// Direction.
    pub dir: Vec3A,
}

impl Ray {
    /// A ray from `origin` along `dir`.
    pub fn new(origin: Vec3A, dir: Vec3A) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + self.dir * t
    }
}
