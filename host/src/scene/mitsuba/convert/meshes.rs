//! Triangle meshes standing in for Mitsuba's analytic shapes, with Mitsuba's uvs.

use super::values::{map, num, seq};
use glam::DVec3;
use ron::Value;

/// Segments of the polygons that stand in for Mitsuba's analytic disks and cylinders (their
/// area is then 1 − 2.5e-4 of the true one).
pub const ROUND_SEGMENTS: usize = 128;

pub(super) fn mesh_value(m: &crate::geometry::TriangleMesh) -> Value {
    let mut e = vec![
        (
            "positions",
            seq(m
                .positions
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64), num(p.z as f64)]))
                .collect()),
        ),
        (
            "indices",
            seq(m
                .indices
                .iter()
                .map(|t| {
                    seq(t
                        .iter()
                        .map(|&i| Value::Number(ron::Number::from(i as i64)))
                        .collect())
                })
                .collect()),
        ),
    ];
    if let Some(n) = &m.normals {
        e.push((
            "normals",
            seq(n
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64), num(p.z as f64)]))
                .collect()),
        ));
    }
    if let Some(t) = &m.uvs {
        e.push((
            "uvs",
            seq(t
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64)]))
                .collect()),
        ));
    }
    map(e)
}

/// A sphere of radius `r` at `centre` with Mitsuba's sphere uvs: `u = φ/2π` (φ = atan2(y, x)
/// in [0, 2π)), `v = θ/π` (θ from +z), stored with v flipped (spectrace's v = 0 is an image's
/// bottom row, Mitsuba's its top row). [`ROUND_SEGMENTS`] sectors × half as many rings; the
/// seam's vertices are doubled (u = 0 and 1) and each pole has a vertex per sector (its u at
/// the sector's middle), so no triangle interpolates across the seam. Smooth normals.
pub fn uv_sphere_mesh(centre: DVec3, r: f64) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    let (np, nt) = (ROUND_SEGMENTS, ROUND_SEGMENTS / 2);
    let (mut positions, mut normals, mut uvs, mut indices) = (vec![], vec![], vec![], vec![]);
    for k in 0..=nt {
        let theta = std::f64::consts::PI * k as f64 / nt as f64;
        for j in 0..=np {
            // At the poles, u in the middle of the sector below (or above) the vertex.
            let uj = if k == 0 || k == nt {
                (j as f64 + 0.5) / np as f64
            } else {
                j as f64 / np as f64
            };
            let phi = std::f64::consts::TAU * j as f64 / np as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let p = centre + n * r;
            positions.push(Vec3A::new(p.x as f32, p.y as f32, p.z as f32));
            normals.push(Vec3A::new(n.x as f32, n.y as f32, n.z as f32));
            uvs.push(Vec2::new(uj as f32, (1.0 - k as f64 / nt as f64) as f32));
        }
    }
    let at = |k: usize, j: usize| (k * (np + 1) + j) as u32;
    for k in 0..nt {
        for j in 0..np {
            let (a, b, c, d) = (at(k, j), at(k + 1, j), at(k + 1, j + 1), at(k, j + 1));
            if k == 0 {
                // a is the north pole's vertex of sector j.
                indices.push([a, b, c]);
            } else if k + 1 == nt {
                // b is the south pole's vertex of sector j.
                indices.push([a, b, d]);
            } else {
                indices.push([a, b, c]);
                indices.push([a, c, d]);
            }
        }
    }
    crate::geometry::TriangleMesh {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

pub(super) fn flip_winding(m: &mut crate::geometry::TriangleMesh) {
    for t in &mut m.indices {
        t.swap(1, 2);
    }
    if let Some(n) = &mut m.normals {
        for v in n {
            *v = -*v;
        }
    }
}

/// Mitsuba 3's uv on its `cube` at point `p` of the face whose outward normal is `s` along
/// axis `a` (0, 1, 2 = x, y, z), as Mitsuba 3.9.1 reports it (`si.uv` of rays hitting each
/// face, `scripts/mitsuba_import/uv_probe.py`): affine in the face's two other coordinates.
pub(super) fn mitsuba_cube_uv(a: usize, s: f32, p: glam::Vec3A) -> (f32, f32) {
    let h = |x: f32| (x + 1.0) / 2.0;
    let g = |x: f32| (1.0 - x) / 2.0;
    match (a, s > 0.0) {
        (0, false) => (h(p.y), h(p.z)),
        (0, true) => (h(p.y), g(p.z)),
        (1, false) => (h(p.z), h(p.x)),
        (1, true) => (g(p.x), g(p.z)),
        (2, false) => (g(p.y), h(p.x)),
        _ => (h(p.y), h(p.x)),
    }
}

/// Mitsuba's `cube`: [−1, 1]³, outward faces, four vertices per face, with Mitsuba's uvs
/// (`mitsuba_cube_uv`) stored with v flipped (spectrace's v = 0 is an image's bottom row).
pub fn cube_mesh(flip: bool) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    let mut m = crate::geometry::TriangleMesh {
        positions: vec![],
        normals: None,
        uvs: Some(vec![]),
        indices: vec![],
    };
    let axes = [Vec3A::X, Vec3A::Y, Vec3A::Z];
    for a in 0..3 {
        for s in [-1.0f32, 1.0] {
            let n = axes[a] * s;
            let u = axes[(a + 1) % 3];
            let v = n.cross(u);
            let k = m.positions.len() as u32;
            for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = n + u * du + v * dv;
                m.positions.push(p);
                if let Some(t) = &mut m.uvs {
                    let (mu, mv) = mitsuba_cube_uv(a, s, p);
                    t.push(Vec2::new(mu, 1.0 - mv));
                }
            }
            m.indices.push([k, k + 1, k + 2]);
            m.indices.push([k, k + 2, k + 3]);
        }
    }
    if flip {
        flip_winding(&mut m);
    }
    m
}

