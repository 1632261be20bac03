//! The glare measurement: the fisheye luminance image of a [`GlareObserver`] rendered with the
//! path tracer, UGR from it, and the EXR / Radiance HDR / JSON outputs. The observer, its
//! parameters and the method are documented in [`crate::builtin::sensor::glare_observer`].

use super::estimate::{draw_wavelengths, point_sampler, Photometric};
use crate::builtin::sensor::glare_observer::GlareObserver;
use crate::geometry::Ray;
use crate::integrator::{PathStats, PathTracer};
use crate::scene::Scene;
use glam::Vec3A;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// The rendered fisheye and the glare figures.
#[derive(Clone, Debug, PartialEq)]
pub struct GlareReading {
    /// Observer name.
    pub name: String,
    /// Image side.
    pub resolution: u32,
    /// Luminance per pixel, cd/m², row-major from the top; 0 outside the circle.
    pub luminance: Vec<f64>,
    /// Standard error per pixel, cd/m².
    pub stderr: Vec<f64>,
    /// Samples per pixel.
    pub samples: u32,
    /// The threshold used, cd/m².
    pub threshold: f64,
    /// Vertical illuminance at the eye, lx.
    pub e_vertical: f64,
    /// Background luminance L_b = E_ind/π, cd/m².
    pub background: f64,
    /// Σ L² ω / p² over the sources.
    pub source_sum: f64,
    /// Solid angle of the sources, sr.
    pub source_solid_angle: f64,
    /// Number of source pixels.
    pub source_pixels: usize,
    /// UGR (−∞ when there is no source; +∞ when the background is black).
    pub ugr: f64,
    /// Its standard error (first-order, from the pixels' errors).
    pub ugr_stderr: f64,
}

/// Render `obs` in `scene` with `samples` per pixel and compute the UGR.
pub fn measure_glare(
    scene: &Scene,
    obs: &GlareObserver,
    samples: u32,
    seed: u64,
    threads: Option<usize>,
    tracer: &PathTracer,
) -> Result<GlareReading, String> {
    let pool = crate::integrator::tiled::thread_pool(threads).map_err(|e| e.to_string())?;
    let n = obs.resolution as usize;
    let samples = samples.max(1);
    let photo = Photometric::new();
    let dx = 2.0 / n as f64;
    let seed = seed ^ crate::film::state_file::fnv1a64(&[obs.name.as_bytes()]);
    let o = Vec3A::new(
        obs.position.x as f32,
        obs.position.y as f32,
        obs.position.z as f32,
    );
    let px: Vec<(f64, f64)> = pool.install(|| {
        (0..n * n)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % n, k / n);
                let (cx, cy) = (-1.0 + (i as f64 + 0.5) * dx, 1.0 - (j as f64 + 0.5) * dx);
                if (cx * cx + cy * cy).sqrt() > 1.0 {
                    return (0.0, 0.0);
                }
                let (mut s, mut s2) = (0.0, 0.0);
                let mut stats = PathStats::default();
                for sidx in 0..samples {
                    let mut rng = point_sampler(seed, k, sidx);
                    let lambda = draw_wavelengths(rng.next_1d());
                    let u = rng.next_2d();
                    let x = cx + (u.x as f64 - 0.5) * dx;
                    let y = cy + (u.y as f64 - 0.5) * dx;
                    let Some((d, _)) = obs.direction(x, y) else {
                        continue;
                    };
                    let ray = Ray::new(o, Vec3A::new(d.x as f32, d.y as f32, d.z as f32));
                    let mut lam = lambda;
                    let l = tracer.li(scene, ray, &mut lam, &mut rng, &mut stats);
                    let v = photo.of(&l, &lam);
                    if v.is_finite() {
                        s += v;
                        s2 += v * v;
                    }
                }
                let m = s / samples as f64;
                let var = if samples > 1 {
                    ((s2 - samples as f64 * m * m) / (samples as f64 - 1.0)).max(0.0)
                } else {
                    0.0
                };
                (m, (var / samples as f64).sqrt())
            })
            .collect()
    });
    let luminance: Vec<f64> = px.iter().map(|p| p.0).collect();
    let stderr: Vec<f64> = px.iter().map(|p| p.1).collect();
    Ok(ugr_of_image(obs, luminance, stderr, samples))
}

