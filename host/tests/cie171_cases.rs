//! Test cases of CIE 171:2006 ("Test cases to assess the accuracy of lighting computer
//! programs") that spectrace can express, as one table: expected, measured, standard error,
//! pass. Run with `--nocapture` to see the table.
//!
//! Expected values: the report's own tables could not be obtained for this work (the report is
//! not freely published; its errata are collected by I. Ashdown, "CIE 171:2006 – Errata",
//! Lighting Analysts, 2008 onwards, after Dau 2007 and Osborne 2012), so every expected value
//! here is derived independently from the closed form or the defining integral of the case as
//! the report states it — the inverse-square cosine law for the point source, Lambert's
//! polygon formula for the diffuse area source, the integrating-sphere relation for diffuse
//! inter-reflections, and the sky component ∫ L(ω) cos θ dω over an opening under the CIE
//! standard general sky (ISO 15469, its formula typed into `common_sky`, integrated here on
//! 300 × 300 points of the opening). These are the quantities the report's analytic cases
//! tabulate; the geometry is the report's kind (a 4 m × 4 m × 3 m room with black surfaces, a
//! roof or façade opening), not necessarily its exact dimensions.
//!
//! Tolerance: the report gives reference values, not a pass band for stochastic programs; a
//! point passes within 4σ + 0.5 % (σ its standard error, required below 2 %; 0.5 % covers the
//! photometric integration and f32 geometry), i.e. an unbiased result fails with probability
//! < 1e-4 per point, and a missing cos θ, π or a wrong sky parameter fails.

use glam::DVec3;
use spectrace::integrator::{IntegratorKind, PathTracer};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::sensor::{measure, Estimator, MeasureSettings};
use std::f64::consts::PI;
use std::path::Path;

mod common_sky;
use common_sky::{efficacy, standard, standard_horizontal, TYPES};

fn scene(text: &str) -> Scene {
    let desc = parse_scene_str(text, Path::new("cie171.ron")).unwrap();
    build_scene(
        &desc,
        Path::new("."),
        Path::new("cie171.ron"),
        &[&BuiltinFactory],
    )
    .unwrap()
}

/// Tiny 1-point grids at `points`, facing +y.
fn point_sensors(points: &[DVec3]) -> String {
    points
        .iter()
        .enumerate()
        .map(|(k, p)| {
            format!(
                r#"(name: "p{k}", type: "illuminance_grid", params: (corner: ({}, {}, {}),
                    edge0: (0.002, 0, 0), edge1: (0, 0, -0.002), resolution: (1, 1)))"#,
                p.x - 0.001,
                p.y,
                p.z + 0.001
            )
        })
        .collect::<Vec<_>>()
        .join(",")
}

struct Row {
    case: String,
    point: usize,
    expected: f64,
    measured: f64,
    se: f64,
}

impl Row {
    fn pass(&self) -> bool {
        self.se < 0.02 * self.expected
            && (self.measured - self.expected).abs() <= 4.0 * self.se + 5e-3 * self.expected
    }
}

fn measure_points(s: &Scene, case: &str, expected: &[f64], samples: u32, rows: &mut Vec<Row>) {
    for (k, &e) in expected.iter().enumerate() {
        let grid = s
            .sensors
            .iter()
            .find(|g| g.name == format!("p{k}"))
            .unwrap();
        let r = measure(
            s,
            grid,
            &MeasureSettings {
                estimator: Estimator::for_integrator(IntegratorKind::Pt),
                samples,
                seed: 171,
                threads: None,
                tracer: PathTracer::default(),
            },
        )
        .unwrap();
        rows.push(Row {
            case: case.to_string(),
            point: k,
            expected: e,
            measured: r.lux[0],
            se: r.stderr[0],
        });
    }
}

