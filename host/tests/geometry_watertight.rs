//! Watertightness: rays aimed exactly at shared vertices and edges of closed meshes must never
//! slip through. Checked both through the BVH and by brute force over every triangle (so a
//! leak in the triangle test cannot be hidden by the BVH or vice versa).

use glam::{DVec3, Vec3A};
use spectrace::geometry::generate::icosphere;
use spectrace::geometry::{
    intersect_triangle, Geometry, Ray, Shape, ShapeDesc, Transform, TriangleMesh, WatertightRay,
};

/// Small deterministic generator (SplitMix64) so the test is reproducible without extra deps.
struct Rng(u64);
impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn world_mesh(mesh: &TriangleMesh, xf: &Transform) -> TriangleMesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        *p = xf.point(*p);
    }
    m
}

fn brute_force_hits(mesh: &TriangleMesh, ray: &Ray) -> bool {
    let wr = WatertightRay::new(ray);
    (0..mesh.indices.len()).any(|i| {
        let [a, b, c] = mesh.triangle(i);
        intersect_triangle(ray, &wr, f32::INFINITY, a, b, c).is_some()
    })
}

/// Aims rays from `origins` (all strictly inside the closed mesh) at every vertex and every
/// edge midpoint; returns (rays, BVH misses, brute-force misses).
fn count_leaks(mesh: &TriangleMesh, origins: &[Vec3A]) -> (usize, usize, usize) {
    let geometry = Geometry::build(vec![ShapeDesc {
        shape: Shape::Mesh(mesh.clone()),
        transform: Transform::IDENTITY,
    }])
    .expect("valid mesh");
    let mut targets: Vec<Vec3A> = mesh.positions.clone();
    for t in &mesh.indices {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a < b {
                targets.push((mesh.positions[a as usize] + mesh.positions[b as usize]) * 0.5);
            }
        }
    }
    let (mut rays, mut bvh_miss, mut brute_miss) = (0, 0, 0);
    for &o in origins {
        for &t in &targets {
            let ray = Ray::new(o, t - o);
            rays += 1;
            if geometry.intersect(&ray, f32::INFINITY).is_none() {
                bvh_miss += 1;
            }
            if !geometry.occluded(&ray, f32::INFINITY) {
                bvh_miss += 1;
            }
            if !brute_force_hits(mesh, &ray) {
                brute_miss += 1;
            }
        }
    }
    (rays, bvh_miss, brute_miss)
}

// Quantity: number of rays from inside a closed icosphere (1280 triangles) aimed at its 642
// vertices and 1920 edge midpoints that find no hit. Tolerance: exactly 0 — watertightness is a
// guarantee, not a statistic. Repeated at unit scale, at 1e-3 scale 0.1 units off the origin and
// at 1e5 scale 1e7 units away, with a rotation so no edge is axis-aligned.
#[test]
fn closed_icosphere_never_leaks() {
    let base = icosphere(3);
    let cases = [(1.0, 0.0), (1e-3, 0.1), (1e5, 1e7)];
    for (scale, offset) in cases {
        let xf = Transform::rotate(DVec3::new(0.3, 1.0, -0.2), 33.0)
            .unwrap()
            .then(&Transform::scale(DVec3::splat(scale)).unwrap())
            .then(&Transform::translate(DVec3::new(
                offset,
                -offset * 0.5,
                offset * 0.25,
            )));
        let mesh = world_mesh(&base, &xf);
        let mut rng = Rng(7);
        let mut origins = vec![xf.point(Vec3A::ZERO)];
        for _ in 0..3 {
            let p = Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.6 - 0.3;
            origins.push(xf.point(p));
        }
        let (rays, bvh_miss, brute_miss) = count_leaks(&mesh, &origins);
        assert!(rays > 10_000);
        assert_eq!(bvh_miss, 0, "BVH leaks at scale {scale} offset {offset}");
        assert_eq!(
            brute_miss, 0,
            "triangle test leaks at scale {scale} offset {offset}"
        );
    }
}

// Quantity: misses for rays from the centre of an axis-aligned cube (12 triangles, exactly
// representable coordinates) aimed at its 8 corners, 12 edge midpoints and along random
// directions, including rays whose direction has exact zero components. Tolerance: exactly 0.
#[test]
fn cube_edges_and_corners_never_leak() {
    let positions: Vec<Vec3A> = (0..8)
        .map(|i| {
            Vec3A::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) * 2.0 - 1.0
        })
        .collect();
    // Faces as quads (outward CCW), fanned into triangles.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut indices = Vec::new();
    for q in quads {
        indices.push([q[0], q[1], q[2]]);
        indices.push([q[0], q[2], q[3]]);
    }
    let mesh = TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices,
    };
    let mut rng = Rng(99);
    let origins: Vec<Vec3A> = std::iter::once(Vec3A::ZERO)
        .chain((0..4).map(|_| Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5))
        .collect();
    let (_, bvh_miss, brute_miss) = count_leaks(&mesh, &origins);
    assert_eq!((bvh_miss, brute_miss), (0, 0));
    // Axis-aligned and diagonal directions from the centre (zero components, 1/0 = ∞ slabs).
    let geometry = Geometry::build(vec![ShapeDesc {
        shape: Shape::Mesh(mesh.clone()),
        transform: Transform::IDENTITY,
    }])
    .unwrap();
    for x in -1..=1 {
        for y in -1..=1 {
            for z in -1..=1 {
                if (x, y, z) == (0, 0, 0) {
                    continue;
                }
                let ray = Ray::new(Vec3A::ZERO, Vec3A::new(x as f32, y as f32, z as f32));
                let hit = geometry.intersect(&ray, f32::INFINITY).expect("no leak");
                assert!(
                    (hit.t - 1.0).abs() < 1e-6,
                    "hits the unit-distance face/edge/corner"
                );
            }
        }
    }
}