/// The UGR of a fisheye luminance image of `obs` (row-major, top first; see the module docs).
pub fn ugr_of_image(
    obs: &GlareObserver,
    mut luminance: Vec<f64>,
    mut stderr: Vec<f64>,
    samples: u32,
) -> GlareReading {
    let n = obs.resolution as usize;
    // An image of another size is cut or padded with black to the observer's.
    luminance.resize(n * n, 0.0);
    stderr.resize(n * n, 0.0);
    let dx = 2.0 / n as f64;
    // Per pixel: solid angle, cos θ, direction.
    let mut geo = Vec::with_capacity(n * n);
    let (mut lsum, mut wsum) = (0.0, 0.0);
    for (k, l) in luminance.iter().enumerate().take(n * n) {
        let (i, j) = (k % n, k / n);
        let (cx, cy) = (-1.0 + (i as f64 + 0.5) * dx, 1.0 - (j as f64 + 0.5) * dx);
        match obs.direction(cx, cy) {
            Some((d, theta)) => {
                let w = GlareObserver::pixel_solid_angle(theta, dx);
                geo.push(Some((d, theta, w)));
                lsum += l * w;
                wsum += w;
            }
            None => geo.push(None),
        }
    }
    let mean = if wsum > 0.0 { lsum / wsum } else { 0.0 };
    let threshold = obs.source_threshold.unwrap_or(5.0 * mean);
    let (mut e_v, mut e_src, mut sum, mut omega, mut count) = (0.0, 0.0, 0.0, 0.0, 0usize);
    // Variances of the sum and the background illuminance (pixels independent).
    let (mut var_sum, mut var_bg) = (0.0, 0.0);
    for k in 0..n * n {
        let Some((d, theta, w)) = geo[k] else {
            continue;
        };
        let (l, se) = (luminance[k], stderr[k]);
        let c = theta.cos().max(0.0);
        e_v += l * c * w;
        if l > threshold && threshold > 0.0 {
            let p = obs.position_index(d);
            sum += l * l * w / (p * p);
            var_sum += (2.0 * l * w / (p * p) * se).powi(2);
            e_src += l * c * w;
            omega += w;
            count += 1;
        } else {
            var_bg += (c * w * se).powi(2);
        }
    }
    let background = (e_v - e_src) / std::f64::consts::PI;
    let var_lb = var_bg / (std::f64::consts::PI * std::f64::consts::PI);
    let (ugr, ugr_se) = if count == 0 {
        (f64::NEG_INFINITY, 0.0)
    } else if !(background > 0.0) {
        (f64::INFINITY, 0.0)
    } else {
        let u = 8.0 * (0.25 / background * sum).log10();
        // d UGR = 8/ln10 · (dS/S − dLb/Lb).
        let rel = (var_sum / (sum * sum) + var_lb / (background * background)).sqrt();
        (u, 8.0 / std::f64::consts::LN_10 * rel)
    };
    GlareReading {
        name: obs.name.clone(),
        resolution: obs.resolution,
        luminance,
        stderr,
        samples,
        threshold,
        e_vertical: e_v,
        background,
        source_sum: sum,
        source_solid_angle: omega,
        source_pixels: count,
        ugr,
        ugr_stderr: ugr_se,
    }
}

/// Write `DIR/NAME.exr` (channel `Y`: luminance in cd/m², and `Y_stderr`), `DIR/NAME.hdr` (a
/// Radiance picture with `VIEW= -vta -vv 180 -vh 180`, pixel values L/179 so Radiance tools such
/// as evalglare read cd/m²) and `DIR/NAME.json` (the figures). Returns the paths.
pub fn write_outputs(
    r: &GlareReading,
    obs: &GlareObserver,
    dir: &Path,
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let n = r.resolution as usize;
    let exr_path = dir.join(format!("{}.exr", r.name));
    {
        use exr::prelude::*;
        let f = |v: &[f64]| v.iter().map(|x| *x as f32).collect::<Vec<f32>>();
        let channels = SmallVec::from_vec(vec![
            AnyChannel::new("Y", FlatSamples::F32(f(&r.luminance))),
            AnyChannel::new("Y_stderr", FlatSamples::F32(f(&r.stderr))),
        ]);
        let layer = Layer::new(
            (n, n),
            LayerAttributes::named(""),
            Encoding {
                line_order: LineOrder::Increasing,
                ..Encoding::FAST_LOSSLESS
            },
            AnyChannels::sort(channels),
        );
        Image::from_layer(layer)
            .write()
            .to_file(&exr_path)
            .map_err(|e| format!("cannot write {}: {e}", exr_path.display()))?;
    }
    let hdr_path = dir.join(format!("{}.hdr", r.name));
    write_radiance_hdr(&hdr_path, n, &r.luminance, obs)?;
    let json_path = dir.join(format!("{}.json", r.name));
    let fin = |x: f64| {
        if x.is_finite() {
            serde_json::json!(x)
        } else {
            serde_json::json!(format!("{x}"))
        }
    };
    let j = serde_json::json!({
        "name": r.name,
        "quantity": "UGR (CIE 117-1995) from a 180° equidistant fisheye luminance image",
        "position_m": obs.position.to_array(),
        "direction": obs.view.to_array(),
        "up": obs.up.to_array(),
        "resolution": r.resolution,
        "samples_per_pixel": r.samples,
        "ugr": fin(r.ugr),
        "ugr_stderr": r.ugr_stderr,
        "source_threshold_cd_m2": r.threshold,
        "source_pixels": r.source_pixels,
        "source_solid_angle_sr": r.source_solid_angle,
        "background_luminance_cd_m2": r.background,
        "vertical_illuminance_lx": r.e_vertical,
        "sum_L2_omega_over_p2": r.source_sum,
    });
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&j).unwrap_or_default() + "\n",
    )
    .map_err(|e| format!("cannot write {}: {e}", json_path.display()))?;
    Ok(vec![exr_path, hdr_path, json_path])
}