/// ∫ cos θ dω over polygon `v` (relative to the receiver) about unit `n` (Lambert).
fn projected_solid_angle(v: &[DVec3], n: DVec3) -> f64 {
    let mut s = 0.0;
    for i in 0..v.len() {
        let (a, b) = (v[i].normalize(), v[(i + 1) % v.len()].normalize());
        let g = a.dot(b).clamp(-1.0, 1.0).acos();
        let c = a.cross(b);
        if c.length() > 0.0 {
            s += g * c.normalize().dot(n);
        }
    }
    0.5 * s.abs()
}

const ROOM_MATERIALS: &str = r#"materials: [(name: "black", type: "lambertian", params: (reflectance: 0)),
    (name: "lum", type: "emissive", params: (radiance: "e", luminance_cd_m2: 1000))]"#;

fn quad(name: &str, corner: [f64; 3], e0: [f64; 3], e1: [f64; 3]) -> String {
    format!(
        r#"(name: "{name}", type: "quad", material: "black", params: (corner: ({}, {}, {}), edge0: ({}, {}, {}), edge1: ({}, {}, {})))"#,
        corner[0], corner[1], corner[2], e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]
    )
}

/// The sky component at `p` (lx) of an opening given as a parallelogram `corner + s·e0 + t·e1`
/// under sky type `ty` (sun at altitude/azimuth `sun`, degrees) of horizontal illuminance
/// `e_h`: ∫ L cos θ_p cos θ_o / r² dA, midpoint rule on 300 × 300 points. Scene frame: up +y,
/// north −z, east +x.
fn sky_component(
    p: DVec3,
    corner: DVec3,
    e0: DVec3,
    e1: DVec3,
    ty: usize,
    sun: (f64, f64),
    e_h: f64,
) -> f64 {
    let t = &TYPES[ty - 1];
    let zs = (90.0 - sun.0).to_radians();
    let azs = sun.1.to_radians();
    let lz = e_h / standard_horizontal(t, zs);
    let n_o = e0.cross(e1).normalize();
    let da = e0.cross(e1).length();
    let n = 300;
    let mut s = 0.0;
    for i in 0..n {
        for j in 0..n {
            let q =
                corner + e0 * ((i as f64 + 0.5) / n as f64) + e1 * ((j as f64 + 0.5) / n as f64);
            let d = q - p;
            let r2 = d.length_squared();
            let u = d / r2.sqrt();
            let (cos_p, cos_o) = (u.y, u.dot(n_o).abs());
            let z = u.y.clamp(-1.0, 1.0).acos();
            let az = u.x.atan2(-u.z);
            s += lz * standard(t, z, az, zs, azs) * cos_p * cos_o / r2;
        }
    }
    s * da / (n * n) as f64
}

