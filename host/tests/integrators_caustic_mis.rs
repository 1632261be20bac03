//! BDPT's MIS weights on a caustic seen through no glass: the glass-sphere caustic of
//! `scenes/bench/glass_sphere.ron` (a 0.1 m ball, IOR 1.5, on a diffuse floor, a 0.1 m one-sided
//! lamp 0.8 m up and 0.5 m aside). Its core is `L T T D E`, made by two strategies only:
//! light tracing (`s = 4, t = 1`) and a camera path that reaches the lamp through the ball by
//! BSDF sampling at the floor (`s = 0, t = 5`); the first has by far the higher density.
//!
//! 1. `weights_through_the_ball_match_brute_force_densities`: for real paths of both
//!    strategies, the implementation's power-heuristic weight against the weight computed from
//!    the two strategies' densities evaluated from scratch, in one common measure (area at the
//!    floor point × area at the lamp point), with the specular chain's Jacobians taken by
//!    finite differences of an independent trace through the sphere (no code of the renderer's
//!    transport).
//! 2. `bdpt_matches_light_tracing_in_the_caustic_core`: the statistical consequence: BDPT's
//!    per-pixel variance in the core at equal samples is no worse than light tracing's, and the
//!    `s = 0` strategies carry a small share of the core's value.
//!
//! Both fail with zero densities at specular vertices (pbrt's `remap0` treatment), which drops
//! the geometry terms on both sides of the chain and puts the core on `s = 0`.
//! Run: `cargo test --release -p spectrace --test integrators_caustic_mis` (about 10 s).

mod common_render;
use glam::{DVec3, Vec2, Vec3A};
use spectrace::camera::CameraSample;
use spectrace::integrator::bdpt::mis::{mis_weight, LIGHT_TRACING_MIS_SCALE};
use spectrace::integrator::select::render_planned;
use spectrace::integrator::subpath::camera_connection::connect_to_camera;
use spectrace::integrator::subpath::light_subpath::generate_light_subpath;
use spectrace::integrator::subpath::random_walk::{generate_camera_subpath, WalkShift};
use spectrace::integrator::subpath::vertex::{Vertex, VertexKind};
use spectrace::integrator::wavelengths::mixture::WavelengthMixture;
use spectrace::integrator::{EffectsRequest, RenderPlan};
use spectrace::integrator::{IntegratorKind, PathStats, SampleRng};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::f64::consts::PI;
use std::path::Path;

const SCENE: &str = include_str!("../../scenes/bench/glass_sphere.ron");

// The geometry, as in scenes/bench/glass_sphere.ron (`scene()` checks the lines).
const EYE: DVec3 = DVec3::new(-0.5, 0.2, 0.3);
const LOOK_AT: DVec3 = DVec3::new(-0.04, 0.05, 0.0);
const FOV_X_DEG: f64 = 30.0;
const RESOLUTION: (f64, f64) = (160.0, 120.0);
const CENTRE: DVec3 = DVec3::new(0.0, 0.1, 0.0);
const RADIUS: f64 = 0.1;
const IOR: f64 = 1.5;
const LAMP_Y: f64 = 0.8;
const LAMP_AREA: f64 = 0.01;
/// Object indices in the file: floor, ball, lamp.
const FLOOR: u32 = 0;
const BALL: u32 = 1;
const LAMP: u32 = 2;

