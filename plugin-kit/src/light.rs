//! The checks of a light source ([`LightObject`]). The light is first told the scene bounds of
//! [`BOUNDS`] (a 2 m cube around the origin), as the host does before rendering.
//!
//! | check | statistic | threshold | why |
//! |---|---|---|---|
//! | `power` | ∣Φ̂ − P∣ / (5σ + 10⁻³P): Φ̂ the flux integrated from `sample_emission` (10⁵ rays × 4 wavelengths drawn from the emission spectrum, value·∣cos∣ / (pdf_pos·pdf_dir·pdf_λ)), P = `total_power_w` | ≤ 1 | the host picks lights by `total_power_w` and weights their paths by the emission: both must describe one light; 5σ keeps false alarms below 10⁻⁶, 10⁻³ is f32 rounding |
//! | `beams_power` | ∣mean beam power − P∣ / (5σ + 10⁻³P) over 10⁵ `next_beam` beams | ≤ 1 | a beam's power is the light's flux estimated by one sample, so their mean is P |
//! | `toward` | `sample_toward` records that disagree with the emission (delta-position lights: value·d² against `sample_emission`'s intensity in the same direction; environment lights: pdf against `incident_pdf`, value against `radiance`), or are not finite, or point elsewhere than their point | 0 | next-event estimation and light tracing must see the same light |
//! | `emission` | smallest p-value of the directions `sample_emission` draws from a fixed origin (u₀, u₁ fixed) against `emission_pdf`'s direction density, with every record's densities equal to `emission_pdf`'s | ≥ Šidák level of 1 % | bidirectional MIS weights light paths by `emission_pdf` |
//! | `beams` | smallest p-value of `next_beam`'s directions (delta-position lights, against `emission_pdf`) and wavelengths (against the emission spectrum's pdf) | ≥ Šidák level of 1 % | beams traced by the host and paths connected to the light must be the same light |
//! | `state` | answers of the object rebuilt from its saved state that differ | 0 | blobs and resumed renders rebuild objects from it |

use crate::report::{Bound, CheckResult};
use crate::rng::Rng;
use crate::stats::{interval_cells, mean_se, pearson, per_test_level, SphereGrid};
use crate::subject::{bits, Calls};
use spectrace_plugin_api::lanes::{status, EmittedRay, Incident, Receiver, Vec4f, Wavelengths};
use spectrace_plugin_api::light::LightBox;
use spectrace_plugin_api::{light_flags, LightObject, RandomSample, SceneBounds, SpdObject, Vec3};

/// The scene bounds every light is told.
pub const BOUNDS: SceneBounds = SceneBounds {
    min: Vec3::new(-1.0, -1.0, -1.0),
    max: Vec3::new(1.0, 1.0, 1.0),
    view_min: Vec3::new(-1.0, -1.0, -1.0),
    view_max: Vec3::new(1.0, 1.0, 3.0),
};
/// Rays or beams per statistical check.
pub const SAMPLES: usize = 100_000;

fn v4(d: [f64; 3]) -> Vec4f {
    Vec4f::new(d[0] as f32, d[1] as f32, d[2] as f32)
}