#[test]
fn cie171_direct_and_interreflected() {
    let mut rows = Vec::new();

    // Point source over a plane: 100 W isotropic (flat spectrum) 2 m above a black floor.
    {
        let pts = [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 2.0),
        ];
        let s = scene(&format!(
            r#"({ROOM_MATERIALS}, objects: [{}],
               lights: [(name: "p", type: "point", params: (position: (0, 2, 0), power: 100, spd: "e"))],
               cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (2, 2)))],
               sensors: [{}])"#,
            quad(
                "floor",
                [-10.0, 0.0, 10.0],
                [20.0, 0.0, 0.0],
                [0.0, 0.0, -20.0]
            ),
            point_sensors(&pts)
        ));
        let i_cd = efficacy("e") * 100.0 / (4.0 * PI);
        let want: Vec<f64> = pts
            .iter()
            .map(|p| {
                let d = DVec3::new(0.0, 2.0, 0.0) - *p;
                i_cd * (d.y / d.length()) / d.length_squared()
            })
            .collect();
        measure_points(&s, "point source, E = I cos θ / d²", &want, 4096, &mut rows);
    }

    // Diffuse area source: 1 m × 2 m Lambertian, 1000 cd/m², 2 m above the floor, facing down.
    {
        let pts = [
            DVec3::ZERO,
            DVec3::new(0.5, 0.0, 1.0),
            DVec3::new(1.5, 0.0, 1.5),
        ];
        let s = scene(&format!(
            r#"({ROOM_MATERIALS}, objects: [{},
               (name: "panel", type: "quad", material: "lum", params: (corner: (-0.5, 2, 1), edge0: (0, 0, -2), edge1: (1, 0, 0)))],
               lights: [],
               cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (2, 2)))],
               sensors: [{}])"#,
            quad(
                "floor",
                [-10.0, 0.0, 10.0],
                [20.0, 0.0, 0.0],
                [0.0, 0.0, -20.0]
            ),
            point_sensors(&pts)
        ));
        let corners = [
            DVec3::new(-0.5, 2.0, 1.0),
            DVec3::new(-0.5, 2.0, -1.0),
            DVec3::new(0.5, 2.0, -1.0),
            DVec3::new(0.5, 2.0, 1.0),
        ];
        let want: Vec<f64> = pts
            .iter()
            .map(|p| {
                let v: Vec<DVec3> = corners.iter().map(|c| *c - *p).collect();
                1000.0 * projected_solid_angle(&v, DVec3::Y)
            })
            .collect();
        measure_points(
            &s,
            "diffuse area source, E = L ∫cos θ dω",
            &want,
            4096,
            &mut rows,
        );
    }

    // Diffuse inter-reflections: integrating sphere (R = 1 m, ρ = 0.5), 100 W point source at
    // the centre: E = Φ / (4πR² (1 − ρ)) everywhere on the wall.
    {
        let s = scene(
            r#"(materials: [(name: "wall", type: "lambertian", params: (reflectance: 0.5))],
               objects: [(name: "sphere", type: "sphere", material: "wall", params: (radius: 1))],
               lights: [(name: "p", type: "point", params: (position: (0, 0, 0), power: 100, spd: "e"))],
               cameras: [(name: "c", type: "pinhole", params: (position: (0, 0, 0.5), look_at: (0, 0, -1), resolution: (2, 2)))],
               sensors: [(name: "p0", type: "illuminance_grid", params: (corner: (-0.001, -0.99999, 0.001),
                          edge0: (0.002, 0, 0), edge1: (0, 0, -0.002), resolution: (1, 1)))])"#,
        );
        let want = efficacy("e") * 100.0 / (4.0 * PI * 0.5);
        measure_points(
            &s,
            "inter-reflections, sphere ρ = 0.5",
            &[want],
            4096,
            &mut rows,
        );
    }

    print_and_check(&rows);
}

fn print_and_check(rows: &[Row]) {
    println!("| case | point | expected (lx) | measured (lx) | standard error (lx) | pass |");
    println!("|---|---|---|---|---|---|");
    for r in rows {
        println!(
            "| {} | {} | {:.2} | {:.2} | {:.2} | {} |",
            r.case,
            r.point,
            r.expected,
            r.measured,
            r.se,
            if r.pass() { "yes" } else { "NO" }
        );
    }
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| !r.pass())
        .map(|r| format!("{} point {}", r.case, r.point))
        .collect();
    assert!(failed.is_empty(), "failed: {failed:?}");
}

