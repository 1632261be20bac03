//! TM-25 ray files as lights, checked against the rays themselves: the shipped LightTools file
//! (`scenes/rays/`, 10 000 rays of about 1 lm) and ray files written by `rays export`.
//!
//! Independent references: the file's rays read here with a few lines of byte decoding (not the
//! crate's reader), binned by direction (far field) or intersected with the floor plane and
//! binned by position (irradiance); both compared with what the renderer derives from the
//! light: its beams, its near-field model's table, its sensor-grid lux.

use spectrace::light::measure::goniometer::{measure, GoniometerSettings};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::sensor::{measure as measure_grid, Estimator, MeasureSettings};
use std::path::{Path, PathBuf};

fn rays_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/rays")
}

/// The rays of a radiant- or luminous-flux-only file (7 floats a record, no spectral tables,
/// no additional columns), decoded straight from the bytes: (x, y, z mm, kx, ky, kz, flux).
fn raw_rays(path: &Path) -> (f32, Vec<[f32; 7]>) {
    let b = std::fs::read(path).unwrap();
    let f = |o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    let header_lm = f(12);
    let n = u64::from_le_bytes(b[20..28].try_into().unwrap()) as usize;
    assert_eq!(b.len(), 36288 + 28 * n, "layout assumed by this reference");
    let rays = (0..n)
        .map(|i| std::array::from_fn(|c| f(36288 + 28 * i + 4 * c)))
        .collect();
    (header_lm, rays)
}

fn scene(text: &str) -> Scene {
    let desc = parse_scene_str(text, Path::new("ray_case.ron")).unwrap();
    build_scene(
        &desc,
        &rays_dir(),
        Path::new("ray_case.ron"),
        &[&BuiltinFactory],
    )
    .unwrap()
}

/// The header's flux against the rays' sum, and the light's power: the LightTools file's
/// header says 1 lm while its rays sum to 10 000 lm (an inconsistency of the file, reported at
/// build); the light takes the rays' sum: power × K = 10 000 lm (f32 rays summed in f64: 1e-6).
#[test]
fn the_light_carries_the_rays_flux() {
    let (header_lm, rays) = raw_rays(&rays_dir().join("cylinder_10k_lighttools.TM25RAY"));
    let sum: f64 = rays.iter().map(|r| r[6] as f64).sum();
    println!("header {header_lm} lm, rays' sum {sum} lm");
    assert_eq!(header_lm, 1.0);
    let s = scene(
        r#"(materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
            objects: [(name: "floor", type: "quad", material: "black",
                       params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
            lights: [(name: "led", type: "ray_file", params: (file: "cylinder_10k_lighttools.TM25RAY",
             position: (0, 0.5, 0), spd: "e"))],
            cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))])"#,
    );
    let l = &s.lights.lights()[0];
    let k = spectrace::photometry::efficacy::luminous_efficacy_lm_per_w(l.spd().as_ref());
    let lm = l.power() * k;
    assert!((lm / sum - 1.0).abs() < 1e-6, "{lm} lm vs rays' {sum} lm");
}

/// γ (from the file's +z, which `aim` (0, −1, 0) points down) and C of a file direction, the
/// goniometer's type C angles in the world (C0 along +x = file x, C90 along −z = file −y).
fn angles(k: [f32; 3]) -> (f64, f64) {
    let (kx, ky, kz) = (k[0] as f64, k[1] as f64, k[2] as f64);
    let len = (kx * kx + ky * ky + kz * kz).sqrt();
    let gamma = (kz / len).clamp(-1.0, 1.0).acos().to_degrees();
    let c = (-ky).atan2(kx).to_degrees().rem_euclid(360.0);
    (gamma, c)
}