fn f3(v: Vec4f) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn len(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Wavelengths for four lanes drawn from the light's spectrum (or uniformly over 360–830 nm
/// when it declares none), with each lane's density.
fn draw_lambda(spectrum: Option<&SpdObject>, rng: &mut Rng) -> Result<Wavelengths, String> {
    let mut w = Wavelengths::at([0.0; 4]);
    for l in 0..4 {
        let u = (l as f64 + rng.f64()) / 4.0;
        let (nm, pdf) = match spectrum {
            Some(s) => {
                let x = s
                    .spd
                    .sample(u)
                    .into_result()
                    .map_err(|e| format!("emission spectrum sample: {e}"))?;
                (x.nm, x.pdf)
            }
            None => (360.0 + 470.0 * u, 1.0 / 470.0),
        };
        w.nm[l] = nm as f32;
        w.pdf[l] = pdf as f32;
    }
    Ok(w)
}

/// Run every light check.
pub fn run(obj: &LightObject, calls: &Calls<'_, LightObject>) -> Vec<CheckResult> {
    if let Err(e) = obj.light.scene_bounds(&BOUNDS).into_result() {
        return vec![CheckResult::failed(
            "construct",
            format!("scene_bounds: {e}"),
        )];
    }
    let power = match obj.light.total_power_w().into_result() {
        Ok(p) => p,
        Err(e) => {
            return vec![CheckResult::failed(
                "construct",
                format!("total_power_w: {e}"),
            )]
        }
    };
    let spectrum = obj.spectrum.as_ref().into_option();
    let connectable = obj.flags.contains(light_flags::CONNECTABLE);
    vec![
        if connectable {
            power_check(obj, spectrum, power, calls)
        } else {
            CheckResult::skipped(
                "power",
                "not CONNECTABLE: no emission to integrate (see beams_power)",
            )
        },
        beams_power(&obj.light, power),
        if connectable {
            toward(obj, spectrum, calls)
        } else {
            CheckResult::skipped("toward", "not CONNECTABLE")
        },
        if connectable {
            emission(obj, spectrum, calls)
        } else {
            CheckResult::skipped("emission", "not CONNECTABLE")
        },
        beams(obj, spectrum),
        state(obj, calls),
    ]
}

fn power_check(
    obj: &LightObject,
    spectrum: Option<&SpdObject>,
    power: f64,
    calls: &Calls<'_, LightObject>,
) -> CheckResult {
    let mut rng = Rng::new(0x504f_5745);
    let mut est = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        let lambda = match draw_lambda(spectrum, &mut rng) {
            Ok(l) => l,
            Err(e) => return CheckResult::failed("power", e),
        };
        let u = [rng.f32(), rng.f32(), rng.f32(), rng.f32()];
        let mut r = EmittedRay::default();
        let st = obj.light.sample_emission(&u, &lambda, &mut r);
        if st == status::ERROR {
            return CheckResult::failed(
                "power",
                format!("sample_emission: {}", calls.error_text()),
            );
        }
        let mut e = 0.0;
        let pd = r.pdf_position as f64 * r.pdf_direction as f64;
        if st == status::WRITTEN && pd > 0.0 {
            let n = f3(r.normal);
            let d = f3(r.direction);
            let cos = if len(n) > 0.0 {
                ((n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / len(n) / len(d).max(1e-30)).abs()
            } else {
                1.0
            };
            for l in 0..4 {
                if lambda.pdf[l] > 0.0 {
                    e += r.value[l] as f64 * cos / (pd * lambda.pdf[l] as f64) / 4.0;
                }
            }
        }
        est.push(e);
    }
    let (mean, se) = mean_se(&est);
    let tol = 5.0 * se + 1e-3 * power.abs();
    CheckResult::measured(
        "power",
        "|Φ̂ − P| / (5σ + 1e-3 P)",
        (mean - power).abs() / tol.max(1e-300),
        Bound::AtMost,
        1.0,
        format!("total_power_w {power:.6e} W, integrated emission {mean:.6e} ± {se:.2e} W"),
    )
}

fn random_sample(rng: &mut Rng) -> RandomSample {
    let mut s = RandomSample::default();
    for u in s.u.iter_mut() {
        *u = rng.f64();
    }
    s
}

fn beams_power(light: &LightBox, power: f64) -> CheckResult {
    let mut rng = Rng::new(0x4245_414d);
    let mut p = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        match light.next_beam(&random_sample(&mut rng)).into_result() {
            Ok(b) => p.push(b.power_w),
            Err(e) => return CheckResult::failed("beams_power", format!("next_beam: {e}")),
        }
    }
    let (mean, se) = mean_se(&p);
    let tol = 5.0 * se + 1e-3 * power.abs();
    CheckResult::measured(
        "beams_power",
        "|mean beam − P| / (5σ + 1e-3 P)",
        if mean.is_finite() {
            (mean - power).abs() / tol.max(1e-300)
        } else {
            f64::NAN
        },
        Bound::AtMost,
        1.0,
        format!("total_power_w {power:.6e} W, mean beam power {mean:.6e} ± {se:.2e} W"),
    )
}

