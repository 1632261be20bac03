//! Spawning secondary rays without self-intersection.
//!
//! Method (error-bound offsetting, as in pbrt-v4 §6.8.6): every hit point comes with a
//! conservative per-axis bound `p_error` on how far the rounded f32 point may be from the true
//! surface. The true surface therefore passes through the box `p ± p_error`. Moving the origin
//! along the geometric normal `n` by `d = |n|·p_error` (the box's extent along `n`) puts it
//! strictly on one side of that box, and rounding each coordinate one more ULP away from the
//! surface absorbs the rounding of the addition itself. Because `p_error` is proportional to the
//! magnitude of the coordinates (not to the scene size), the same code works for scenes from 1e-3
//! to 1e5 units across and far from the world origin, with no scene-dependent epsilon.
//! The intersection routines complement this: the watertight triangle test rejects hits whose
//! `t` is not provably positive, and spheres are solved in f64 and re-projected onto the surface.

use glam::Vec3A;

use super::float_error::{next_float_down, next_float_up, MACHINE_EPSILON};
use super::Ray;

/// Moves `p` (known to within `p_error` per axis) off the surface with geometric normal `n`
/// onto the side that `w` points to. The result is the origin to use for a ray leaving along `w`.
#[inline]
pub fn offset_ray_origin(p: Vec3A, p_error: Vec3A, n: Vec3A, w: Vec3A) -> Vec3A {
    let d = n.abs().dot(p_error);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    for i in 0..3 {
        if offset[i] > 0.0 {
            po[i] = next_float_up(po[i]);
        } else if offset[i] < 0.0 {
            po[i] = next_float_down(po[i]);
        }
    }
    po
}

/// A ray leaving the surface point `p` (error bound `p_error`, geometric normal
/// `n_geometric`) in direction `dir`, with its origin offset so it cannot re-hit that surface.
/// Trace it with `t ∈ (0, ∞)`.
#[inline]
pub fn spawn_ray(p: Vec3A, p_error: Vec3A, n_geometric: Vec3A, dir: Vec3A) -> Ray {
    Ray::new(offset_ray_origin(p, p_error, n_geometric, dir), dir)
}

/// Fraction of the segment kept at the far end: the segment is shortened by 32 ε relative
/// (~2e-6) so the target surface, already offset towards the origin, is not reported as its own
/// occluder through the rounding of `t` (at most a few ε relative in the triangle test).
pub const CONNECTION_T_MAX: f32 = 1.0 - 32.0 * MACHINE_EPSILON;

/// A ray from surface point `p` to surface point `target_p` for a shadow ray or a path
/// connection. Both ends are offset off their surfaces (pass `target_n = Vec3A::ZERO` and a
/// zero error for a point light, which then is not offset). The direction is *not*
/// normalised: `t = 1` is (just past) the target, and the returned `t_max` stops just short.
/// Trace with `occluded(&ray, t_max)`.
#[inline]
pub fn spawn_ray_to(
    p: Vec3A,
    p_error: Vec3A,
    n: Vec3A,
    target_p: Vec3A,
    target_error: Vec3A,
    target_n: Vec3A,
) -> (Ray, f32) {
    let origin = offset_ray_origin(p, p_error, n, target_p - p);
    let target = offset_ray_origin(target_p, target_error, target_n, origin - target_p);
    (Ray::new(origin, target - origin), CONNECTION_T_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    // The offset origin must lie strictly outside the error box along the normal, on the side
    // of `w`, at both tiny and huge coordinates (exact comparison: it is a strict inequality).
    #[test]
    fn offset_leaves_error_box() {
        for &scale in &[1e-3f32, 1.0, 1e5] {
            let p = Vec3A::new(1.0, 2.0, 3.0) * scale;
            let err = p.abs() * 1e-6;
            let n = Vec3A::new(0.0, 1.0, 0.0);
            let up = offset_ray_origin(p, err, n, n);
            let down = offset_ray_origin(p, err, n, -n);
            assert!(up.y > p.y + err.y, "{scale}");
            assert!(down.y < p.y - err.y, "{scale}");
        }
    }

    // With zero error the origin still moves by at least nothing along n and stays on the
    // requested side: a connection to itself gives a zero-length direction, never NaN.
    #[test]
    fn spawn_to_points_at_target() {
        let p = Vec3A::new(0.0, 0.0, 0.0);
        let q = Vec3A::new(0.0, 2.0, 0.0);
        let (r, tmax) = spawn_ray_to(
            p,
            Vec3A::splat(1e-7),
            Vec3A::Y,
            q,
            Vec3A::splat(1e-7),
            -Vec3A::Y,
        );
        let end = r.at(tmax);
        assert!(end.y < q.y && end.y > 1.99, "{end}");
    }
}
