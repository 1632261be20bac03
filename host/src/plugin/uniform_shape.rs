//! Checking a plugin light's claim to emit one spectral shape everywhere (the
//! `UNIFORM_SPECTRAL_SHAPE` bit), once, when it is built. The host then gives a path
//! from the light through spectrally flat surfaces the exact colour of the light's spectrum
//! (`integrator::flat_colour`); a light whose emission changes colour from place to place or
//! direction to direction would get the wrong colour with no noise to show it. So the probe asks
//! the light for its emission where the renderer does, at two sets of four wavelengths, and
//! divides by the spectrum the host integrates over: the quotient must be one number per sample.
//!
//! | probe | values |
//! |---|---|
//! | wavelengths, nm | [`SET_A_NM`] and [`SET_B_NM`] |
//! | spectrum | the light's `spd()` (its own emission SPD, or its wavelength distribution) |
//! | emission (`sample_emission`) | [`SAMPLES`] uniforms; origin, direction and value per lane |
//! | arrival (`sample_toward`) | from one unit along each sampled beam, the same uniforms |
//! | environment (`radiance`) | the 6 axis directions and 8 diagonals |
//! | agreement | `value(λ) / spd(λ)` within [`REL_TOLERANCE`] of that at the probe's reference lane (the one where `spd` is largest), over both sets when both sampled the same point; `value` 0 where `spd` is 0 |
//!
//! 16 emission samples and 16 arrivals (8 uniforms at each set), or 28 radiance calls: nothing
//! next to building a scene.
//! A light whose spectrum has lines gets no exact colour (the renderer skips it), so it is not
//! probed. What the probe cannot see stays the plugin's responsibility, as the API's
//! documentation says.

use super::flatness::{SET_A_NM, SET_B_NM};
use crate::light::{EnvironmentRadiance, Light, LightSampleContext};
use crate::spectrum::{LaneMask, SampledWavelengths, Spd, LANES};
use glam::{Vec2, Vec3A};

/// Relative difference allowed between lanes' quotients: the plugin may compute in `f64` and
/// hand over values rounded to `f32` (1e-7 relative) and its spectrum through another path; a
/// shape that changes colour differs by far more.
pub const REL_TOLERANCE: f64 = 1e-4;

/// Uniforms tried per wavelength set.
pub const SAMPLES: usize = 8;

/// The `k`-th probe's uniforms: a fixed, well spread point set (Weyl sequences).
fn uniforms(k: usize) -> [f32; 4] {
    const ALPHA: [f64; 4] = [0.618_034, 0.414_214, 0.732_051, 0.236_068];
    ALPHA.map(|a| (0.5 + (k as f64 + 1.0) * a).fract() as f32)
}

fn lanes(nm: [f32; LANES]) -> SampledWavelengths {
    SampledWavelengths {
        lambda: nm,
        pdf: [1.0; LANES],
        lanes: LaneMask::ALL,
    }
}

/// A point or direction for a message, scene units.
fn show(v: Vec3A) -> String {
    format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z)
}

/// One probe's values at both sets (when both sets sampled the same point and direction, they
/// are compared together, else each on its own).
struct Probe {
    what: String,
    values: [[f32; LANES]; 2],
    same_point: bool,
}