fn scene() -> Scene {
    for line in [
        "params: (center: (0, 0.1, 0), radius: 0.1)),",
        "(name: \"glass\", type: \"dielectric\", params: (ior: 1.5)),",
        "params: (corner: (0.45, 0.8, -0.05), edge0: (0.1, 0, 0), edge1: (0, 0, 0.1))),",
        "params: (position: (-0.5, 0.2, 0.3), look_at: (-0.04, 0.05, 0), fov: 30,",
        "resolution: (160, 120))),",
    ] {
        assert!(SCENE.contains(line), "glass_sphere.ron changed: {line}");
    }
    let file = Path::new("glass_sphere.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Unpolarised Fresnel reflectance at incidence cosine `c` for relative index `eta` =
/// n_t/n_i, and the cosine of refraction (`None` at total internal reflection).
fn fresnel(c: f64, eta: f64) -> (f64, Option<f64>) {
    let sin_t2 = (1.0 - c * c) / (eta * eta);
    if sin_t2 >= 1.0 {
        return (1.0, None);
    }
    let ct = (1.0 - sin_t2).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    (0.5 * (rs * rs + rp * rp), Some(ct))
}

/// From `o` outside the ball along unit `d`: refracted in, across, refracted out. Returns
/// the exit point, the outgoing direction and the two transmission probabilities' product
/// (the dielectric picks transmission with probability 1 − F at each).
fn through_ball(o: DVec3, d: DVec3) -> Option<(DVec3, DVec3, f64)> {
    let oc = o - CENTRE;
    let b = oc.dot(d);
    let h = b * b - (oc.length_squared() - RADIUS * RADIUS);
    if h <= 0.0 {
        return None;
    }
    let t = -b - h.sqrt();
    if t <= 1e-9 {
        return None;
    }
    let p1 = o + t * d;
    let n1 = (p1 - CENTRE) / RADIUS;
    let ci = -d.dot(n1);
    let (f1, ct) = fresnel(ci, IOR);
    let d1 = (d / IOR + (ci / IOR - ct?) * n1).normalize();
    let oc = p1 - CENTRE;
    let b = oc.dot(d1);
    let t = -b
        + (b * b - (oc.length_squared() - RADIUS * RADIUS))
            .max(0.0)
            .sqrt();
    let p2 = p1 + t * d1;
    let n2 = (p2 - CENTRE) / RADIUS;
    let ci2 = d1.dot(n2);
    let (f2, ct2) = fresnel(ci2, 1.0 / IOR);
    let d2 = (IOR * d1 - (IOR * ci2 - ct2?) * n2).normalize();
    Some((p2, d2, (1.0 - f1) * (1.0 - f2)))
}

/// Where the ray from `o` along `d` through the ball meets the plane `y = plane_y`.
fn chain_end(o: DVec3, d: DVec3, plane_y: f64) -> Option<DVec3> {
    let (p, w, _) = through_ball(o, d)?;
    let t = (plane_y - p.y) / w.y;
    (t > 0.0).then(|| p + t * w)
}

/// `dA/dω` (m²/sr) of the map from the direction leaving `o` to the chain's end on the plane,
/// by central differences over two orthogonal tilts of `d`.
fn area_per_solid_angle(o: DVec3, d: DVec3, plane_y: f64) -> Option<f64> {
    let u = d.any_orthonormal_vector();
    let v = d.cross(u);
    let h = 1e-6;
    let at = |a: f64, b: f64| chain_end(o, (d + a * u + b * v).normalize(), plane_y);
    let du = (at(h, 0.0)? - at(-h, 0.0)?) / (2.0 * h);
    let dv = (at(0.0, h)? - at(0.0, -h)?) / (2.0 * h);
    Some(du.cross(dv).length())
}

/// The pinhole's area density (1/m²) of its ray hitting floor point `x`: `1/(A cos³θ)` per
/// steradian, `A` the image plane's area at unit distance, times `cos θ_x / d²`.
fn camera_area_density(x: DVec3) -> f64 {
    let forward = (LOOK_AT - EYE).normalize();
    let tan_x = (FOV_X_DEG.to_radians() / 2.0).tan();
    let tan_y = tan_x * RESOLUTION.1 / RESOLUTION.0;
    let a = 4.0 * tan_x * tan_y;
    let w = x - EYE;
    let d2 = w.length_squared();
    let w = w / d2.sqrt();
    let cos_cam = w.dot(forward);
    1.0 / (a * cos_cam.powi(3)) * (-w.y) / d2
}

/// The two strategies' densities of the path floor `xf` → ball (entered at `gf`) → lamp `xl`
/// (left it at `gl`) in the measure dA(floor)·dA(lamp): `(p_s0, p_lt)`.
fn brute_force(xf: DVec3, gf: DVec3, xl: DVec3, gl: DVec3) -> (f64, f64) {
    let wf = (gf - xf).normalize();
    let wl = (gl - xl).normalize();
    // s = 0: the camera's density at xf, the floor's cosine sampling towards the ball, the
    // two lobe choices, and the chain's Jacobian onto the lamp.
    let (_, _, tf) = through_ball(xf, wf).unwrap();
    let p0 =
        camera_area_density(xf) * (wf.y / PI) * tf / area_per_solid_angle(xf, wf, LAMP_Y).unwrap();
    // Light tracing: the lamp's point (one light, uniform by area), its cosine emission
    // towards the ball, the lobe choices, and the chain's Jacobian onto the floor.
    let (_, _, tl) = through_ball(xl, wl).unwrap();
    let pl = (1.0 / LAMP_AREA) * (-wl.y / PI) * tl / area_per_solid_angle(xl, wl, 0.0).unwrap();
    (p0, pl)
}

fn dv(p: Vec3A) -> DVec3 {
    DVec3::new(p.x as f64, p.y as f64, p.z as f64)
}

fn on(v: &Vertex, object: u32) -> bool {
    v.kind == VertexKind::Surface { object }
}

/// The light-tracing density over the `s = 0` one, from a power-heuristic weight `w` of one
/// of them (`t1` when `w` is light tracing's): the implementation's ratio.
fn implied_ratio(w: f32, t1: bool) -> f64 {
    let w = w as f64;
    let r2 = if t1 { w / (1.0 - w) } else { (1.0 - w) / w };
    r2.sqrt() / LIGHT_TRACING_MIS_SCALE as f64
}

/// Quantity: the ratio p_lt/p_s0 of the two strategies' densities that BDPT's weight of each
/// path implies, against the brute-force ratio; for camera paths of the caustic's core that hit
/// the lamp through the ball (`s = 0, t = 5`) and for light paths through the ball onto the
/// visible floor (`s = 4, t = 1`). Tolerance: 0.5% relative: the implementation works in f32
/// (positions to ~1e-7 m, cosines near grazing lose more) and the finite differences (step
/// 1e-6 rad in f64) are good to ~1e-6; the measured worst case is printed. With zero
/// densities at the specular vertices the ratio is off by G(ball, lamp)/G(floor, ball): measured
/// 0.0197 against 18.1 (a factor of about 900).
#[test]
fn weights_through_the_ball_match_brute_force_densities() {
    let scene = scene();
    let camera = scene.cameras.get(None).unwrap().camera.as_ref();
    let mixture = WavelengthMixture::new(&scene);
    let mut stats = PathStats::default();
    let mut path = Vec::new();
    let mut worst = 0.0f64;
    let mut checked = [0usize; 2];
    let mut ratios = Vec::new();
    // Camera paths through the core (pixels x 62..83, y 85..93).
    for k in 0..400_000u64 {
        if checked[0] >= 40 {
            break;
        }
        let mut rng = SampleRng::for_sample(3, k, 0);
        let lambda = mixture.sample(&mut rng);
        let p_film = Vec2::new(62.0, 85.0) + Vec2::new(21.0, 8.0) * rng.next_2d();
        let cs = CameraSample {
            p_film,
            p_lens: rng.next_2d(),
        };
        let cray = camera.generate_ray(&cs).unwrap();
        generate_camera_subpath(
            &scene,
            camera,
            cray.ray,
            cray.weight,
            &lambda,
            &mut rng,
            5,
            100,
            &mut path,
            &mut stats,
        );
        let through_ball = path.len() == 5
            && on(&path[1], FLOOR)
            && on(&path[2], BALL)
            && path[2].delta
            && on(&path[3], BALL)
            && path[3].delta
            && on(&path[4], LAMP);
        if !through_ball {
            continue;
        }
        let w = mis_weight(&scene, camera, &[], &path, None, 0, 5, &lambda, 1);
        let (xf, gf, gl, xl) = (dv(path[1].p), dv(path[2].p), dv(path[3].p), dv(path[4].p));
        // The independent trace must find this very path.
        let end = chain_end(xf, (gf - xf).normalize(), LAMP_Y).unwrap();
        assert!(
            (end - xl).length() < 1e-4,
            "trace ends at {end}, path at {xl}"
        );
        let (p0, pl) = brute_force(xf, gf, xl, gl);
        let (want, got) = (pl / p0, implied_ratio(w, false));
        ratios.push(want);
        worst = worst.max((got / want - 1.0).abs());
        assert!(
            (got / want - 1.0).abs() < 5e-3,
            "s = 0 path {k}: weight {w}, ratio p_lt/p_s0 {got} against brute force {want}"
        );
        checked[0] += 1;
    }
    // Light paths lamp → ball → ball → floor, joined to the camera.
    for k in 0..400_000u64 {
        if checked[1] >= 40 {
            break;
        }
        let mut rng = SampleRng::for_sample(5, k, 0);
        let lambda = mixture.sample(&mut rng);
        generate_light_subpath(
            &scene,
            &lambda,
            &mut rng,
            4,
            100,
            &mut path,
            &mut stats,
            WalkShift::Off,
        );
        let through_ball = path.len() == 4
            && on(&path[1], BALL)
            && path[1].delta
            && on(&path[2], BALL)
            && path[2].delta
            && on(&path[3], FLOOR);
        if !through_ball {
            continue;
        }
        let Some((_, _, cam)) =
            connect_to_camera(&scene, camera, &path, 4, &lambda, rng.next_2d(), &mut stats)
        else {
            continue;
        };
        let w = mis_weight(&scene, camera, &path, &[], Some(&cam), 4, 1, &lambda, 1);
        let (xl, gl, gf, xf) = (dv(path[0].p), dv(path[1].p), dv(path[2].p), dv(path[3].p));
        let end = chain_end(xl, (gl - xl).normalize(), 0.0).unwrap();
        assert!(
            (end - xf).length() < 1e-4,
            "trace ends at {end}, path at {xf}"
        );
        let (p0, pl) = brute_force(xf, gf, xl, gl);
        let (want, got) = (pl / p0, implied_ratio(w, true));
        ratios.push(want);
        worst = worst.max((got / want - 1.0).abs());
        assert!(
            (got / want - 1.0).abs() < 5e-3,
            "t = 1 path {k}: weight {w}, ratio p_lt/p_s0 {got} against brute force {want}"
        );
        checked[1] += 1;
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "checked {} s = 0 and {} t = 1 paths; worst relative error {worst:.2e}; p_lt/p_s0 from \
         {:.3} to {:.3} (median {:.3})",
        checked[0],
        checked[1],
        ratios[0],
        ratios[ratios.len() - 1],
        ratios[ratios.len() / 2]
    );
    assert!(
        checked[0] >= 20 && checked[1] >= 20,
        "too few paths: {checked:?}"
    );
}

/// Core pixels of the caustic (x 63..=80, y 87..=90 of 160×120: inside the part brighter than
/// a quarter of its peak, and clear of the ball's silhouette).
fn core_pixels() -> impl Iterator<Item = usize> {
    (87..=90).flat_map(|y| (63..=80).map(move |x| y * 160 + x))
}

/// Quantity: per-pixel variance of luminance Y in the core at 32 spp, BDPT over light tracing,
/// each estimated from two seeds' images ((A − B)²/2 averaged over the 72 pixels). Light
/// tracing is the good strategy here, and BDPT with right weights gives it nearly the whole
/// core: measured ratio 0.75–1.0 with one light subpath per camera sample (four seed pairs:
/// 0.79 for the pair used here), 0.24 with the default four (`bdpt::LIGHT_PATHS`); with zero
/// densities at the specular vertices 20–24 (23.7 here; the core went to `s = 0`, whose samples
/// are rare and large). Limit 2: the
/// ratio of two 72-pixel variance estimates scatters by about ±30% (heavier tails than
/// Gaussian), and 2 is still ten times below the failure. Also: the `s = 0` strategies' share
/// of the core's value below 20% (measured 4.6% with one light subpath, 0.3% with four; 99.9%
/// without the fix), and the two means within
/// 4 standard errors of each other (no bias between the estimators).
#[test]
fn bdpt_matches_light_tracing_in_the_caustic_core() {
    let scene = scene();
    let plan = RenderPlan::new(&scene, &EffectsRequest::default());
    let render = |kind: IntegratorKind, seed: u64, strategies: bool| {
        let settings = common_render::spp_settings(&scene, 32, seed);
        render_planned(&scene, &plan, &settings, kind, strategies, &|_, _| {}, None).unwrap()
    };
    let stats = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        let n = core_pixels().count() as f64;
        let var = core_pixels()
            .map(|i| (a[i][1] - b[i][1]).powi(2) / 2.0)
            .sum::<f64>()
            / n;
        let mean = core_pixels().map(|i| a[i][1] + b[i][1]).sum::<f64>() / (2.0 * n);
        (var, mean, n)
    };
    let b1 = render(IntegratorKind::Bdpt, 1, true);
    let b2 = render(IntegratorKind::Bdpt, 2, false);
    let l1 = render(IntegratorKind::Lt, 1, false);
    let l2 = render(IntegratorKind::Lt, 2, false);
    let (var_b, mean_b, n) = stats(&b1.result.image.xyz, &b2.result.image.xyz);
    let (var_l, mean_l, _) = stats(&l1.result.image.xyz, &l2.result.image.xyz);
    let core_sum = |img: &[[f64; 3]]| core_pixels().map(|i| img[i][1]).sum::<f64>();
    let total: f64 = b1
        .strategy_images
        .iter()
        .map(|(_, img)| core_sum(&img.xyz))
        .sum();
    let s0: f64 = b1
        .strategy_images
        .iter()
        .filter(|((s, _), _)| *s == 0)
        .map(|(_, img)| core_sum(&img.xyz))
        .sum();
    // The standard error of each mean: its pixels' variance over the two seeds and n pixels
    // (pixels are independent; their means differ, so the spread across pixels is not used).
    let se = (var_b / (2.0 * n) + var_l / (2.0 * n)).sqrt();
    println!(
        "core: variance BDPT {var_b:.4} LT {var_l:.4} (ratio {:.3}); s = 0 share {:.1}%; \
         mean BDPT {mean_b:.4} LT {mean_l:.4} ({:+.2} standard errors)",
        var_b / var_l,
        100.0 * s0 / total,
        (mean_b - mean_l) / se
    );
    assert!(
        var_b < 2.0 * var_l,
        "BDPT's variance in the caustic core is {:.2}× light tracing's",
        var_b / var_l
    );
    assert!(
        s0 < 0.2 * total,
        "s = 0 carries {:.1}% of the core",
        100.0 * s0 / total
    );
    assert!(
        (mean_b - mean_l).abs() < 4.0 * se,
        "core means differ: BDPT {mean_b}, LT {mean_l} (standard error {se})"
    );
}