/// A Radiance RGBE picture (flat, uncompressed scanlines) of grey pixels L/179 (Radiance's
/// luminous efficacy of its white, 179 lm/W), with the angular-fisheye view in the header.
fn write_radiance_hdr(
    path: &Path,
    n: usize,
    lum: &[f64],
    obs: &GlareObserver,
) -> Result<(), String> {
    let mut out = Vec::with_capacity(n * n * 4 + 256);
    let (p, v, u) = (obs.position, obs.view, obs.up);
    let header = format!(
        "#?RADIANCE\nSOFTWARE=spectrace\nVIEW= -vta -vp {} {} {} -vd {} {} {} -vu {} {} {} -vh 180 -vv 180\nFORMAT=32-bit_rle_rgbe\n\n-Y {n} +X {n}\n",
        p.x, p.y, p.z, v.x, v.y, v.z, u.x, u.y, u.z
    );
    out.extend_from_slice(header.as_bytes());
    for &l in lum {
        let x = (l / 179.0).max(0.0);
        if !(x > 1e-32) || !x.is_finite() {
            out.extend_from_slice(&[0, 0, 0, 0]);
            continue;
        }
        let e = x.log2().floor() as i32 + 1;
        let m = (x / 2f64.powi(e) * 256.0).min(255.0) as u8;
        let ex = (e + 128).clamp(0, 255) as u8;
        out.extend_from_slice(&[m, m, m, ex]);
    }
    std::fs::write(path, out).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::sensor::glare_observer::guth_position_index;
    use glam::DVec3;
    use std::f64::consts::FRAC_PI_2;

    fn obs() -> GlareObserver {
        GlareObserver::from_params(
            "g",
            &ron::from_str("(position: (0, 1.2, 0), direction: (0, 0, -1), resolution: 64)")
                .unwrap(),
        )
        .unwrap()
    }

    /// The pixels' solid angles add up to the hemisphere, 2π (midpoint rule on 512² pixels:
    /// the rim pixels cut by the circle are counted whole or not, 2e-3 relative), and the
    /// position index is 1 on the line of sight and grows away from it (Luckiesh–Guth table:
    /// p ≈ 1.5–1.6 at τ = 0°, σ = 15°... the closed form gives 1.76 at σ = 15°, τ = 0).
    #[test]
    fn geometry() {
        let n = 512;
        let dx = 2.0 / n as f64;
        let mut sum = 0.0;
        for k in 0..n * n {
            let (i, j) = (k % n, k / n);
            let (x, y) = (-1.0 + (i as f64 + 0.5) * dx, -1.0 + (j as f64 + 0.5) * dx);
            if (x * x + y * y).sqrt() <= 1.0 {
                sum += GlareObserver::pixel_solid_angle((x * x + y * y).sqrt() * FRAC_PI_2, dx);
            }
        }
        assert!(
            (sum / (2.0 * std::f64::consts::PI) - 1.0).abs() < 2e-3,
            "{sum}"
        );
        assert_eq!(guth_position_index(0.0, 0.0), 1.0);
        let o = obs();
        assert!((o.position_index(o.view) - 1.0).abs() < 1e-12);
        assert!(guth_position_index(0.0, 30.0) > guth_position_index(0.0, 15.0));
        let (d, t) = o.direction(0.0, 1.0).unwrap();
        assert!((t - FRAC_PI_2).abs() < 1e-12 && (d - DVec3::Y).length() < 1e-12);
    }

    /// Bad parameters name the parameter.
    #[test]
    fn bad_parameters() {
        let e = |s: &str| GlareObserver::from_params("g", &ron::from_str(s).unwrap()).unwrap_err();
        assert!(e("(position: (0, 1, 0), direction: (0, 0, 0))").contains("direction"));
        assert!(e("(position: (0, 1, 0), direction: (0, 1, 0))").contains("up"));
        assert!(
            e("(position: (0, 1, 0), direction: (0, 0, 1), resolution: 4)").contains("resolution")
        );
        assert!(
            e("(position: (0, 1, 0), direction: (0, 0, 1), source_threshold: -1)")
                .contains("source_threshold")
        );
    }
}
