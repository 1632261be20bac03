//! Light-sampling densities checked against analytic solid angles and areas, and object
//! construction rules (transforms of spheres, mirrored meshes).

use std::f64::consts::PI;

use glam::{DVec3, Vec2, Vec3A};
use spectrace::geometry::generate::{grid, icosphere};
use spectrace::geometry::{Geometry, GeometryError, Ray, Shape, ShapeDesc, Transform};

/// A `2a × 2b` rectangle at distance `d` on the −z axis, facing +z, as a quad (object 0) and as
/// a 8×4 grid mesh (object 1, offset sideways by 10 so the two never overlap), plus a sphere of
/// radius 1 at distance 5 (object 2).
fn lights(a: f32, b: f32, d: f32) -> Geometry {
    let grid_xf = Transform::scale(DVec3::new(2.0 * a as f64, 1.0, 2.0 * b as f64))
        .unwrap()
        .then(&Transform::translate(DVec3::new(-a as f64, 0.0, -b as f64)))
        .then(&Transform::rotate(DVec3::X, 90.0).unwrap())
        .then(&Transform::translate(DVec3::new(10.0, 0.0, -d as f64)));
    Geometry::build(vec![
        ShapeDesc {
            shape: Shape::Quad {
                corner: Vec3A::new(-a, -b, -d),
                edge0: Vec3A::new(2.0 * a, 0.0, 0.0),
                edge1: Vec3A::new(0.0, 2.0 * b, 0.0),
            },
            transform: Transform::IDENTITY,
        },
        ShapeDesc {
            shape: Shape::Mesh(grid(8, 4)),
            transform: grid_xf,
        },
        ShapeDesc {
            shape: Shape::Sphere {
                center: Vec3A::new(0.0, 0.0, 5.0),
                radius: 1.0,
            },
            transform: Transform::IDENTITY,
        },
    ])
    .unwrap()
}

/// Mean of 1/pdf (= the solid angle covered) over a stratified 200×200 grid of samples, and
/// the largest relative mismatch between a sample's pdf and `pdf_solid_angle` for its point.
fn solid_angle_estimate(g: &Geometry, object: u32, reference: Vec3A) -> (f64, f64) {
    let n = 200;
    let (mut sum, mut worst) = (0.0f64, 0.0f64);
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let s = g
                .sample_solid_angle(object, reference, u)
                .expect("visible light");
            sum += 1.0 / s.pdf as f64;
            let p = g.pdf_solid_angle(object, reference, s.point, s.normal) as f64;
            worst = worst.max((p - s.pdf as f64).abs() / s.pdf as f64);
        }
    }
    (sum / (n * n) as f64, worst)
}

// Quantity: solid angle of a 2×1 rectangle seen on-axis from distance 2, estimated as E[1/pdf]
// of area sampling converted to solid angle, for the quad and for the same rectangle as a grid
// mesh; analytic Ω = 4·asin(ab/√((a²+d²)(b²+d²))) (rectangle on-axis formula). Tolerance 0.2%:
// the 40,000-sample stratified estimate of this smooth integrand has a relative error well
// below 1e-3. Also the sphere's cone sampling must give exactly 2π(1 − cos θmax) (1e-5: f32
// pdf rounding) and pdf_solid_angle must reproduce each sample's pdf (1e-4 relative).
#[test]
fn solid_angle_pdfs_integrate_to_analytic_solid_angles() {
    let (a, b, d) = (1.0f32, 0.5f32, 2.0f32);
    let g = lights(a, b, d);
    let (a64, b64, d64) = (a as f64, b as f64, d as f64);
    let omega =
        4.0 * (a64 * b64 / ((a64 * a64 + d64 * d64) * (b64 * b64 + d64 * d64)).sqrt()).asin();
    let (quad, worst_q) = solid_angle_estimate(&g, 0, Vec3A::ZERO);
    let (mesh, worst_m) = solid_angle_estimate(&g, 1, Vec3A::new(10.0, 0.0, 0.0));
    assert!(
        ((quad - omega) / omega).abs() < 2e-3,
        "quad {quad} vs {omega}"
    );
    assert!(
        ((mesh - omega) / omega).abs() < 2e-3,
        "mesh {mesh} vs {omega}"
    );
    assert!(worst_q < 1e-4 && worst_m < 1e-4, "{worst_q} {worst_m}");
    let (sphere, worst_s) = solid_angle_estimate(&g, 2, Vec3A::ZERO);
    let cone = 2.0 * PI * (1.0 - (1.0f64 - 1.0 / 25.0).sqrt());
    assert!(
        ((sphere - cone) / cone).abs() < 1e-5,
        "sphere {sphere} vs {cone}"
    );
    assert!(worst_s < 1e-4);
}