fn toward(
    obj: &LightObject,
    spectrum: Option<&SpdObject>,
    calls: &Calls<'_, LightObject>,
) -> CheckResult {
    let light = &obj.light;
    let delta = obj.flags.contains(light_flags::DELTA_POSITION);
    let env = obj.flags.contains(light_flags::ENVIRONMENT);
    let mut rng = Rng::new(0x544f_5741);
    let mut bad = 0u64;
    let mut compared = 0u64;
    let mut first = String::new();
    // Values that differ from the emission by more than 1e-3: a few in 10³ are directions
    // rounded to f32 where the intensity falls steeply (a cone's smooth edge); a light that
    // disagrees with itself disagrees nearly everywhere.
    let mut off_values = 0u64;
    let mut first_off = String::new();
    let mut note = |what: String, bad: &mut u64| {
        *bad += 1;
        if first.is_empty() {
            first = what;
        }
    };
    for i in 0..2000 {
        let lambda = match draw_lambda(spectrum, &mut rng) {
            Ok(l) => l,
            Err(e) => return CheckResult::failed("toward", e),
        };
        // The receiver: for delta-position lights at distance 2 or 3 along an emitted ray, so
        // that the intensity there is known; otherwise anywhere in the scene box.
        let mut expected: Option<([f32; 4], f64)> = None;
        let p = if delta {
            let mut r = EmittedRay::default();
            let u = [rng.f32(), rng.f32(), rng.f32(), rng.f32()];
            let st = light.sample_emission(&u, &lambda, &mut r);
            if st != status::WRITTEN {
                if st == status::ERROR {
                    note(format!("sample_emission: {}", calls.error_text()), &mut bad);
                }
                continue;
            }
            let d = if i % 2 == 0 { 2.0 } else { 3.0 };
            let o = f3(r.origin);
            let dir = f3(r.direction);
            expected = Some((r.value, d));
            [o[0] + dir[0] * d, o[1] + dir[1] * d, o[2] + dir[2] * d]
        } else {
            [
                rng.f64() * 2.0 - 1.0,
                rng.f64() * 2.0 - 1.0,
                rng.f64() * 2.0 - 1.0,
            ]
        };
        let receiver = Receiver {
            p: v4(p),
            p_error: Vec4f::default(),
            n: Vec4f::default(),
        };
        let mut inc = Incident::default();
        let st = light.sample_toward(&receiver, rng.f32(), rng.f32(), &lambda, &mut inc);
        match st {
            status::WRITTEN => {}
            status::NONE => continue,
            _ => {
                note(format!("sample_toward: {}", calls.error_text()), &mut bad);
                continue;
            }
        }
        if inc.pdf == 0.0 {
            continue;
        }
        compared += 1;
        if !inc.pdf.is_finite()
            || inc.pdf < 0.0
            || inc.value.iter().any(|v| !v.is_finite() || *v < 0.0)
        {
            note(format!("record not finite or negative: {inc:?}"), &mut bad);
            continue;
        }
        let d = f3(inc.direction);
        if (len(d) - 1.0).abs() > 1e-3 {
            note(format!("direction not unit: {d:?}"), &mut bad);
            continue;
        }
        if !env {
            let q = f3(inc.point);
            let to = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let l = len(to);
            if l > 1e-4 {
                let cos = (to[0] * d[0] + to[1] * d[1] + to[2] * d[2]) / l;
                if cos < 1.0 - 1e-4 {
                    note(
                        format!("direction does not point at the point (cos {cos})"),
                        &mut bad,
                    );
                    continue;
                }
            }
        }
        if let Some((intensity, dist)) = expected {
            for (l, &i_l) in intensity.iter().enumerate() {
                let want = i_l as f64 / (dist * dist);
                let got = inc.value[l] as f64;
                if (got - want).abs() > 1e-3 * want.abs().max(got.abs()) + 1e-30 {
                    off_values += 1;
                    if first_off.is_empty() {
                        first_off = format!(
                            "at {dist} m: value {got:.5e}, intensity/d² from sample_emission {want:.5e}"
                        );
                    }
                    break;
                }
            }
        }
        if env {
            let ip = light.incident_pdf(&receiver, &inc.direction);
            let r = light.radiance(&inc.direction, &lambda);
            if (ip - inc.pdf).abs() as f64 > 1e-3 * ip.abs().max(inc.pdf.abs()) as f64 {
                note(
                    format!("record pdf {} but incident_pdf {ip}", inc.pdf),
                    &mut bad,
                );
            } else if (0..4).any(|l| {
                (r.v[l] - inc.value[l]).abs() > 1e-3 * r.v[l].abs().max(inc.value[l].abs())
            }) {
                note(
                    format!("record value {:?} but radiance {:?}", inc.value, r.v),
                    &mut bad,
                );
            }
        }
    }
    if off_values as f64 > 1e-3 * compared as f64 {
        bad += off_values;
        if first.is_empty() {
            first = first_off;
        }
    }
    CheckResult::measured(
        "toward",
        "records disagreeing",
        bad as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{compared} records compared ({}){}",
            if delta {
                "value·d² against sample_emission's intensity"
            } else if env {
                "pdf against incident_pdf, value against radiance"
            } else {
                "finite, unit direction towards the point"
            },
            if first.is_empty() {
                String::new()
            } else {
                format!("; first: {first}")
            }
        ),
    )
}