/// `Ok` when the probes find the emission of `light` (or of `environment`, for an environment
/// light) one shape `spd` everywhere; else what they found, as the end of a sentence (naming the
/// wavelength where the claim fails).
pub fn check(
    light: &dyn Light,
    environment: Option<&dyn EnvironmentRadiance>,
    spd: &dyn Spd,
) -> Result<(), String> {
    if !spd.delta_lines().is_empty() {
        return Ok(());
    }
    let sets = [lanes(SET_A_NM), lanes(SET_B_NM)];
    let mut probes = Vec::new();
    if let Some(env) = environment {
        let mut dirs = vec![
            Vec3A::X,
            Vec3A::NEG_X,
            Vec3A::Y,
            Vec3A::NEG_Y,
            Vec3A::Z,
            Vec3A::NEG_Z,
        ];
        let c = 1.0 / 3f32.sqrt();
        for k in 0..8 {
            let s = |b: usize| if k >> b & 1 == 1 { -c } else { c };
            dirs.push(Vec3A::new(s(0), s(1), s(2)));
        }
        for d in dirs {
            let at = |w: &SampledWavelengths| env.radiance(d, w).0;
            probes.push(Probe {
                what: format!("its radiance from direction {}", show(d)),
                values: [at(&sets[0]), at(&sets[1])],
                same_point: true,
            });
        }
    } else {
        for k in 0..SAMPLES {
            let u = uniforms(k);
            let em = |w: &SampledWavelengths| {
                light.sample_le(Vec2::new(u[0], u[1]), Vec2::new(u[2], u[3]), w)
            };
            let (Some(a), Some(b)) = (em(&sets[0]), em(&sets[1])) else {
                continue;
            };
            probes.push(Probe {
                what: format!(
                    "its emission from {} toward {} (sample_emission)",
                    show(a.ray.origin),
                    show(a.ray.dir)
                ),
                values: [a.radiance.0, b.radiance.0],
                same_point: a.ray.origin == b.ray.origin && a.ray.dir == b.ray.dir,
            });
            let ctx = LightSampleContext {
                p: a.ray.origin + a.ray.dir,
                p_error: Vec3A::ZERO,
                n: Vec3A::ZERO,
            };
            let to = |w: &SampledWavelengths| light.sample_li(&ctx, Vec2::new(u[0], u[1]), w);
            if let (Some(a), Some(b)) = (to(&sets[0]), to(&sets[1])) {
                probes.push(Probe {
                    what: format!(
                        "the radiance arriving at {} from {} (sample_toward)",
                        show(ctx.p),
                        show(a.p_light)
                    ),
                    values: [a.radiance.0, b.radiance.0],
                    same_point: a.p_light == b.p_light,
                });
            }
        }
    }
    let shape: [Vec<f64>; 2] = [0, 1].map(|i| {
        sets[i]
            .lambda
            .iter()
            .map(|&l| spd.value(l as f64))
            .collect()
    });
    let lane = |p: &Probe, i: usize| -> Vec<(f64, f64, f64)> {
        (0..LANES)
            .map(|j| (sets[i].lambda[j] as f64, p.values[i][j] as f64, shape[i][j]))
            .collect()
    };
    for p in &probes {
        if p.same_point {
            let mut both = lane(p, 0);
            both.extend(lane(p, 1));
            compare(&both, &p.what)?;
        } else {
            compare(&lane(p, 0), &p.what)?;
            compare(&lane(p, 1), &p.what)?;
        }
    }
    Ok(())
}

/// `lanes` are (nm, value, spd value): every quotient the same, 0 where the shape is 0.
fn compare(lanes: &[(f64, f64, f64)], what: &str) -> Result<(), String> {
    let Some(&(ref_nm, ref_v, ref_s)) = lanes
        .iter()
        .filter(|l| l.2 > 0.0)
        .max_by(|a, b| a.2.total_cmp(&b.2))
    else {
        return Ok(());
    };
    let k = ref_v / ref_s;
    for &(nm, v, s) in lanes {
        let fits = if s > 0.0 {
            let q = v / s;
            q == k || (q - k).abs() <= REL_TOLERANCE * q.abs().max(k.abs())
        } else {
            v == 0.0
        };
        if !fits {
            let expected = k * s;
            return Err(format!(
                "at {nm} nm {what} is {v:.6e}, where its spectrum's shape scaled to {ref_v:.6e} \
                 at {ref_nm} nm gives {expected:.6e} ({:+.2}%)",
                if expected != 0.0 {
                    100.0 * (v - expected) / expected
                } else {
                    f64::INFINITY
                }
            ));
        }
    }
    Ok(())
}
