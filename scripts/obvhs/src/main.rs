//! obvhs (compressed eight-wide BVH, PLOC builder) on the same triangles and rays as spectrace's
//! BVH and Embree: the comparison `docs/performance.md` ("obvhs") reports.
//!
//! Reads the input file of `scripts/embree/embree_rays.c` (little endian: u32 vertex count V,
//! u32 triangle count T, V×3 f32 positions, T×3 u32 indices, u32 ray count R, R×6 f32 rays).
//! Builds a CWBVH with `BvhBuildParams::medium_build()` (the preset its author describes as
//! "about Embree's build time with faster traversal") on one and on two rayon threads, then
//! traces every ray for the closest hit, best of three runs, with two triangle tests:
//! obvhs's own (`Triangle::intersect`, Möller–Trumbore, no error bound) and spectrace's
//! watertight test with its error bound (the same code as `host/src/geometry/triangle.rs`,
//! repeated here because this crate is built apart from the workspace). Prints one line:
//! `build1_s <s> build2_s <s> hits <n> mrays_1 <M/s> mrays_2 <M/s> wt_hits <n> wt_mrays_1 <M/s>`.

use std::time::{Duration, Instant};

use glam::Vec3A;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use rayon::prelude::*;

fn read_u32(b: &[u8], at: &mut usize) -> u32 {
    let v = u32::from_le_bytes(b[*at..*at + 4].try_into().expect("4 bytes"));
    *at += 4;
    v
}

fn read_f32(b: &[u8], at: &mut usize) -> f32 {
    f32::from_bits(read_u32(b, at))
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn best_of_three<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..3 {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("three runs"))
}

/// γₙ = n·ε/(1 − n·ε) with ε = 2⁻²⁴ (Pharr, Jakob & Humphreys, PBR 3rd ed., 3.9).
fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

/// spectrace's watertight test (Woop, Benthin & Wald 2013) with its error bound on `t`:
/// returns the hit distance or +∞.
fn watertight(ray: &Ray, t_max: f32, p0: Vec3A, p1: Vec3A, p2: Vec3A) -> f32 {
    let d = ray.direction;
    let a = d.abs();
    let kz = if a.x > a.y {
        if a.x > a.z {
            0
        } else {
            2
        }
    } else if a.y > a.z {
        1
    } else {
        2
    };
    let kx = (kz + 1) % 3;
    let ky = (kx + 1) % 3;
    let (sx, sy, sz) = (-d[kx] / d[kz], -d[ky] / d[kz], 1.0 / d[kz]);
    let a = p0 - ray.origin;
    let b = p1 - ray.origin;
    let c = p2 - ray.origin;
    let (az, bz, cz) = (a[kz], b[kz], c[kz]);
    let ax = a[kx] + sx * az;
    let ay = a[ky] + sy * az;
    let bx = b[kx] + sx * bz;
    let by = b[ky] + sy * bz;
    let cx = c[kx] + sx * cz;
    let cy = c[ky] + sy * cz;
    let mut e0 = bx * cy - by * cx;
    let mut e1 = cx * ay - cy * ax;
    let mut e2 = ax * by - ay * bx;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let (ax, ay, bx, by, cx, cy) = (
            ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
        );
        e0 = (bx * cy - by * cx) as f32;
        e1 = (cx * ay - cy * ax) as f32;
        e2 = (ax * by - ay * bx) as f32;
    }
    let miss = f32::INFINITY;
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return miss;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return miss;
    }
    let max_z_world = az.abs().max(bz.abs()).max(cz.abs());
    let (az, bz, cz) = (az * sz, bz * sz, cz * sz);
    let t_scaled = e0 * az + e1 * bz + e2 * cz;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return miss;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return miss;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t < t_max) {
        return miss;
    }
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
        return miss;
    }
    t
}

fn trace<F: Fn(&Ray, usize) -> f32 + Sync>(bvh: &CwBvh, rays: &[Ray], test: F) -> usize {
    rays.par_chunks(1024)
        .map(|c| {
            c.iter()
                .filter(|r| {
                    let mut hit = RayHit::none();
                    bvh.ray_traverse(**r, &mut hit, |ray, id| test(ray, id))
                })
                .count()
        })
        .sum()
}

fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| {
        eprintln!("usage: obvhs-rays FILE");
        std::process::exit(2)
    });
    let bytes = std::fs::read(&path).unwrap_or_else(|e| {
        eprintln!("obvhs-rays: {path}: {e}");
        std::process::exit(2)
    });
    let at = &mut 0;
    let (nv, nt) = (read_u32(&bytes, at) as usize, read_u32(&bytes, at) as usize);
    let positions: Vec<Vec3A> = (0..nv)
        .map(|_| {
            Vec3A::new(
                read_f32(&bytes, at),
                read_f32(&bytes, at),
                read_f32(&bytes, at),
            )
        })
        .collect();
    let tris: Vec<Triangle> = (0..nt)
        .map(|_| {
            let i = [0; 3].map(|_| read_u32(&bytes, at) as usize);
            Triangle {
                v0: positions[i[0]],
                v1: positions[i[1]],
                v2: positions[i[2]],
            }
        })
        .collect();
    let nr = read_u32(&bytes, at) as usize;
    let rays: Vec<Ray> = (0..nr)
        .map(|_| {
            let o = Vec3A::new(
                read_f32(&bytes, at),
                read_f32(&bytes, at),
                read_f32(&bytes, at),
            );
            let d = Vec3A::new(
                read_f32(&bytes, at),
                read_f32(&bytes, at),
                read_f32(&bytes, at),
            );
            Ray::new_inf(o, d)
        })
        .collect();

    let build = |threads: usize| {
        pool(threads).install(|| {
            best_of_three(|| {
                build_cwbvh_from_tris(
                    &tris,
                    BvhBuildParams::medium_build(),
                    &mut Duration::default(),
                )
            })
        })
    };
    let (build1, _) = build(1);
    let (build2, bvh) = build(2);
    // Triangles in leaf order, as spectrace stores its leaf records.
    let ordered: Vec<Triangle> = bvh
        .primitive_indices
        .iter()
        .map(|&i| tris[i as usize])
        .collect();
    let own = |ray: &Ray, id: usize| ordered[id].intersect(ray);
    let wt = |ray: &Ray, id: usize| {
        let t = &ordered[id];
        watertight(ray, ray.tmax, t.v0, t.v1, t.v2)
    };
    let (s1, hits) = pool(1).install(|| best_of_three(|| trace(&bvh, &rays, own)));
    let (s2, _) = pool(2).install(|| best_of_three(|| trace(&bvh, &rays, own)));
    let (w1, wt_hits) = pool(1).install(|| best_of_three(|| trace(&bvh, &rays, wt)));
    println!(
        "build1_s {build1:.4} build2_s {build2:.4} hits {hits} mrays_1 {:.4} mrays_2 {:.4} \
         wt_hits {wt_hits} wt_mrays_1 {:.4}",
        nr as f64 / s1 / 1e6,
        nr as f64 / s2 / 1e6,
        nr as f64 / w1 / 1e6
    );
}