fn emission(
    obj: &LightObject,
    spectrum: Option<&SpdObject>,
    calls: &Calls<'_, LightObject>,
) -> CheckResult {
    let light = &obj.light;
    let grid = SphereGrid::DEFAULT;
    let origins = 2;
    let level = per_test_level(origins);
    let mut min_p = f64::INFINITY;
    let mut detail = Vec::new();
    let mut pdf_mismatch = 0u64;
    let mut first_mismatch = String::new();
    let mut rng = Rng::new(0x454d_4953);
    let lambda = match draw_lambda(spectrum, &mut rng) {
        Ok(l) => l,
        Err(e) => return CheckResult::failed("emission", e),
    };
    let mut tested = 0;
    for case in 0..origins {
        let u01 = [rng.f32(), rng.f32()];
        let mut counts = vec![0u64; grid.rows * grid.cols];
        let mut origin: Option<Vec4f> = None;
        let mut moved = false;
        let mut first_dir: Option<[f64; 3]> = None;
        let mut same_dir = true;
        for _ in 0..SAMPLES {
            let u = [u01[0], u01[1], rng.f32(), rng.f32()];
            let mut r = EmittedRay::default();
            match light.sample_emission(&u, &lambda, &mut r) {
                status::WRITTEN => {}
                status::NONE => continue,
                _ => {
                    return CheckResult::failed(
                        "emission",
                        format!("sample_emission: {}", calls.error_text()),
                    )
                }
            }
            if r.pdf_direction == 0.0 || r.pdf_position == 0.0 {
                continue;
            }
            let want = light.emission_pdf(&r.origin, &r.direction);
            let off = |a: f32, b: f32| (a - b).abs() > 1e-3 * a.abs().max(b.abs());
            if off(want.position, r.pdf_position) || off(want.direction, r.pdf_direction) {
                pdf_mismatch += 1;
                if first_mismatch.is_empty() {
                    first_mismatch = format!(
                        "record (position {}, direction {}) but emission_pdf ({}, {})",
                        r.pdf_position, r.pdf_direction, want.position, want.direction
                    );
                }
            }
            match origin {
                None => origin = Some(r.origin),
                Some(o) if o != r.origin => moved = true,
                _ => {}
            }
            let d = f3(r.direction);
            match first_dir {
                None => first_dir = Some(d),
                Some(f) if f != d => same_dir = false,
                _ => {}
            }
            if let Some(c) = grid.cell(d) {
                counts[c] += 1;
            }
        }
        let Some(o) = origin else { continue };
        if obj.flags.contains(light_flags::DELTA_DIRECTION) {
            detail.push(format!(
                "origin {case}: delta direction, {}",
                if same_dir {
                    "one direction"
                } else {
                    "directions VARY"
                }
            ));
            if !same_dir {
                min_p = 0.0;
            }
            continue;
        }
        if moved {
            detail.push(format!(
                "origin {case}: the origin depends on u₂, u₃, so no conditional test"
            ));
            continue;
        }
        let integrals = grid.integrate(&mut |d| light.emission_pdf(&o, &v4(d)).direction as f64);
        let t = pearson(&counts, &integrals);
        tested += 1;
        min_p = min_p.min(t.p_value);
        detail.push(format!(
            "origin {case}: χ² {:.1}, dof {}, p {:.3e}, ∫pdf_dir {:.4}",
            t.statistic, t.dof, t.p_value, t.mass
        ));
    }
    if pdf_mismatch > 0 {
        detail.push(format!(
            "{pdf_mismatch} records whose densities differ from emission_pdf (first: {first_mismatch})"
        ));
        // A direction rounded to f32 right at a jump of the density (a cone's edge) may land
        // on the other side of it: a few in 10⁴ are tolerated, a systematic difference is not.
        if pdf_mismatch as f64 > 1e-4 * (origins * SAMPLES) as f64 {
            min_p = 0.0;
        }
    }
    if tested == 0 && pdf_mismatch == 0 && min_p.is_infinite() {
        return CheckResult::skipped(
            "emission",
            format!(
                "no conditional direction test applies; {}",
                detail.join("; ")
            ),
        );
    }
    CheckResult::measured(
        "emission",
        "min p-value",
        if min_p.is_infinite() { 1.0 } else { min_p },
        Bound::AtLeast,
        level,
        detail.join("; "),
    )
}