/// Far field: the light's beams measured by the goniometer (2 M draws binned into 15° cells
/// centred on the grid nodes) against the file's own rays binned into the same cells here.
/// Both are normalised to fractions of the flux per cell (the goniometer's table is rescaled to
/// its trapezoid flux, a global factor). Per cell the draws are multinomial: σ = √(p(1−p)/N);
/// every cell within 4.5σ + 1e-4 (probability of a false failure over ~300 cells < 0.1 %).
#[test]
fn far_field_equals_the_files_binned_far_field() {
    let (_, rays) = raw_rays(&rays_dir().join("cylinder_10k_lighttools.TM25RAY"));
    let s = scene(
        r#"(materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
            objects: [(name: "floor", type: "quad", material: "black",
                       params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
            lights: [(name: "led", type: "ray_file", params: (file: "cylinder_10k_lighttools.TM25RAY",
             position: (0, 0.5, 0)))],
            cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))])"#,
    );
    let step = 15.0;
    let n = 2_000_000u64;
    let m = measure(
        s.lights.lights()[0].as_ref(),
        &GoniometerSettings {
            step_deg: step,
            samples: n,
            seed: 3,
        },
    )
    .unwrap();
    let lum = &m.luminaire;
    let nv = lum.v_deg.len();
    let nh = lum.h_deg.len() - 1;
    // Reference: flux fraction per (C node, γ node) cell.
    let total: f64 = rays.iter().map(|r| r[6] as f64).sum();
    let mut want = vec![0.0f64; nh * nv];
    for r in &rays {
        let (g, c) = angles([r[3], r[4], r[5]]);
        let iv = ((g / step).round() as usize).min(nv - 1);
        let ih = ((c / step).round() as usize) % nh;
        want[ih * nv + iv] += r[6] as f64 / total;
    }
    // The table back to fractions: I × cell solid angle, normalised.
    let half = (step / 2.0).to_radians();
    let dh = step.to_radians();
    let mut got = vec![0.0f64; nh * nv];
    for ih in 0..nh {
        for iv in 0..nv {
            let v = lum.v_deg[iv].to_radians();
            let omega =
                dh * ((v - half).max(0.0).cos() - (v + half).min(std::f64::consts::PI).cos());
            got[ih * nv + iv] = lum.stored_cd(ih, iv) * omega;
        }
    }
    let gs: f64 = got.iter().sum();
    let mut worst: f64 = 0.0;
    for i in 0..got.len() {
        let g = got[i] / gs;
        let p = want[i];
        let sigma = (p * (1.0 - p) / n as f64).sqrt();
        let z = (g - p).abs() / (sigma + 1e-12);
        worst = worst.max(if p > 0.0 { z } else { 0.0 });
        assert!(
            (g - p).abs() <= 4.5 * sigma + 1e-4,
            "cell {i}: {g} vs {p} (σ {sigma})"
        );
    }
    println!("{} cells, worst |z| {worst:.2}", got.len());
}

