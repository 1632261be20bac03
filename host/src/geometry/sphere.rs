//! Analytic spheres: intersection, uniform area sampling and solid-angle (cone) sampling.
//!
//! Intersection is solved in f64 with the cancellation-free discriminant
//! `4a·(r − |v|)(r + |v|)`, where `v` is the origin minus its projection onto the ray (Hearn &
//! Baker's formulation, also used by pbrt-v4 and Ray Tracing Gems ch. 7). `|v|` is accurate even
//! for a tiny sphere far from the ray origin, where the textbook `b² − 4ac` loses all digits.
//! The hit point is re-projected onto the sphere in f64 and rounded once to f32, so its error
//! bound is essentially one f32 rounding.

use std::f64::consts::PI;

use glam::{DVec3, Vec2, Vec3A};

use super::float_error::gamma;
use super::Ray;
use super::SurfaceDerivatives;

/// A sphere in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (scene units).
    pub center: Vec3A,
    /// Radius (scene units, > 0).
    pub radius: f32,
}

/// Surface data at a point on a sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePoint {
    /// The point, rounded to f32.
    pub point: Vec3A,
    /// Per-axis bound on the point's distance from the true surface.
    pub error: Vec3A,
    /// Outward unit normal.
    pub normal: Vec3A,
    /// Texture coordinates, see [`Sphere::uv`].
    pub uv: Vec2,
}

/// A point sampled on a sphere for light sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereSample {
    /// The surface point.
    pub surface: SpherePoint,
    /// Density: per unit area (1/units²) for area sampling, per steradian for cone sampling.
    pub pdf: f32,
}

impl Sphere {
    /// Surface area `4πr²` (scene units²).
    pub fn area(&self) -> f32 {
        (4.0 * PI * (self.radius as f64).powi(2)) as f32
    }

    /// Nearest `t ∈ (0, t_max)` where `ray` meets the sphere (either side), or `None`.
    #[inline]
    pub fn intersect_t(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let o = ray.origin.as_dvec3() - self.center.as_dvec3();
        let d = ray.dir.as_dvec3();
        let r = self.radius as f64;
        let a = d.length_squared();
        let b = 2.0 * d.dot(o);
        let c = o.length_squared() - r * r;
        let v = o - d * (b / (2.0 * a));
        let len = v.length();
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim < 0.0 {
            return None;
        }
        let root = discrim.sqrt();
        let q = if b < 0.0 {
            -0.5 * (b - root)
        } else {
            -0.5 * (b + root)
        };
        let (mut t0, mut t1) = (q / a, c / q);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = t_max as f64;
        let t = if t0 > 0.0 && t0 < t_max {
            t0
        } else if t1 > 0.0 && t1 < t_max {
            t1
        } else {
            return None;
        };
        // q = 0 (ray origin at the centre along a zero direction) gives NaN: rejected above.
        let tf = t as f32;
        if tf > 0.0 && tf < t_max as f32 {
            Some(tf)
        } else {
            None
        }
    }

    /// Surface data where `ray` meets the sphere at parameter `t` (from [`Self::intersect_t`]).
    pub fn surface_at(&self, ray: &Ray, t: f32) -> SpherePoint {
        let local = ray.origin.as_dvec3() - self.center.as_dvec3() + ray.dir.as_dvec3() * t as f64;
        self.surface_from_local(local)
    }

    /// Re-projects `local` (relative to the centre, f64) onto the sphere and fills in the data.
    fn surface_from_local(&self, local: DVec3) -> SpherePoint {
        let r = self.radius as f64;
        let len = local.length();
        let local = if len > 0.0 {
            local * (r / len)
        } else {
            DVec3::new(0.0, r, 0.0)
        };
        let world = self.center.as_dvec3() + local;
        let point: Vec3A = world.as_vec3().into();
        // One f32 rounding (≤ ε|x|) plus the f64 work, bounded generously by γ₂ of f32.
        let error = Vec3A::from(world.abs().as_vec3()) * gamma(2) + Vec3A::splat(f32::MIN_POSITIVE);
        let normal: Vec3A = (local / r).as_vec3().into();
        SpherePoint {
            point,
            error,
            normal: normal.normalize(),
            uv: Self::uv(local / r),
        }
    }