fn beams(obj: &LightObject, spectrum: Option<&SpdObject>) -> CheckResult {
    let light = &obj.light;
    let mut rng = Rng::new(0x4245_4d53);
    let mut dirs = Vec::with_capacity(SAMPLES);
    let mut nms = Vec::with_capacity(SAMPLES);
    let mut origin: Option<Vec3> = None;
    let mut moved = false;
    for _ in 0..SAMPLES {
        match light.next_beam(&random_sample(&mut rng)).into_result() {
            Ok(b) => {
                dirs.push(b.direction);
                nms.push(b.colour[0]);
                match origin {
                    None => origin = Some(b.origin),
                    Some(o) if o != b.origin => moved = true,
                    _ => {}
                }
            }
            Err(e) => return CheckResult::failed("beams", format!("next_beam: {e}")),
        }
    }
    // Which beams' representation the type declares is not part of the object; the kit reads
    // directions as unit vectors and colours as wavelengths only where they look like them.
    let unit = dirs.iter().all(|d| (len(*d) - 1.0).abs() < 1e-6);
    let spectral = nms.iter().all(|&nm| (100.0..10_000.0).contains(&nm));
    let mut tests: Vec<(String, f64)> = Vec::new();
    let connectable = obj.flags.contains(light_flags::CONNECTABLE);
    if connectable && !moved && unit && !obj.flags.contains(light_flags::DELTA_DIRECTION) {
        if let Some(o) = origin {
            let grid = SphereGrid::DEFAULT;
            let mut counts = vec![0u64; grid.rows * grid.cols];
            for d in &dirs {
                if let Some(c) = grid.cell(*d) {
                    counts[c] += 1;
                }
            }
            let o4 = Vec4f::new(o.x as f32, o.y as f32, o.z as f32);
            let integrals =
                grid.integrate(&mut |d| light.emission_pdf(&o4, &v4(d)).direction as f64);
            let t = pearson(&counts, &integrals);
            tests.push((
                format!(
                    "directions: χ² {:.1}, dof {}, p {:.3e}",
                    t.statistic, t.dof, t.p_value
                ),
                t.p_value,
            ));
        }
    }
    if let (Some(s), true) = (spectrum, spectral) {
        let lines: Vec<f64> = s.lines.iter().map(|l| l.nm).collect();
        let cont: Vec<f64> = nms
            .iter()
            .copied()
            .filter(|nm| !lines.iter().any(|l| (l - nm).abs() < 1e-9))
            .collect();
        let (a, b) = (s.range.min_nm, s.range.max_nm);
        if !cont.is_empty() && b > a {
            let (counts, integrals, outside) = interval_cells(&cont, a, b, 64, &mut |x| {
                s.spd.pdf(x).into_result().unwrap_or(f64::NAN)
            });
            let t = pearson(&counts, &integrals);
            let p = if outside > 0 { 0.0 } else { t.p_value };
            tests.push((
                format!(
                    "wavelengths: χ² {:.1}, dof {}, p {:.3e}{}",
                    t.statistic,
                    t.dof,
                    t.p_value,
                    if outside > 0 {
                        format!(", {outside} outside the spectrum's range")
                    } else {
                        String::new()
                    }
                ),
                p,
            ));
        }
    }
    if tests.is_empty() {
        return CheckResult::skipped(
            "beams",
            "no reference distribution: the light is not CONNECTABLE with one origin, declares no \
             spectrum, or its beams are not in the native representation",
        );
    }
    let level = per_test_level(tests.len());
    let min_p = tests.iter().map(|t| t.1).fold(1.0, f64::min);
    CheckResult::measured(
        "beams",
        "min p-value",
        min_p,
        Bound::AtLeast,
        level,
        tests
            .into_iter()
            .map(|t| t.0)
            .collect::<Vec<_>>()
            .join("; "),
    )
}