/// Lux under the real file: its near-field model (a 10° table binned from the rays, emitted
/// from the box of their start points) 0.2 m above a black floor, a sensor grid of 20 × 20
/// points over 0.4 m × 0.4 m, against the irradiance of the rays themselves: each ray (in the
/// world: file z down) intersected with the floor and binned into 2 × 2 cells of 0.2 m, lux =
/// Σ lm / area. The grid's points in each cell are averaged (the cell mean, not its centre).
/// Tolerance per cell 3.5 × the rays' Poisson σ (√Σφ² / area, the reference's noise, ~4 %) +
/// 3.5 × the grid's σ + 2 % for the model (the table's 10° cells against the rays' directions,
/// and the box against the cylinder: second order in size / distance = 0.1).
#[test]
fn lux_under_the_file_equals_the_rays_binned_on_the_floor() {
    let (_, rays) = raw_rays(&rays_dir().join("cylinder_10k_lighttools.TM25RAY"));
    let h = 0.2f64;
    let s = scene(&format!(
        r#"(materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
            objects: [(name: "floor", type: "quad", material: "black",
                       params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
            lights: [(name: "led", type: "ray_file", params: (file: "cylinder_10k_lighttools.TM25RAY",
                      position: (0, {h}, 0), spd: "e", model: "near_field", table_step_deg: 10))],
            cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
            sensors: [(name: "floor", type: "illuminance_grid",
                       params: (corner: (-0.2, 0, 0.2), edge0: (0.4, 0, 0), edge1: (0, 0, -0.4), resolution: (20, 20)))])"#
    ));
    let grid = s.sensors.iter().find(|g| g.name == "floor").unwrap();
    let reading = measure_grid(
        &s,
        grid,
        &MeasureSettings {
            estimator: Estimator::SensorPathTracing,
            samples: 256,
            seed: 5,
            threads: None,
            tracer: spectrace::integrator::PathTracer::default(),
        },
    )
    .unwrap();
    // Reference: rays in the world (origin (0, h, 0) + file point in mm; file z → world −y,
    // file x → world x, file y → world z).
    let (mut sum, mut sum2) = ([0.0f64; 4], [0.0f64; 4]);
    for r in &rays {
        let p = [
            r[0] as f64 * 1e-3,
            h - r[2] as f64 * 1e-3,
            r[1] as f64 * 1e-3,
        ];
        let d = [r[3] as f64, -(r[5] as f64), r[4] as f64];
        if !(d[1] < 0.0) {
            continue;
        }
        let t = -p[1] / d[1];
        let (x, z) = (p[0] + t * d[0], p[2] + t * d[2]);
        if x.abs() >= 0.2 || z.abs() >= 0.2 {
            continue;
        }
        let cell = (x > 0.0) as usize + 2 * (z < 0.0) as usize;
        sum[cell] += r[6] as f64;
        sum2[cell] += (r[6] as f64).powi(2);
    }
    let area = 0.2 * 0.2;
    for cell in 0..4 {
        let (mut g, mut g2, mut k) = (0.0, 0.0, 0.0);
        for (i, p) in reading.points.iter().enumerate() {
            let c = (p.x > 0.0) as usize + 2 * (p.z < 0.0) as usize;
            if c == cell {
                g += reading.lux[i];
                g2 += reading.stderr[i].powi(2);
                k += 1.0;
            }
        }
        let (lux, lux_se) = (g / k, g2.sqrt() / k);
        let want = sum[cell] / area;
        let want_se = sum2[cell].sqrt() / area;
        let tol = 3.5 * (want_se + lux_se) + 0.02 * want;
        println!(
            "cell {cell}: grid {lux:.1} ± {lux_se:.1} lx, rays {want:.1} ± {want_se:.1} lx, off {:+.2} %",
            (lux / want - 1.0) * 100.0
        );
        assert!(
            (lux - want).abs() <= tol,
            "cell {cell}: {lux} vs {want} lx (tolerance {tol})"
        );
    }
}

use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};

fn floor_scene(light: &str) -> Scene {
    scene(&format!(
        r#"(observer: "cie1931-2",
            materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
            objects: [(name: "floor", type: "quad", material: "grey",
                       params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4)))],
            lights: [{light}],
            cameras: [(name: "c", type: "perspective",
                       params: (position: (0, 2.5, 2.5), look_at: (0, 0, 0), fov: 50, resolution: (16, 16)))])"#
    ))
}

/// Per-pixel Y of `runs` LT renders with different seeds: (mean, standard error of the mean).
fn lt_images(s: &Scene, runs: u64, spp: u32) -> (Vec<f64>, Vec<f64>) {
    let mut sum = vec![0.0; 256];
    let mut sum2 = vec![0.0; 256];
    for seed in 0..runs {
        let settings = RenderSettings {
            sampler: Default::default(),
            budget: SampleBudget::Spp(spp),
            seed: 100 + seed,
            threads: None,
            camera: None,
            tile_size: 16,
            tracer: PathTracer {
                max_depth: 1,
                ..PathTracer::default()
            },
        };
        let out = render_with(s, &settings, IntegratorKind::Lt, false, &|_, _| {}, None).unwrap();
        for (i, p) in out.result.image.xyz.iter().enumerate() {
            sum[i] += p[1];
            sum2[i] += p[1] * p[1];
        }
    }
    let n = runs as f64;
    let mean: Vec<f64> = sum.iter().map(|s| s / n).collect();
    let se = sum2
        .iter()
        .zip(&mean)
        .map(|(s2, m)| ((s2 / n - m * m).max(0.0) / (n - 1.0)).sqrt())
        .collect();
    (mean, se)
}