    /// Texture coordinates of a unit direction from the centre: `u = φ/2π` with
    /// `φ = atan2(−z, x) ∈ [0, 2π)` (counter-clockwise seen from +y), `v = θ/π` with θ from +y.
    pub fn uv(n: DVec3) -> Vec2 {
        let mut phi = (-n.z).atan2(n.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let theta = n.y.clamp(-1.0, 1.0).acos();
        Vec2::new((phi / (2.0 * PI)) as f32, (theta / PI) as f32)
    }

    /// ∂p/∂(u, v) and ∂n/∂(u, v) at surface point `p`, in the texture coordinates of
    /// [`Self::uv`] (`u = φ/2π`, `v = θ/π`, θ from +y): with the offset from the centre
    /// `r(sin θ cos φ, cos θ, −sin θ sin φ)`, ∂p/∂u = 2π ∂p/∂φ, ∂p/∂v = π ∂p/∂θ, and since the
    /// outward unit normal is the offset over `r`, ∂n = ∂p / r. ∂p/∂u vanishes at the poles
    /// (θ = 0, π), where this chart is singular.
    pub fn derivatives(&self, p: Vec3A) -> SurfaceDerivatives {
        let r = self.radius as f64;
        let n = (p.as_dvec3() - self.center.as_dvec3()).normalize_or_zero();
        let theta = n.y.clamp(-1.0, 1.0).acos();
        let phi = (-n.z).atan2(n.x);
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        let dpdphi = DVec3::new(-st * sp, 0.0, -st * cp) * r;
        let dpdtheta = DVec3::new(ct * cp, -st, -ct * sp) * r;
        let dpdu = dpdphi * (2.0 * PI);
        let dpdv = dpdtheta * PI;
        SurfaceDerivatives {
            dpdu: dpdu.as_vec3().into(),
            dpdv: dpdv.as_vec3().into(),
            dndu: (dpdu / r).as_vec3().into(),
            dndv: (dpdv / r).as_vec3().into(),
        }
    }

    /// Uniform sample by area from `u ∈ [0,1)²`; `pdf` is `1/(4πr²)` per unit area.
    pub fn sample_area(&self, u: Vec2) -> SphereSample {
        let y = 1.0 - 2.0 * u.x as f64;
        let s = (1.0 - y * y).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y as f64;
        let dir = DVec3::new(s * phi.cos(), y, -s * phi.sin());
        SphereSample {
            surface: self.surface_from_local(dir * self.radius as f64),
            pdf: 1.0 / self.area(),
        }
    }

    /// `1 − cos θ_max` of the cone the sphere subtends from `reference`, or `None` if the point
    /// is inside (or on) the sphere. Computed from `sin²θ_max` so it stays accurate for tiny cones.
    fn cone_one_minus_cos(&self, reference: Vec3A) -> Option<(f64, f64)> {
        let r = self.radius as f64;
        let dist2 = (self.center.as_dvec3() - reference.as_dvec3()).length_squared();
        // Points on the surface itself (rounded either way) must use area sampling: from there
        // the "cone" is a whole hemisphere whose nearest hit is the point itself.
        if dist2 <= r * r * (1.0 + 1e-4) {
            return None;
        }
        let sin2 = r * r / dist2;
        let cos = (1.0 - sin2).max(0.0).sqrt();
        Some((sin2 / (1.0 + cos), sin2))
    }

    /// Samples a point on the part of the sphere visible from `reference` (outside the sphere),
    /// uniformly in solid angle inside the subtended cone; `pdf` is per steradian. Falls back to
    /// [`Self::sample_area`] (pdf per unit area!) and returns `None` when `reference` is inside,
    /// so callers should use [`Self::pdf_solid_angle`] to know which applies.
    pub fn sample_solid_angle(&self, reference: Vec3A, u: Vec2) -> Option<SphereSample> {
        let (one_minus_cos_max, _) = self.cone_one_minus_cos(reference)?;
        let to_center = self.center.as_dvec3() - reference.as_dvec3();
        let dist = to_center.length();
        let w = to_center / dist;
        // Uniform in the cone: 1 − cos θ uniform in [0, 1 − cos θ_max].
        let one_minus_cos = u.x as f64 * one_minus_cos_max;
        let cos_t = 1.0 - one_minus_cos;
        let sin_t = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y as f64;
        let (t1, t2) = orthonormal_basis(w);
        let dir = (t1 * (sin_t * phi.cos()) + t2 * (sin_t * phi.sin()) + w * cos_t).normalize();
        // Nearest point along dir: distance to the chord midpoint minus half the chord. The
        // perpendicular offset is computed as a vector (no |c|² − tca² cancellation).
        let r = self.radius as f64;
        let tca = to_center.dot(dir);
        let perp2 = (to_center - dir * tca).length_squared();
        let half_chord = (r * r - perp2).max(0.0).sqrt();
        let hit = dir * (tca - half_chord) - to_center; // relative to the centre
        Some(SphereSample {
            surface: self.surface_from_local(hit),
            pdf: (1.0 / (2.0 * PI * one_minus_cos_max)) as f32,
        })
    }

    /// Solid-angle density (1/sr) with which [`Self::sample_solid_angle`] picks a direction
    /// from `reference`; `None` if `reference` is inside, where area sampling applies instead.
    pub fn pdf_solid_angle(&self, reference: Vec3A) -> Option<f32> {
        let (one_minus_cos_max, _) = self.cone_one_minus_cos(reference)?;
        Some((1.0 / (2.0 * PI * one_minus_cos_max)) as f32)
    }
}

/// Two unit vectors completing `w` (unit) to a right-handed orthonormal basis (Duff et al. 2017).
fn orthonormal_basis(w: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0f64.copysign(w.z);
    let a = -1.0 / (sign + w.z);
    let b = w.x * w.y * a;
    (
        DVec3::new(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x),
        DVec3::new(b, sign + w.y * w.y * a, -w.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    // A unit sphere hit head-on from z = 5 must be at t = 4 exactly-ish (1e-6 = few ULPs).
    #[test]
    fn head_on_hit() {
        let s = Sphere {
            center: Vec3A::ZERO,
            radius: 1.0,
        };
        let r = Ray::new(Vec3A::new(0.0, 0.0, 5.0), Vec3A::new(0.0, 0.0, -1.0));
        let t = s.intersect_t(&r, f32::INFINITY).unwrap();
        assert!((t - 4.0).abs() < 1e-6);
        let p = s.surface_at(&r, t);
        assert!((p.normal - Vec3A::Z).length() < 1e-6);
    }

    // A 1e-3-radius sphere 1e4 units away must still be hit by a ray aimed at it, and the hit
    // point must lie within its error bound of the surface (f64 check of |p − c| = r).
    #[test]
    fn small_far_sphere_is_accurate() {
        let s = Sphere {
            center: Vec3A::new(1.0e4, 2.0e3, -3.0e3),
            radius: 1.0e-3,
        };
        let o = Vec3A::new(-1.0, 0.5, 0.25);
        let r = Ray::new(o, (s.center - o).normalize());
        let t = s.intersect_t(&r, f32::INFINITY).expect("must hit");
        let p = s.surface_at(&r, t);
        let dist = (p.point.as_dvec3() - s.center.as_dvec3()).length();
        let bound = p.error.as_dvec3().length();
        assert!((dist - 1.0e-3).abs() <= bound, "{dist} vs bound {bound}");
    }

    // Cone sampling must only return points on the visible cap (normal faces the reference)
    // and its pdf must equal 1/(2π(1−cosθmax)) with cos θmax = sqrt(1 − r²/d²) (1e-4 rel.).
    #[test]
    fn cone_samples_visible_cap() {
        let s = Sphere {
            center: Vec3A::new(0.0, 0.0, -10.0),
            radius: 2.0,
        };
        let refp = Vec3A::ZERO;
        let cos_max = (1.0f64 - 4.0 / 100.0).sqrt();
        let expect = 1.0 / (2.0 * PI * (1.0 - cos_max));
        for i in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, ((i * 37) % 64) as f32 / 64.0);
            let smp = s.sample_solid_angle(refp, u).unwrap();
            assert!(smp.surface.normal.dot(refp - smp.surface.point) >= -1e-4);
            assert!(((smp.pdf as f64 - expect) / expect).abs() < 1e-4);
        }
        assert!(s.sample_solid_angle(s.center, Vec2::ZERO).is_none());
    }

    // ∂p/∂(u, v) and ∂n/∂(u, v) against central differences of the chart itself (point from
    // (u, v) via the formula of `uv`, normal = offset / r), step 1e-4 in f64: the truncation
    // error is O(h²) ≈ 1e-8 relative, the f32 rounding of the result ≈ 1e-7 relative; bound
    // 1e-5 of the vector's size.
    #[test]
    fn derivatives_match_finite_differences() {
        let s = Sphere {
            center: Vec3A::new(0.3, -1.2, 2.0),
            radius: 0.7,
        };
        let chart = |u: f64, v: f64| {
            let (phi, theta) = (2.0 * PI * u, PI * v);
            DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            )
        };
        let h = 1e-4;
        for &(u, v) in &[(0.1, 0.3), (0.45, 0.5), (0.8, 0.77), (0.6, 0.12)] {
            let n0 = chart(u, v);
            let p = s.center.as_dvec3() + n0 * s.radius as f64;
            let d = s.derivatives(p.as_vec3().into());
            let du = (chart(u + h, v) - chart(u - h, v)) / (2.0 * h);
            let dv = (chart(u, v + h) - chart(u, v - h)) / (2.0 * h);
            let r = s.radius as f64;
            for (got, want) in [
                (d.dpdu, du * r),
                (d.dpdv, dv * r),
                (d.dndu, du),
                (d.dndv, dv),
            ] {
                let err = (got.as_dvec3() - want).length();
                assert!(err <= 1e-5 * want.length().max(1.0), "{got:?} vs {want:?}");
            }
        }
    }
}