/// Answers of a fixed list of calls, as bits.
fn answers(obj: &LightObject) -> Vec<Vec<u32>> {
    let light = &obj.light;
    let mut rng = Rng::new(0x5354_4154);
    let lambda = Wavelengths::at([450.0, 520.0, 600.0, 680.0]);
    let connectable = obj.flags.contains(light_flags::CONNECTABLE);
    (0..256)
        .map(|_| {
            let mut a = Vec::new();
            let s = random_sample(&mut rng);
            match light.next_beam(&s).into_result() {
                Ok(b) => {
                    for v in [
                        b.origin.x,
                        b.origin.y,
                        b.origin.z,
                        b.direction[0],
                        b.direction[1],
                        b.direction[2],
                        b.colour[0],
                        b.colour[1],
                        b.colour[2],
                        b.power_w,
                    ] {
                        let x = v.to_bits();
                        a.extend([x as u32, (x >> 32) as u32]);
                    }
                }
                Err(_) => a.push(u32::MAX),
            }
            if connectable {
                let u = [rng.f32(), rng.f32(), rng.f32(), rng.f32()];
                let mut r = EmittedRay::default();
                a.push(light.sample_emission(&u, &lambda, &mut r));
                a.extend(
                    [
                        r.origin.x,
                        r.origin.y,
                        r.origin.z,
                        r.direction.x,
                        r.direction.y,
                    ]
                    .iter()
                    .map(|&v| bits(v)),
                );
                a.extend(r.value.iter().map(|&v| bits(v)));
                a.extend([bits(r.pdf_position), bits(r.pdf_direction)]);
                let receiver = Receiver {
                    p: v4([
                        rng.f64() * 2.0 - 1.0,
                        rng.f64() * 2.0 - 1.0,
                        rng.f64() * 2.0 - 1.0,
                    ]),
                    p_error: Vec4f::default(),
                    n: Vec4f::default(),
                };
                let mut inc = Incident::default();
                a.push(light.sample_toward(&receiver, rng.f32(), rng.f32(), &lambda, &mut inc));
                a.extend(inc.value.iter().map(|&v| bits(v)));
                a.extend([bits(inc.pdf), bits(inc.direction.x), bits(inc.direction.y)]);
            }
            a
        })
        .collect()
}

fn state(obj: &LightObject, calls: &Calls<'_, LightObject>) -> CheckResult {
    let Some(restore) = calls.restore else {
        return CheckResult::skipped("state", "no way to rebuild this object from state here");
    };
    let bytes = match obj.light.save_state().into_result() {
        Ok(b) => b,
        Err(e) => return CheckResult::failed("state", format!("save_state failed: {e}")),
    };
    let restored = match restore(&bytes) {
        Ok(r) => r,
        Err(e) => {
            return CheckResult::failed("state", format!("rebuilding from its state failed: {e}"))
        }
    };
    if let Err(e) = restored.light.scene_bounds(&BOUNDS).into_result() {
        return CheckResult::failed("state", format!("restored object: scene_bounds: {e}"));
    }
    let a1 = answers(obj);
    let a2 = answers(obj);
    let mask: Vec<bool> = a1.iter().zip(&a2).map(|(x, y)| x == y).collect();
    let b = answers(&restored);
    let n = crate::material::differences(&a1, &b, &mask);
    let p1 = obj.light.total_power_w().into_result().ok();
    let p2 = restored.light.total_power_w().into_result().ok();
    let n = n + usize::from(p1.map(f64::to_bits) != p2.map(f64::to_bits));
    CheckResult::measured(
        "state",
        "answers differing after restore",
        n as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{} bytes of state, {} inputs and total_power_w compared",
            bytes.len(),
            a1.len()
        ),
    )
}
