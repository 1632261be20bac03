//! Axis-aligned bounding boxes and the conservative ray–slab test used by the BVH.

use glam::Vec3A;

use super::float_error::gamma;

/// An axis-aligned box `[min, max]`; the empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3A,
    /// Upper corner.
    pub max: Vec3A,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box (union identity).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    /// The box around one point.
    #[inline]
    pub fn from_point(p: Vec3A) -> Self {
        Self { min: p, max: p }
    }

    /// Smallest box holding both.
    #[inline]
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Smallest box holding `self` and `p`.
    #[inline]
    pub fn grow(&self, p: Vec3A) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Whether the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Centre point.
    #[inline]
    pub fn centroid(&self) -> Vec3A {
        (self.min + self.max) * 0.5
    }

    /// Surface area (0 for an empty box).
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.max - self.min;
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Index of the longest axis.
    #[inline]
    pub fn longest_axis(&self) -> usize {
        let d = self.max - self.min;
        if d.x > d.y && d.x > d.z {
            0
        } else if d.y > d.z {
            1
        } else {
            2
        }
    }

    /// Slab test: whether the ray `origin + t·dir` meets the box for some `t ∈ [0, t_max]`.
    /// `inv_dir` is `1/dir` per component. The far distance is enlarged by `1 + 2γ₃` so that
    /// rounding can never make a ray miss a box that it actually grazes (pbrt-v4 §6.1.2).
    #[inline]
    pub fn hit(&self, origin: Vec3A, inv_dir: Vec3A, t_max: f32) -> bool {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let near = t0.min(t1);
        let far = t0.max(t1);
        let t_near = near.x.max(near.y).max(near.z).max(0.0);
        let t_far = far.x.min(far.y).min(far.z).min(t_max) * (1.0 + 2.0 * gamma(3));
        t_near <= t_far
    }
}
