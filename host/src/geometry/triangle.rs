//! Watertight ray–triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2013) with a conservative bound on the hit point's error.
//!
//! The ray is turned into a shear transform that maps it onto the +z axis; the three 2D edge
//! functions of the sheared triangle are then evaluated with the *same* operations for an edge
//! shared by two triangles (only with the sign flipped), so a ray can never slip between them.
//! Edge functions that come out exactly zero are recomputed in f64 to decide the sign.

use glam::{DVec3, Vec2, Vec3A};

use super::float_error::gamma;
use super::Ray;
use super::SurfaceDerivatives;

/// Per-ray data for the watertight test, computed once per ray and reused for every triangle.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    /// The dominant direction axis; the other two, `kx = kz + 1` and `ky = kz + 2` (mod 3),
    /// follow from it.
    kz: usize,
    /// Shear coefficients `(-d_x/d_z, -d_y/d_z, 1/d_z)` in permuted axes.
    sx: f32,
    sy: f32,
    sz: f32,
}

impl WatertightRay {
    /// Precomputes the shear for `ray`. The direction must be non-zero.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        match dominant_axis(ray.dir) {
            0 => Self::for_axis::<0>(ray),
            1 => Self::for_axis::<1>(ray),
            _ => Self::for_axis::<2>(ray),
        }
    }

    /// [`WatertightRay::new`] for a ray whose dominant axis ([`dominant_axis`]) is `KZ`: the
    /// permuted components are read at constant indices, where `new` alone would index the
    /// direction by a run-time axis (through memory); the same divisions, the same shear.
    #[inline(always)]
    pub fn for_axis<const KZ: usize>(ray: &Ray) -> Self {
        let dz = ray.dir[KZ];
        Self {
            kz: KZ,
            sx: -ray.dir[(KZ + 1) % 3] / dz,
            sy: -ray.dir[(KZ + 2) % 3] / dz,
            sz: 1.0 / dz,
        }
    }

    /// The shear `(s_x, s_y, s_z)`: `-d_x/d_z`, `-d_y/d_z`, `1/d_z` in permuted axes (for
    /// tests of several triangles at once that repeat [`intersect_triangle_axis`]' operations).
    #[inline]
    pub fn shear(&self) -> [f32; 3] {
        [self.sx, self.sy, self.sz]
    }

    /// The dominant axis of the ray direction (0, 1, 2 for x, y, z): the `KZ` to pass to
    /// [`intersect_triangle_axis`].
    #[inline]
    pub fn dominant_axis(&self) -> usize {
        self.kz
    }
}

/// The axis (0, 1, 2 for x, y, z) of the largest component of `dir` in magnitude, ties to the
/// later axis: the `KZ` of [`WatertightRay::for_axis`] and [`intersect_triangle_axis`].
#[inline(always)]
pub fn dominant_axis(dir: Vec3A) -> usize {
    let a = dir.abs();
    if a.x > a.y {
        if a.x > a.z {
            0
        } else {
            2
        }
    } else if a.y > a.z {
        1
    } else {
        2
    }
}

/// A triangle hit: ray parameter and barycentrics (`b0` weights `p0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter (units of `ray.dir`), provably positive.
    pub t: f32,
    /// Barycentric weight of vertex 0.
    pub b0: f32,
    /// Barycentric weight of vertex 1.
    pub b1: f32,
    /// Barycentric weight of vertex 2.
    pub b2: f32,
}

/// Intersects `ray` with triangle `p0 p1 p2`, accepting only `0 < t < t_max`. Both faces hit.
#[inline]
pub fn intersect_triangle(
    ray: &Ray,
    wr: &WatertightRay,
    t_max: f32,
    p0: Vec3A,
    p1: Vec3A,
    p2: Vec3A,
) -> Option<TriangleHit> {
    match wr.kz {
        0 => intersect_triangle_axis::<0>(ray, wr, t_max, p0, p1, p2),
        1 => intersect_triangle_axis::<1>(ray, wr, t_max, p0, p1, p2),
        _ => intersect_triangle_axis::<2>(ray, wr, t_max, p0, p1, p2),
    }
}

