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
    step_away(p + offset, offset)
}

/// Each coordinate of `po` one ULP further in the direction of its `offset`: [`next_float_up`]
/// where the offset is positive, [`next_float_down`] where it is negative, unchanged where it
/// is zero or NaN. On x86-64 all three at once with SSE2 (part of the x86-64 baseline), bit
/// for bit what [`step_away_scalar`] does (test `vector_step_matches_the_scalar_one`): three
/// branches on the offset's sign and the special cases of each step cost about as many
/// instructions as the rest of a shadow ray's set-up (two offsets a shadow ray, one a bounce).
#[inline]
fn step_away(po: Vec3A, offset: Vec3A) -> Vec3A {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        // SAFETY: SSE2 is part of the x86-64 baseline, so every x86-64 CPU runs these
        // intrinsics; they only compute on registers (no memory is read or written).
        unsafe {
            let v: __m128 = po.into();
            let o: __m128 = offset.into();
            let zero = _mm_setzero_ps();
            // `cmpgt`/`cmplt` are false on NaN: a NaN offset moves nothing, as in the scalar.
            let up = _mm_cmpgt_ps(o, zero);
            let down = _mm_cmplt_ps(o, zero);
            // The zero the step starts from: `+0` going up, `-0` going down (`next_float_up`
            // treats `-0` as `+0`, `next_float_down` `+0` as `-0`). `v + 0` is `v` except that
            // `-0 + 0 = +0`; `-((-v) + 0)` is `v` except that it makes either zero `-0`.
            let sign = _mm_set1_ps(-0.0);
            let w_up = _mm_add_ps(v, zero);
            let w_down = _mm_xor_ps(_mm_add_ps(_mm_xor_ps(v, sign), zero), sign);
            let w = _mm_or_ps(_mm_and_ps(down, w_down), _mm_andnot_ps(down, w_up));
            let bits = _mm_castps_si128(w);
            // Away from zero (bits + 1) where the sign bit agrees with the direction (clear going
            // up, set going down), towards it (bits − 1) where not: the scalar's `v >= 0` and
            // `v > 0` tests once the zero's sign is settled as above.
            let negative = _mm_srai_epi32::<31>(bits);
            let towards = _mm_xor_si128(negative, _mm_castps_si128(down));
            let delta = _mm_or_si128(towards, _mm_set1_epi32(1));
            // Where the scalar returns its input: NaN, and the infinity the step points at
            // (`+∞` going up, `−∞` going down: sign agreeing with the direction).
            let magnitude = _mm_and_si128(bits, _mm_set1_epi32(0x7FFF_FFFF));
            let inf_or_nan = _mm_cmpgt_epi32(magnitude, _mm_set1_epi32(0x7F7F_FFFF));
            let nan = _mm_cmpgt_epi32(magnitude, _mm_set1_epi32(0x7F80_0000));
            let fixed = _mm_or_si128(nan, _mm_andnot_si128(towards, inf_or_nan));
            let moving = _mm_andnot_si128(fixed, _mm_castps_si128(_mm_or_ps(up, down)));
            let stepped = _mm_add_epi32(bits, delta);
            let out = _mm_or_si128(
                _mm_and_si128(moving, stepped),
                _mm_andnot_si128(moving, _mm_castps_si128(v)),
            );
            Vec3A::from(_mm_castsi128_ps(out))
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        step_away_scalar(po, offset)
    }
}

/// [`step_away`] coordinate by coordinate: the definition.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline]
fn step_away_scalar(mut po: Vec3A, offset: Vec3A) -> Vec3A {
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

    // The SSE2 step equals the scalar definition bit for bit for every coordinate class a
    // hit point can have (±0, subnormals, ±1, the largest finite values, ±∞, NaN of either
    // sign, and 20,000 random finite values over the whole exponent range) against every
    // offset class (positive, negative, ±0, NaN): exact equality of the bits, since any
    // difference would move a ray's origin.
    #[test]
    fn vector_step_matches_the_scalar_one() {
        let mut values = vec![
            0.0f32,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1.0,
            -1.0,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..20_000 {
            state = crate::sampler::mix64(state);
            let v = f32::from_bits(state as u32);
            if v.is_finite() {
                values.push(v);
            }
        }
        let offsets = [1e-3f32, -1e-3, 0.0, -0.0, f32::NAN, 7.0, -7.0];
        let mut checked = 0;
        for (k, &v) in values.iter().enumerate() {
            for (j, &o) in offsets.iter().enumerate() {
                // Three lanes of different classes at once.
                let w = values[(k * 7 + 3) % values.len()];
                let u = values[(k * 13 + 5) % values.len()];
                let o2 = offsets[(j + 1) % offsets.len()];
                let o3 = offsets[(j + 3) % offsets.len()];
                let po = Vec3A::new(v, w, u);
                let off = Vec3A::new(o, o2, o3);
                let a = step_away(po, off).to_array().map(f32::to_bits);
                let b = step_away_scalar(po, off).to_array().map(f32::to_bits);
                assert_eq!(a, b, "po {po:?} offset {off:?}");
                checked += 1;
            }
        }
        assert!(checked > 100_000);
    }

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