/// Round trip light → TM-25 → light: a spot light (D65, 30° cone) 1 m above a grey floor,
/// exported as 1 M rays (`rays export`'s function: a spectral table, identifier 3), read back
/// as a `ray_file` light in the world frame; both rendered with light tracing (direct light,
/// 16 × 16 pixels, 6 seeds each). The exported header's flux equals the rays' sum (f32 sum:
/// 1e-5) and the spot's power within 0.5 % (1 M-sample estimate with σ ≈ 0.1 %). Images,
/// compared in 4 × 4-pixel blocks (the file itself is one sample of the light: ~1e5 rays per
/// lit block, < 0.5 % noise): every lit block within 4σ (both renders' standard errors from
/// the seed repeats) + 1.5 % (the file's own sampling noise, 3 × its ~0.5 %).
#[test]
fn round_trip_light_to_rays_to_light_renders_the_same() {
    let spot = floor_scene(
        r#"(name: "spot", type: "spot", params: (position: (0, 1, 0), target: (0, 0, 0),
             power: 10, inner_angle: 25, outer_angle: 30, spd: "d65"))"#,
    );
    let out = std::env::temp_dir().join(format!(
        "spectrace_round_trip_{}.TM25RAY",
        std::process::id()
    ));
    let mut bytes = Vec::new();
    let summary = spectrace::light::measure::tm25_export::export_light(
        spot.lights.lights()[0].as_ref(),
        1_000_000,
        1,
        Default::default(),
        &mut bytes,
    )
    .unwrap();
    std::fs::write(&out, &bytes).unwrap();
    let file = spectrace::photometry::tm25::RayFile::open(&out).unwrap();
    let sum: f64 = (0..file.n_rays())
        .map(|i| file.ray(i).radiant_w.unwrap() as f64)
        .sum();
    println!(
        "exported {} W (header {} W), spot {} W",
        summary.flux_w, file.header.radiant_flux_w, summary.stated_w
    );
    assert_eq!(file.header.spectral_id.code(), 3);
    assert!((file.header.radiant_flux_w as f64 / sum - 1.0).abs() < 1e-5);
    assert!(
        (sum / summary.stated_w - 1.0).abs() < 5e-3,
        "{sum} vs {}",
        summary.stated_w
    );
    let rays = floor_scene(&format!(
        r#"(name: "rays", type: "ray_file", params: (file: "{}", position: (0, 0, 0),
             aim: (0, 0, 1), x_axis: (1, 0, 0)))"#,
        out.display()
    ));
    let (a, sa) = lt_images(&spot, 6, 16);
    let (b, sb) = lt_images(&rays, 6, 16);
    let _ = std::fs::remove_file(&out);
    let max = a.iter().copied().fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for by in 0..4 {
        for bx in 0..4 {
            let (mut ya, mut yb, mut va, mut vb) = (0.0, 0.0, 0.0, 0.0);
            for y in 0..4 {
                for x in 0..4 {
                    let i = (by * 4 + y) * 16 + bx * 4 + x;
                    ya += a[i];
                    yb += b[i];
                    va += sa[i] * sa[i];
                    vb += sb[i] * sb[i];
                }
            }
            if ya < 0.05 * max * 16.0 {
                continue;
            }
            let sigma = (va + vb).sqrt();
            let tol = 4.0 * sigma + 0.015 * ya;
            worst = worst.max((ya - yb).abs() / ya);
            println!(
                "block ({bx}, {by}): {ya:.5} vs {yb:.5} (σ {sigma:.5}), off {:+.2} %",
                (yb / ya - 1.0) * 100.0
            );
            assert!((ya - yb).abs() <= tol, "block ({bx}, {by}): {ya} vs {yb}");
        }
    }
    println!("worst block difference {:.2} %", worst * 100.0);
}