/// [`intersect_triangle`] with the ray's dominant axis `KZ` (`wr.dominant_axis()`, which it
/// must equal) fixed at compile time. The same operations on the same values, so bit for bit
/// the same result; but the permutation becomes fixed lane picks instead of three indexings
/// by a run-time axis per vertex (each a branch). Scene traversal dispatches on the axis once
/// per ray and then tests every triangle with this.
#[inline(always)]
pub fn intersect_triangle_axis<const KZ: usize>(
    ray: &Ray,
    wr: &WatertightRay,
    t_max: f32,
    p0: Vec3A,
    p1: Vec3A,
    p2: Vec3A,
) -> Option<TriangleHit> {
    debug_assert_eq!(KZ, wr.kz);
    let (kx, ky) = ((KZ + 1) % 3, (KZ + 2) % 3);
    // Translate to the ray origin, permute so z is the dominant axis, shear onto +z.
    let a = (p0 - ray.origin).to_array();
    let b = (p1 - ray.origin).to_array();
    let c = (p2 - ray.origin).to_array();
    let (az, bz, cz) = (a[KZ], b[KZ], c[KZ]);
    let ax = a[kx] + wr.sx * az;
    let ay = a[ky] + wr.sy * az;
    let bx = b[kx] + wr.sx * bz;
    let by = b[ky] + wr.sy * bz;
    let cx = c[kx] + wr.sx * cz;
    let cy = c[ky] + wr.sy * cz;

    // Edge functions; e0 is opposite p0 (edge p1→p2) and so on.
    let mut e0 = bx * cy - by * cx;
    let mut e1 = cx * ay - cy * ax;
    let mut e2 = ax * by - ay * bx;
    // `|` and `&` rather than `||` and `&&`: one branch each instead of up to six
    // data-dependent ones (the signs of a missed triangle's edge functions are unpredictable).
    if (e0 == 0.0) | (e1 == 0.0) | (e2 == 0.0) {
        let (ax, ay, bx, by, cx, cy) = (
            ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
        );
        e0 = (bx * cy - by * cx) as f32;
        e1 = (cx * ay - cy * ax) as f32;
        e2 = (ax * by - ay * bx) as f32;
    }
    if ((e0 < 0.0) | (e1 < 0.0) | (e2 < 0.0)) & ((e0 > 0.0) | (e1 > 0.0) | (e2 > 0.0)) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }

    // Scaled distance, compared against [0, t_max·det] without dividing.
    let max_z_world = az.abs().max(bz.abs()).max(cz.abs());
    let (az, bz, cz) = (az * wr.sz, bz * wr.sz, cz * wr.sz);
    let t_scaled = e0 * az + e1 * bz + e2 * cz;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t < t_max) {
        return None;
    }

    // Reject hits whose t is not provably > 0 given the rounding in the steps above
    // (bounds derived term by term from γₙ of each operation chain). The sheared x and y carry
    // the error of `x + s_x·z` with the *unscaled* z (|s_x|, |s_y| ≤ 1 since z is the dominant
    // axis); only t uses the z scaled by 1/d_z. Mixing the two (as some references do) inflates
    // the bound enormously for short, unnormalised directions such as `spawn_ray_to`'s.
    let max_z = az.abs().max(bz.abs()).max(cz.abs());
    let delta_z = gamma(3) * max_z;
    let max_x = ax.abs().max(bx.abs()).max(cx.abs());
    let max_y = ay.abs().max(by.abs()).max(cy.abs());
    let delta_x = gamma(5) * (max_x + max_z_world);
    let delta_y = gamma(5) * (max_y + max_z_world);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t =
        3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit {
        t,
        b0: e0 * inv_det,
        b1: e1 * inv_det,
        b2: e2 * inv_det,
    })
}