// Quantity: area-sampling pdf equals 1/area (areas 2, 2 and 4π, 1e-5 relative for f32), and
// the mean sampled point of the quad is its centre (tolerance 0.01 ≫ the 1/√10⁴-scaled standard
// error ~0.006·side of a uniform mean over 10,000 stratified samples).
#[test]
fn area_sampling_is_uniform() {
    let g = lights(1.0, 0.5, 2.0);
    for (obj, area) in [(0u32, 2.0f64), (1, 2.0), (2, 4.0 * PI)] {
        let pdf = g.pdf_area(obj) as f64;
        assert!((pdf * area - 1.0).abs() < 1e-5, "object {obj}: pdf {pdf}");
        assert!(((g.object_area(obj) as f64) - area).abs() < 1e-5 * area);
    }
    let mut mean = Vec3A::ZERO;
    let n = 100;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let s = g.sample_area(0, u).unwrap();
            assert_eq!(s.normal, Vec3A::Z);
            assert!(s.point.x.abs() <= 1.0 && s.point.y.abs() <= 0.5 && s.point.z == -2.0);
            mean += s.point;
        }
    }
    mean /= (n * n) as f32;
    assert!(
        (mean - Vec3A::new(0.0, 0.0, -2.0)).length() < 0.01,
        "{mean}"
    );
}

// Quantity: a quad's sample numbers are its chart: `sample_area(u)` is the point
// `corner + u.x·edge0 + u.y·edge1` (to 1e-6 of the side, f32 rounding) on either half
// (u.x ≥ u.y and below), and `sample_coords` of that point gives `u` back (to 1e-5), which is
// what lets the path tracer's visibility guide draw `u` from a density of its own and weigh
// a hit on the light with the same density. Uniform by area follows (the chart is linear).
// A small mesh (the 8 × 4 grid: 64 triangles) inverts its own map (area CDF, then square-root
// barycentrics) to 1e-4 in u (the square root's inverse squares the rounding near a vertex);
// spheres offer no coordinates.
#[test]
fn quad_samples_through_its_chart_and_inverts_it() {
    let g = lights(1.0, 0.5, 2.0);
    let n = 37;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.3) / n as f32, (j as f32 + 0.6) / n as f32);
            let s = g.sample_area(0, u).unwrap();
            let chart = Vec3A::new(-1.0 + 2.0 * u.x, -0.5 + u.y, -2.0);
            assert!(
                (s.point - chart).length() < 1e-6,
                "{u}: {} vs {chart}",
                s.point
            );
            let back = g.sample_coords(0, s.point).unwrap();
            assert!((back - u).length() < 1e-5, "{u} came back as {back}");
        }
    }
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.3) / n as f32, (j as f32 + 0.6) / n as f32);
            let s = g.sample_area(1, u).unwrap();
            let back = g.sample_coords(1, s.point).unwrap();
            assert!((back - u).length() < 1e-4, "mesh: {u} came back as {back}");
        }
    }
    assert!(g.sample_coords(2, Vec3A::new(0.0, 0.0, 4.0)).is_none());
}