/// Mitsuba's `disk`: the unit disk in z = 0, normal +z, with Mitsuba's polar uvs, `u = r`,
/// `v = φ/2π` (φ = atan2(y, x) in [0, 2π)), stored with v flipped: [`ROUND_SEGMENTS`] sectors
/// by 16 rings (a fan in the innermost), so that interpolating the uvs linearly inside each
/// triangle stays within 10⁻³ of the polar coordinates except within 1/16 of the centre, where
/// the fan's v may be off by up to half a sector (1/256). The seam's vertices are doubled (v = 0
/// and 1) and the centre has a vertex per sector (v at the sector's middle), so no triangle
/// interpolates across the seam.
pub fn disk_mesh(flip: bool) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    const RINGS: usize = 16;
    let n = ROUND_SEGMENTS;
    let (mut positions, mut uvs, mut indices) = (vec![], vec![], vec![]);
    for i in 0..n {
        positions.push(Vec3A::ZERO);
        uvs.push(Vec2::new(0.0, (1.0 - (i as f64 + 0.5) / n as f64) as f32));
    }
    // Ring k (1…RINGS) at radius k/RINGS, vertex i at φ = 2πi/n (i = n doubles i = 0).
    let ring = |k: usize, i: usize| (n + (k - 1) * (n + 1) + i) as u32;
    for k in 1..=RINGS {
        let r = k as f64 / RINGS as f64;
        for i in 0..=n {
            let phi = std::f64::consts::TAU * i as f64 / n as f64;
            let (s, c) = phi.sin_cos();
            positions.push(Vec3A::new((r * c) as f32, (r * s) as f32, 0.0));
            uvs.push(Vec2::new(r as f32, (1.0 - i as f64 / n as f64) as f32));
        }
    }
    for i in 0..n {
        indices.push([i as u32, ring(1, i), ring(1, i + 1)]);
        for k in 1..RINGS {
            let (a, b, c, d) = (
                ring(k, i),
                ring(k + 1, i),
                ring(k + 1, i + 1),
                ring(k, i + 1),
            );
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    let mut m = crate::geometry::TriangleMesh {
        positions,
        normals: None,
        uvs: Some(uvs),
        indices,
    };
    if flip {
        flip_winding(&mut m);
    }
    m
}

/// Mitsuba's `cylinder` (open tube from p0 to p1), outward normals.
pub fn cylinder_mesh(p0: DVec3, p1: DVec3, r: f64, flip: bool) -> crate::geometry::TriangleMesh {
    use glam::Vec3A;
    let axis = (p1 - p0).normalize();
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let n = ROUND_SEGMENTS;
    let (mut positions, mut normals, mut indices) = (vec![], vec![], vec![]);
    for i in 0..n {
        let phi = std::f64::consts::TAU * i as f64 / n as f64;
        let d = u * phi.cos() + v * phi.sin();
        for base in [p0, p1] {
            let q = base + d * r;
            positions.push(Vec3A::new(q.x as f32, q.y as f32, q.z as f32));
            normals.push(Vec3A::new(d.x as f32, d.y as f32, d.z as f32));
        }
        let a = 2 * i as u32;
        let b = 2 * ((i + 1) % n) as u32;
        indices.push([a, b, b + 1]);
        indices.push([a, b + 1, a + 1]);
    }
    let mut m = crate::geometry::TriangleMesh {
        positions,
        normals: Some(normals),
        uvs: None,
        indices,
    };
    if flip {
        flip_winding(&mut m);
    }
    m
}