/// The point with barycentrics `(b0, b1, b2)` and a conservative per-axis bound on its error
/// (`γ₇ · Σ|bᵢ pᵢ|`: interpolating from barycentrics avoids the `t`-proportional error of
/// `o + t·d`).
#[inline]
pub fn barycentric_point(
    b0: f32,
    b1: f32,
    b2: f32,
    p0: Vec3A,
    p1: Vec3A,
    p2: Vec3A,
) -> (Vec3A, Vec3A) {
    let p = p0 * b0 + p1 * b1 + p2 * b2;
    let err = ((p0 * b0).abs() + (p1 * b1).abs() + (p2 * b2).abs()) * gamma(7);
    (p, err)
}

/// `(p1 − p0) × (p2 − p0)` in f64. Its length is the square of the edge lengths, and the
/// length's square (taken to normalise it) is their fourth power: in f32 that overflows for
/// edges above ~4e9 scene units (a Cornell box in mm scaled by 1e7) and underflows below
/// ~1e-10, so big walls got a zero normal (no ray offset, zero cosines: lost indirect light) and
/// big emitters an infinite area. The f32 inputs' differences and products are exact or
/// rounded once in f64, whose range covers every finite f32 scene.
#[inline]
fn edge_cross(p0: Vec3A, p1: Vec3A, p2: Vec3A) -> DVec3 {
    let (p0, p1, p2) = (p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
    (p1 - p0).cross(p2 - p0)
}

/// Unit geometric normal of `p0 p1 p2`: counter-clockwise winding (seen from the side it
/// points to) is the front, `(p1 − p0) × (p2 − p0)` normalised (in f64, see `edge_cross`).
/// Zero for degenerate triangles.
#[inline]
pub fn geometric_normal(p0: Vec3A, p1: Vec3A, p2: Vec3A) -> Vec3A {
    Vec3A::from(edge_cross(p0, p1, p2).normalize_or_zero().as_vec3())
}

/// Area of triangle `p0 p1 p2` (scene units²; computed in f64, see `edge_cross`, and rounded
/// once: `+∞` only when the area itself exceeds f32's range).
#[inline]
pub fn triangle_area(p0: Vec3A, p1: Vec3A, p2: Vec3A) -> f32 {
    (0.5 * edge_cross(p0, p1, p2).length()) as f32
}

/// Barycentrics `(b0, b1, b2)` of `p` projected onto the plane of `p0 p1 p2` (in f64;
/// `None` for a degenerate triangle).
pub fn barycentrics_of(p: Vec3A, p0: Vec3A, p1: Vec3A, p2: Vec3A) -> Option<(f32, f32, f32)> {
    let (p, p0) = (p.as_dvec3(), p0.as_dvec3());
    let (e1, e2, d) = (p1.as_dvec3() - p0, p2.as_dvec3() - p0, p - p0);
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = a * c - b * b;
    if !(det > 0.0) {
        return None;
    }
    let (r1, r2) = (d.dot(e1), d.dot(e2));
    let b1 = (c * r1 - b * r2) / det;
    let b2 = (a * r2 - b * r1) / det;
    Some(((1.0 - b1 - b2) as f32, b1 as f32, b2 as f32))
}

/// ∂p/∂(b1, b2) of the flat triangle `p0 p1 p2` (`p = p0 + b1 (p1 − p0) + b2 (p2 − p0)`); its
/// normal does not turn.
#[inline]
pub fn triangle_derivatives(p0: Vec3A, p1: Vec3A, p2: Vec3A) -> SurfaceDerivatives {
    SurfaceDerivatives::flat(p1 - p0, p2 - p0)
}

/// Uniform barycentrics on a triangle from `u ∈ [0,1)²` (square-root warp; density is
/// constant per unit area).
#[inline]
pub fn sample_uniform_barycentrics(u: Vec2) -> (f32, f32, f32) {
    let su0 = u.x.max(0.0).sqrt();
    let b0 = 1.0 - su0;
    let b1 = u.y * su0;
    (b0, b1, (1.0 - b0 - b1).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> (Vec3A, Vec3A, Vec3A) {
        (
            Vec3A::new(0.0, 0.0, 0.0),
            Vec3A::new(1.0, 0.0, 0.0),
            Vec3A::new(0.0, 1.0, 0.0),
        )
    }

    // A ray straight down −z onto (0.25, 0.25) must hit at t = 1 with barycentrics
    // (0.5, 0.25, 0.25); tolerance 1e-6 is a few f32 ULPs at 1.
    #[test]
    fn hits_interior_point() {
        let (a, b, c) = tri();
        let r = Ray::new(Vec3A::new(0.25, 0.25, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        let h = intersect_triangle(&r, &WatertightRay::new(&r), f32::INFINITY, a, b, c).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!((h.b0 - 0.5).abs() < 1e-6 && (h.b1 - 0.25).abs() < 1e-6);
        assert_eq!(geometric_normal(a, b, c), Vec3A::Z);
    }

    // Misses outside, behind the origin and beyond t_max are all rejected.
    #[test]
    fn rejects_misses() {
        let (a, b, c) = tri();
        let r = Ray::new(Vec3A::new(0.75, 0.75, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        assert!(intersect_triangle(&r, &WatertightRay::new(&r), 10.0, a, b, c).is_none());
        let r = Ray::new(Vec3A::new(0.25, 0.25, 1.0), Vec3A::new(0.0, 0.0, 1.0));
        assert!(intersect_triangle(&r, &WatertightRay::new(&r), 10.0, a, b, c).is_none());
        let r = Ray::new(Vec3A::new(0.25, 0.25, 1.0), Vec3A::new(0.0, 0.0, -1.0));
        assert!(intersect_triangle(&r, &WatertightRay::new(&r), 0.5, a, b, c).is_none());
    }

    // The error bound of an interpolated point must contain the f64 exact interpolation.
    #[test]
    fn barycentric_error_contains_exact() {
        let p0 = Vec3A::new(1.0e4 + 0.1, 3.3, -7.7);
        let p1 = Vec3A::new(1.0e4 - 0.3, 3.9, -7.1);
        let p2 = Vec3A::new(1.0e4 + 0.7, 2.1, -7.4);
        let (b0, b1, b2) = (0.3f32, 0.45f32, 0.25f32);
        let (p, e) = barycentric_point(b0, b1, b2, p0, p1, p2);
        let exact =
            p0.as_dvec3() * b0 as f64 + p1.as_dvec3() * b1 as f64 + p2.as_dvec3() * b2 as f64;
        let d = (p.as_dvec3() - exact).abs();
        assert!(d.x <= e.x as f64 && d.y <= e.y as f64 && d.z <= e.z as f64);
    }

    // Normals and areas of huge and tiny triangles: the f32 cross product's squared length
    // (edge⁴) overflowed above edges of ~4e9 (zero normal, infinite area) and underflowed below
    // ~1e-10. A right triangle with legs L in the x-y plane must have normal +z exactly and area
    // L²/2 within 1e-6 relative (one f32 rounding of an exact f64 value) for L from 1e-15 to 1e15.
    #[test]
    fn huge_and_tiny_triangles_keep_normal_and_area() {
        for e in -15..=15 {
            let l = 10f32.powi(e);
            let (a, b, c) = (
                Vec3A::ZERO,
                Vec3A::new(l, 0.0, 0.0),
                Vec3A::new(0.0, l, 0.0),
            );
            assert_eq!(geometric_normal(a, b, c), Vec3A::Z, "legs {l:e}");
            let want = 0.5 * (l as f64) * (l as f64);
            let area = triangle_area(a, b, c) as f64;
            assert!(
                (area / want - 1.0).abs() < 1e-6,
                "legs {l:e}: area {area:e}"
            );
        }
    }
}