/// Bounded randomised inputs (the quick companion of the `tm25` fuzz target): 20 000 damaged
/// copies of the two fuzz seeds (a cut LightTools file; a table-indexed file), each with one to
/// four edits aimed where the layout lives (a 4-byte field of the 288-byte header or of the
/// spectral tables set to an extreme value, a flipped byte, a cut): the reader answers every
/// one with a file or an error, never a panic, and an accepted file has every ray readable.
#[test]
fn the_reader_survives_damaged_files() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds/tm25");
    let seeds: Vec<Vec<u8>> = ["lighttools_8rays.TM25RAY", "indexed_tables.TM25RAY"]
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect();
    let mut rng = 0x853C49E6748FEA9Bu64;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let extremes: [u32; 10] = [
        0,
        1,
        2,
        4,
        5,
        2013,
        u32::MAX,
        i32::MAX as u32,
        0x7FC0_0000,
        0xFF80_0000,
    ];
    let (mut accepted, mut refused) = (0, 0);
    for case in 0..20_000 {
        let mut b = seeds[case % 2].clone();
        for _ in 0..1 + next() % 4 {
            match next() % 4 {
                0 => {
                    let at = 4 * (next() as usize % 72);
                    if at + 4 <= b.len() {
                        b[at..at + 4]
                            .copy_from_slice(&extremes[next() as usize % 10].to_le_bytes());
                    }
                }
                1 => {
                    let at = 36288 + 4 * (next() as usize % 40);
                    if at + 4 <= b.len() {
                        b[at..at + 4]
                            .copy_from_slice(&extremes[next() as usize % 10].to_le_bytes());
                    }
                }
                2 => {
                    let at = next() as usize % b.len();
                    b[at] ^= 1 << (next() % 8);
                }
                _ => {
                    let at = next() as usize % (b.len() + 1);
                    b.truncate(at);
                }
            }
        }
        match spectrace::photometry::tm25::RayFile::from_bytes(b, Path::new("damaged.TM25RAY")) {
            Ok(f) => {
                accepted += 1;
                let _ = f.check_rays();
                for i in 0..f.n_rays() {
                    let _ = f.ray(i);
                }
            }
            Err(e) => {
                refused += 1;
                assert!(e.to_string().contains("damaged.TM25RAY"));
            }
        }
    }
    println!("{accepted} accepted, {refused} refused");
    assert!(accepted > 0 && refused > 0);
}

/// `max_rays` below the file's count: 500 rays chosen by systematic resampling in proportion to
/// flux stand for the 10 000. The light's flux is unchanged (the sum is taken over every ray;
/// 1e-9), and the share of the beams' flux in each 30° ring of γ matches the file's within 4σ
/// of a 500-ray multinomial sample (systematic resampling varies less, so this is loose on it)
/// + 400 000 draws' own noise.
#[test]
fn max_rays_keeps_the_flux_and_the_distribution() {
    let (_, rays) = raw_rays(&rays_dir().join("cylinder_10k_lighttools.TM25RAY"));
    let text = |m: u64| {
        format!(
            r#"(materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
            objects: [(name: "floor", type: "quad", material: "black",
                       params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
            lights: [(name: "led", type: "ray_file", params: (file: "cylinder_10k_lighttools.TM25RAY",
             position: (0, 0.5, 0), aim: (0, 0, 1), x_axis: (1, 0, 0), max_rays: {m}))],
            cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))])"#
        )
    };
    let full = scene(&text(4_000_000));
    let sub = scene(&text(500));
    let (lf, ls) = (&full.lights.lights()[0], &sub.lights.lights()[0]);
    assert!((lf.power() / ls.power() - 1.0).abs() < 1e-9);
    let total: f64 = rays.iter().map(|r| r[6] as f64).sum();
    let mut want = [0.0f64; 6];
    for r in &rays {
        let (g, _) = angles([r[3], r[4], r[5]]);
        want[((g / 30.0) as usize).min(5)] += r[6] as f64 / total;
    }
    let n = 400_000;
    let mut got = [0.0f64; 6];
    for i in 0..n {
        let u = spectrace_plugin_api::RandomSample {
            u: std::array::from_fn(|k| ((i as f64 + 0.5) / n as f64 + 0.37 * k as f64).fract()),
        };
        let b = ls.next_beam(&u).unwrap();
        // File frame = world frame here: γ from +z.
        let (g, _) = angles([
            b.direction.x as f32,
            b.direction.y as f32,
            b.direction.z as f32,
        ]);
        got[((g / 30.0) as usize).min(5)] += 1.0 / n as f64;
    }
    for k in 0..6 {
        let p = want[k];
        let sigma = (p * (1.0 - p) / 500.0).sqrt() + (p * (1.0 - p) / n as f64).sqrt();
        println!(
            "ring {k}: {:.4} of the flux from 500 rays, {p:.4} in the file (σ {sigma:.4})",
            got[k]
        );
        assert!((got[k] - p).abs() <= 4.0 * sigma, "ring {k}");
    }
}
