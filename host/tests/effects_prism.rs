//! The N-SF11 prism of scenes/prism.ron disperses white light as Snell's law says.
//!
//! Rays of single wavelengths are traced from the slit's centre along the beam axis through the
//! scene with the library (scene geometry, the dielectric material's own sampling), and the spot
//! they reach on the screen is compared with an independent 2-D Snell computation (own Sellmeier
//! evaluation from the SCHOTT N-SF11 data sheet, own prism planes). Tolerance: one camera pixel's
//! footprint on the screen, the resolution at which a render could show the spot.

use glam::{Vec2, Vec3A};
use spectrace::geometry::{spawn_ray, Ray};
use spectrace::material::{Frame, MaterialFlags, ShadingContext, TransportMode};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::{LaneMask, SampledWavelengths, LANES};
use std::path::Path;

const SCENE: &str = include_str!("../../scenes/prism.ron");
/// Object indices in scenes/prism.ron.
const SCREEN: u32 = 0;
const PRISM: u32 = 1;
/// Beam axis: from the slit centre at 33.5° above +x (the scene's comment).
const BEAM_DEG: f64 = 33.5;
/// Screen plane x (m) and the camera's pixel footprint on it (m): 2·1.2 m·tan(15°)/120 rows.
const SCREEN_X: f64 = 1.0;

fn scene() -> Scene {
    let file = Path::new("scenes/prism.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    build_scene(&desc, Path::new("scenes"), file, &[&BuiltinFactory]).unwrap()
}

fn pixel_footprint_m() -> f64 {
    2.0 * 1.2 * (15f64.to_radians()).tan() / 120.0
}

/// Slit centre (m): the slit quad's corner plus half its edges (scenes/prism.ron).
fn slit_centre() -> [f64; 2] {
    let (corner, e0) = ([-0.514183, -0.106933], [-0.005519, 0.008339]);
    [corner[0] + 0.5 * e0[0], corner[1] + 0.5 * e0[1]]
}

/// Where a ray of `nm` leaving the slit centre along the beam axis meets the screen, traced by
/// the renderer: the prism always refracts (u_lobe near 1 picks transmission over Fresnel
/// reflection), anything else but the screen fails the test.
fn traced_screen_y(scene: &Scene, nm: f32) -> f64 {
    let lambda = SampledWavelengths {
        lambda: [nm; LANES],
        pdf: [1.0; LANES],
        lanes: LaneMask::ALL,
    };
    let [sx, sy] = slit_centre();
    let a = BEAM_DEG.to_radians();
    // Start 1 mm in front of the slit so the ray does not meet the slit itself.
    let dir = Vec3A::new(a.cos() as f32, a.sin() as f32, 0.0);
    let mut ray = Ray::new(Vec3A::new(sx as f32, sy as f32, 0.0) + 1e-3 * dir, dir);
    for _ in 0..8 {
        let hit = scene
            .geometry
            .intersect(&ray, f32::INFINITY)
            .expect("the beam leaves the scene");
        if hit.object == SCREEN {
            return hit.point.y as f64;
        }
        assert_eq!(hit.object, PRISM, "the beam hits object {}", hit.object);
        let material = scene.objects.material(hit.object);
        let frame = Frame::from_normal(hit.shading_normal);
        let wo = frame.to_local(-ray.dir.normalize());
        let ctx = ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
        let bs = material
            .sample(
                wo,
                &ctx,
                &lambda,
                0.9999,
                Vec2::splat(0.5),
                TransportMode::Radiance,
            )
            .expect("the prism scatters");
        assert!(bs.flags.contains(MaterialFlags::TRANSMISSION));
        assert!(bs.flags.contains(MaterialFlags::DISPERSIVE));
        let wi = frame.to_world(bs.wi);
        ray = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, wi);
    }
    panic!("the beam did not reach the screen");
}

/// N-SF11 index at `nm` by Sellmeier's formula, coefficients from the SCHOTT data sheet.
fn n_sf11(nm: f64) -> f64 {
    let b = [1.73759695, 0.313747346, 1.89878101];
    let c = [0.013188707, 0.0623068142, 155.23629];
    let l2 = (nm * 1e-3).powi(2);
    (1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f64>()).sqrt()
}

/// Refract unit `d` at a plane with unit normal `n` facing the incoming side, `eta = n1/n2`.
fn refract(d: [f64; 2], n: [f64; 2], eta: f64) -> [f64; 2] {
    let cos_i = -(d[0] * n[0] + d[1] * n[1]);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    assert!(k > 0.0, "total internal reflection");
    let f = eta * cos_i - k.sqrt();
    [eta * d[0] + f * n[0], eta * d[1] + f * n[1]]
}

/// Ray `p + t·d` against the line through `a` and `b`: the point.
fn meet(p: [f64; 2], d: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    let t = ((a[0] - p[0]) * e[1] - (a[1] - p[1]) * e[0]) / den;
    [p[0] + t * d[0], p[1] + t * d[1]]
}

/// The same spot by Snell's law in the prism's cross-section (apex (0, 0.2√3), base corners
/// (±0.2, 0)). Returns (screen y in m, deviation in degrees).
fn snell_screen_y(nm: f64) -> (f64, f64) {
    let n = n_sf11(nm);
    let (left, right, apex) = ([-0.2, 0.0], [0.2, 0.0], [0.0, 0.2 * 3f64.sqrt()]);
    let a = BEAM_DEG.to_radians();
    let d0 = [a.cos(), a.sin()];
    let s = 3f64.sqrt() / 2.0;
    // Outward normals of the left and right faces.
    let n_left = [-s, 0.5];
    let n_right = [s, 0.5];
    let p1 = meet(slit_centre(), d0, left, apex);
    let d1 = refract(d0, n_left, 1.0 / n);
    let p2 = meet(p1, d1, right, apex);
    let d2 = refract(d1, [-n_right[0], -n_right[1]], n);
    let t = (SCREEN_X - p2[0]) / d2[0];
    let deviation = (d0[0] * d2[0] + d0[1] * d2[1]).acos().to_degrees();
    (p2[1] + t * d2[1], deviation)
}

/// At 450, 550 and 650 nm the traced spot lies within one pixel footprint (≈ 5.4 mm) of the
/// Snell spot, and the spots are many pixels apart, so the check resolves the dispersion.
#[test]
fn deviation_matches_snell_for_n_sf11() {
    let scene = scene();
    let px = pixel_footprint_m();
    let mut ys = Vec::new();
    for nm in [450.0, 550.0, 650.0] {
        let traced = traced_screen_y(&scene, nm as f32);
        let (expected, deviation) = snell_screen_y(nm);
        println!(
            "{nm} nm: n = {:.5}, deviation {deviation:.3}°, screen y traced {traced:.5} m, \
             Snell {expected:.5} m",
            n_sf11(nm)
        );
        assert!(
            (traced - expected).abs() < px,
            "{nm} nm: traced y {traced} m vs Snell {expected} m (pixel {px} m)"
        );
        ys.push(traced);
    }
    // Blue is deviated most: lowest on the screen; the 450–650 nm spread spans many pixels.
    assert!(ys[0] < ys[1] && ys[1] < ys[2], "order of spots {ys:?}");
    assert!((ys[2] - ys[0]) > 10.0 * px, "spread {} m", ys[2] - ys[0]);
}