/// Daylight through an opening: a 4 m × 4 m × 3 m room, black inside, with a 2 m × 2 m opening
/// in the roof centre (`roof`) or a 2 m × 1.5 m window (sill 1 m) in the south wall, under
/// CIE sky type `ty` (sun 40° altitude, due south) of 10 000 lx horizontal illuminance, no sun:
/// the floor receives the sky component alone.
fn daylight_case(roof: bool, ty: usize) {
    // (name, corner, edge0, edge1) of the room's quads: the floor and three walls, then either
    // the south wall and the roof around its opening, or the roof and the south wall around
    // its window.
    type Quad = (&'static str, [f64; 3], [f64; 3], [f64; 3]);
    const WALLS: [Quad; 4] = [
        ("floor", [-2.0, 0.0, 2.0], [4.0, 0.0, 0.0], [0.0, 0.0, -4.0]),
        ("west", [-2.0, 0.0, 2.0], [0.0, 0.0, -4.0], [0.0, 3.0, 0.0]),
        ("east", [2.0, 0.0, 2.0], [0.0, 3.0, 0.0], [0.0, 0.0, -4.0]),
        ("north", [-2.0, 0.0, -2.0], [4.0, 0.0, 0.0], [0.0, 3.0, 0.0]),
    ];
    const ROOF_OPENING: [Quad; 5] = [
        ("south", [-2.0, 0.0, 2.0], [0.0, 3.0, 0.0], [4.0, 0.0, 0.0]),
        ("r1", [-2.0, 3.0, 2.0], [4.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ("r2", [-2.0, 3.0, -1.0], [4.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ("r3", [-2.0, 3.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -2.0]),
        ("r4", [1.0, 3.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -2.0]),
    ];
    // South wall (z = 2) with a 2 m × 1.5 m window, sill at 1 m.
    const WINDOW: [Quad; 5] = [
        ("roof", [-2.0, 3.0, 2.0], [4.0, 0.0, 0.0], [0.0, 0.0, -4.0]),
        ("s1", [-2.0, 0.0, 2.0], [0.0, 3.0, 0.0], [1.0, 0.0, 0.0]),
        ("s2", [1.0, 0.0, 2.0], [0.0, 3.0, 0.0], [1.0, 0.0, 0.0]),
        ("s3", [-1.0, 0.0, 2.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]),
        ("s4", [-1.0, 2.5, 2.0], [0.0, 0.5, 0.0], [2.0, 0.0, 0.0]),
    ];
    let rest = if roof { &ROOF_OPENING } else { &WINDOW };
    let room = WALLS
        .iter()
        .chain(rest)
        .map(|(name, c, e0, e1)| quad(name, *c, *e0, *e1))
        .collect::<Vec<_>>()
        .join(",");
    // The opening (corner, edge, edge) and the floor points measured.
    let (opening, pts) = if roof {
        (
            (
                DVec3::new(-1.0, 3.0, -1.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.0, 0.0, 2.0),
            ),
            [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.5, 0.0, 1.5),
            ],
        )
    } else {
        (
            (
                DVec3::new(-1.0, 1.0, 2.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.0, 1.5, 0.0),
            ),
            [
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, -1.0),
            ],
        )
    };
    let s = scene(&format!(
        r#"({ROOM_MATERIALS}, objects: [{room}],
           lights: [(name: "sky", type: "cie_sky", params: (sky_type: {ty}, sun_altitude: 40,
                     sun_azimuth: 180, horizontal_illuminance_lx: 10000))],
           cameras: [(name: "c", type: "pinhole", params: (position: (0, 1.5, 0), look_at: (0, 1.5, -1), resolution: (2, 2)))],
           sensors: [{}])"#,
        point_sensors(&pts)
    ));
    let want: Vec<f64> = pts
        .iter()
        .map(|p| {
            let (c, e0, e1) = opening;
            sky_component(*p, c, e0, e1, ty, (40.0, 180.0), 10_000.0)
        })
        .collect();
    let case = format!(
        "sky component, {} opening, CIE sky type {ty}",
        if roof { "roof" } else { "façade (south)" }
    );
    let mut rows = Vec::new();
    measure_points(&s, &case, &want, 262_144, &mut rows);
    print_and_check(&rows);
}

#[test]
fn cie171_roof_opening_overcast_sky() {
    daylight_case(true, 1);
}

#[test]
fn cie171_roof_opening_clear_sky() {
    daylight_case(true, 12);
}

#[test]
fn cie171_facade_opening_overcast_sky() {
    daylight_case(false, 1);
}

#[test]
fn cie171_facade_opening_clear_sky() {
    daylight_case(false, 12);
}