// Object rules: a sphere under non-uniform scale is rejected (it would no longer be a sphere);
// under a uniform scale its radius and area scale; a mirrored icosphere keeps outward normals
// (hit from outside, the normal faces the ray origin); bad objects name their index.
#[test]
fn object_transforms() {
    let e = Geometry::build(vec![
        ShapeDesc {
            shape: Shape::Mesh(icosphere(1)),
            transform: Transform::IDENTITY,
        },
        ShapeDesc {
            shape: Shape::Sphere {
                center: Vec3A::ZERO,
                radius: 1.0,
            },
            transform: Transform::scale(DVec3::new(1.0, 2.0, 1.0)).unwrap(),
        },
    ])
    .unwrap_err();
    assert!(
        matches!(e, GeometryError::InvalidObject { object: 1, .. }),
        "{e}"
    );
    let g = Geometry::build(vec![
        ShapeDesc {
            shape: Shape::Sphere {
                center: Vec3A::ZERO,
                radius: 1.0,
            },
            transform: Transform::scale(DVec3::splat(3.0)).unwrap(),
        },
        ShapeDesc {
            shape: Shape::Mesh(icosphere(2)),
            transform: Transform::scale(DVec3::new(-1.0, 1.0, 1.0))
                .unwrap()
                .then(&Transform::translate(DVec3::new(10.0, 0.0, 0.0))),
        },
    ])
    .unwrap();
    assert!((g.object_area(0) as f64 - 4.0 * PI * 9.0).abs() < 1e-3);
    for dir in [Vec3A::X, -Vec3A::X, Vec3A::Y, Vec3A::new(0.3, -0.5, 0.8)] {
        let origin = Vec3A::new(10.0, 0.0, 0.0) + dir.normalize() * 3.0;
        let h = g.intersect(&Ray::new(origin, -dir), f32::INFINITY).unwrap();
        assert_eq!(h.object, 1);
        assert!(
            h.geometric_normal.dot(dir) > 0.0,
            "mirrored mesh normal points inward"
        );
        assert!(h.shading_normal.dot(dir) > 0.0);
    }
    let bad = Geometry::build(vec![ShapeDesc {
        shape: Shape::Quad {
            corner: Vec3A::ZERO,
            edge0: Vec3A::X,
            edge1: Vec3A::X * 2.0,
        },
        transform: Transform::IDENTITY,
    }]);
    assert!(matches!(
        bad,
        Err(GeometryError::InvalidObject { object: 0, .. })
    ));
}

// Regression (white-furnace finding): a reference point on the sphere's own surface must not
// use cone sampling (its "cone" is a hemisphere whose nearest hit is the point itself, giving
// zero-length connections). Quantity: fraction of samples that land within 1e-3·r of the
// reference; area sampling makes that ~1e-6, the degenerate cone made it ~100%. Tolerance 1%.
// Also pdf_solid_angle must agree with the sample's pdf (1e-4 relative).
#[test]
fn sphere_reference_on_its_own_surface_uses_area_sampling() {
    let g = Geometry::build(vec![ShapeDesc {
        shape: Shape::Sphere {
            center: Vec3A::new(3.0, -2.0, 1.0),
            radius: 1.0,
        },
        transform: Transform::IDENTITY,
    }])
    .unwrap();
    let on_surface = g.sample_area(0, Vec2::new(0.3, 0.7)).unwrap().point;
    let (mut near, mut total) = (0, 0);
    for i in 0..64 {
        for j in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
            let Some(s) = g.sample_solid_angle(0, on_surface, u) else {
                continue;
            };
            total += 1;
            if (s.point - on_surface).length() < 1e-3 {
                near += 1;
            }
            let p = g.pdf_solid_angle(0, on_surface, s.point, s.normal);
            assert!(((p - s.pdf) / s.pdf).abs() < 1e-4, "{p} vs {}", s.pdf);
        }
    }
    assert!(total > 4000, "{total}");
    assert!(
        (near as f64) < 0.01 * total as f64,
        "{near} of {total} samples at the reference"
    );
}
