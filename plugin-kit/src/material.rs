//! The checks of a material ([`MaterialObject`]).
//!
//! Every check calls the material at one surface point (position 0, geometric and shading
//! normal +z, uv (0.5, 0.5)) with the four wavelengths 450, 520, 600 and 680 nm, from the
//! outgoing directions of [`WO`] (three above the surface, one below it, at different azimuths).
//!
//! | check | statistic | threshold | why |
//! |---|---|---|---|
//! | `finite` | values that are NaN, ±∞ or < 0, plus calls that failed | 0 | eval, pdf and every sampled record must be usable as they are |
//! | `chi2` | smallest p-value of the directions sampled (10⁵ per `wo`) against `pdf`, sphere binned 16 × 32 | ≥ Šidák level of 1 % over the cases | the sampling routine must draw what `pdf` says (shape; the mass is `pdf_integral`'s) |
//! | `sample_pdf` | share of sampled records whose `pdf`/`value` differ from `pdf()`/`eval()` at the same directions by > 10⁻³ relative | ≤ 10⁻³ | the integrators weight a sampled direction with the record's values and an NEE direction with the calls' |
//! | `pdf_integral` | max over `wo` of (∫pdf dω − 1) and of (∣∫pdf − f∣ − 5σ), f the share of non-delta samples | ≤ 0.01 | a density integrates to at most 1, and to the share of samples it describes; 0.01 covers the quadrature error of sharp lobes |
//! | `energy` | max over `wo` and lanes of the white-furnace albedo E[f·∣cos θi∣/pdf] − 5σ, in importance transport | ≤ 1.001 | a passive surface reflects at most what it receives (importance transport carries no 1/η² radiance scaling); 5σ keeps false alarms below 10⁻⁶ |
//! | `reciprocity` | max relative ∣f(wo, wi) − f(wi, wo)∣ over 2000 pairs | ≤ 10⁻³ | declared RECIPROCAL; 10⁻³ is f32 rounding with margin |
//! | `determinism` | answers that differ when the same call is made twice | 0 | the host draws all random numbers; equal numbers must give equal answers |
//! | `threads` | answers on 4 threads at once that differ from the calling thread's | 0 | the host calls one object from every render thread (calls that differ on one thread already are `determinism`'s) |
//! | `state` | answers of the object rebuilt from its saved state that differ | 0 | blobs and resumed renders rebuild objects from it |

use crate::report::{Bound, CheckResult};
use crate::rng::Rng;
use crate::stats::{mean_se, pearson, per_test_level, SphereGrid};
use crate::subject::{bits, Calls};
use spectrace_plugin_api::lanes::{status, Scatter, Surface, Vec4f, Wavelengths};
use spectrace_plugin_api::material::MaterialBox;
use spectrace_plugin_api::{material_flags, MaterialObject, TransportMode};

/// The outgoing directions (cos θ, φ in degrees) the checks use.
pub const WO: [(f64, f64); 4] = [(0.95, 10.0), (0.6, 100.0), (0.15, 200.0), (-0.6, 300.0)];
/// Samples per outgoing direction for `chi2`, `sample_pdf`, `pdf_integral`.
pub const SAMPLES: usize = 100_000;
/// Samples per outgoing direction for `energy`.
pub const ENERGY_SAMPLES: usize = 50_000;
const LAMBDA: [f32; 4] = [450.0, 520.0, 600.0, 680.0];

fn dir(cos_theta: f64, phi_deg: f64) -> [f64; 3] {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let p = phi_deg.to_radians();
    [s * p.cos(), s * p.sin(), cos_theta]
}

fn v4(d: [f64; 3]) -> Vec4f {
    Vec4f::new(d[0] as f32, d[1] as f32, d[2] as f32)
}

fn surface() -> Surface {
    Surface {
        uv: [0.5, 0.5],
        position: Vec4f::new(0.0, 0.0, 0.0),
        geometric_normal: Vec4f::new(0.0, 0.0, 1.0),
        shading_normal: Vec4f::new(0.0, 0.0, 1.0),
    }
}

struct Draw {
    status: u32,
    s: Scatter,
}

fn sample(m: &MaterialBox, wo: &Vec4f, u: [f32; 3], mode: TransportMode) -> Draw {
    let mut s = Scatter::default();
    let status = m.sample(
        wo,
        &surface(),
        &Wavelengths::at(LAMBDA),
        u[0],
        u[1],
        u[2],
        mode,
        &mut s,
    );
    Draw { status, s }
}

fn is_delta(s: &Scatter) -> bool {
    s.flags.contains(material_flags::SPECULAR)
}

fn bad(v: f32) -> bool {
    !v.is_finite() || v < 0.0
}

/// Run every material check.
pub fn run(obj: &MaterialObject, calls: &Calls<'_, MaterialObject>) -> Vec<CheckResult> {
    let m = &obj.material;
    let lambda = Wavelengths::at(LAMBDA);
    let surf = surface();
    let grid = SphereGrid::DEFAULT;

    // One pass over the sampled directions serves chi2, sample_pdf, pdf_integral and finite.
    let mut bad_values = 0u64;
    let mut failed_calls = 0u64;
    let mut first_error = String::new();
    let mut note_error = |what: &str, calls: &Calls<'_, MaterialObject>, n: &mut u64| {
        *n += 1;
        if first_error.is_empty() {
            first_error = format!("{what}: {}", calls.error_text());
        } else {
            let _ = (calls.take_error)();
        }
    };
    let mut min_p = f64::INFINITY;
    let mut chi2_detail = Vec::new();
    let mut chi2_cases = 0;
    let mut record_mismatch = 0u64;
    let mut record_compared = 0u64;
    let mut record_worst = 0.0f64;
    let mut integral_excess = f64::NEG_INFINITY;
    let mut integral_detail = Vec::new();
    let level = per_test_level(WO.len());
    for (case, &(c, phi)) in WO.iter().enumerate() {
        let wo = v4(dir(c, phi));
        let mut rng = Rng::new(0x4d41_5431 + case as u64);
        let mut counts = vec![0u64; grid.rows * grid.cols];
        let mut non_delta = 0u64;
        for _ in 0..SAMPLES {
            let u = [rng.f32(), rng.f32(), rng.f32()];
            let d = sample(m, &wo, u, TransportMode::Radiance);
            match d.status {
                status::NONE => continue,
                status::WRITTEN => {}
                _ => {
                    note_error("sample", calls, &mut failed_calls);
                    continue;
                }
            }
            let s = d.s;
            let len = s.wi.dot(s.wi).sqrt();
            let lanes = if s.flags.contains(material_flags::DISPERSIVE) {
                1
            } else {
                4
            };
            let record_bad = bad(s.pdf)
                || s.value[..lanes].iter().any(|&v| bad(v))
                || !((len - 1.0).abs() < 1e-3);
            if record_bad {
                bad_values += 1;
                continue;
            }
            if is_delta(&s) {
                continue;
            }
            non_delta += 1;
            if let Some(cell) = grid.cell([s.wi.x as f64, s.wi.y as f64, s.wi.z as f64]) {
                counts[cell] += 1;
            }
            if record_compared < 4000 {
                record_compared += 1;
                let p = m.pdf(&wo, &s.wi, &surf, &lambda, TransportMode::Radiance);
                let f = m.eval(&wo, &s.wi, &surf, &lambda, TransportMode::Radiance);
                let mut worst = rel(s.pdf, p);
                for l in 0..lanes {
                    worst = worst.max(rel(s.value[l], f.v[l]));
                }
                if worst.is_nan() {
                    worst = f64::INFINITY;
                }
                record_worst = record_worst.max(worst);
                if worst > 1e-3 {
                    record_mismatch += 1;
                }
            }
        }
        let mut pdf_calls_failed = 0u64;
        let integrals = grid.integrate(&mut |d| {
            let p = m.pdf(&wo, &v4(d), &surf, &lambda, TransportMode::Radiance);
            if p.is_nan() {
                pdf_calls_failed += 1;
                let _ = (calls.take_error)();
            }
            p as f64
        });
        let t = pearson(&counts, &integrals);
        let f = non_delta as f64 / SAMPLES as f64;
        let sigma = (f * (1.0 - f) / SAMPLES as f64).sqrt();
        let excess = (t.mass - 1.0).max((t.mass - f).abs() - 5.0 * sigma);
        integral_excess = integral_excess.max(excess);
        integral_detail.push(format!("cosθo {c}: ∫pdf {:.4}, f {:.4}", t.mass, f));
        if non_delta > 0 || t.mass > 0.0 {
            chi2_cases += 1;
            min_p = min_p.min(t.p_value);
            chi2_detail.push(format!(
                "cosθo {c}: χ² {:.1}, dof {}, p {:.3e}{}",
                t.statistic,
                t.dof,
                t.p_value,
                if t.in_zero_cells > 0 {
                    format!(", {} samples where pdf = 0", t.in_zero_cells)
                } else {
                    String::new()
                }
            ));
        }
    }

    // Eval and pdf over random pairs of directions on the whole sphere, both transport modes.
    let mut rng = Rng::new(0x4649_4e49);
    for i in 0..20_000 {
        let wo = v4(rng.sphere());
        let wi = v4(rng.sphere());
        let mode = if i % 2 == 0 {
            TransportMode::Radiance
        } else {
            TransportMode::Importance
        };
        let f = m.eval(&wo, &wi, &surf, &lambda, mode);
        if f.v.iter().all(|v| v.is_nan()) {
            note_error("eval", calls, &mut failed_calls);
        } else if f.v.iter().any(|&v| bad(v)) {
            bad_values += 1;
        }
        let p = m.pdf(&wo, &wi, &surf, &lambda, mode);
        if p.is_nan() {
            note_error("pdf", calls, &mut failed_calls);
        } else if bad(p) {
            bad_values += 1;
        }
    }

    let mut out = Vec::new();
    out.push(CheckResult::measured(
        "finite",
        "bad values + failed calls",
        (bad_values + failed_calls) as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{bad_values} values NaN/inf/negative, {failed_calls} calls failed{}",
            if first_error.is_empty() {
                String::new()
            } else {
                format!(" (first: {first_error})")
            }
        ),
    ));
    out.push(if chi2_cases == 0 {
        CheckResult::skipped(
            "chi2",
            "no non-delta lobes: nothing is sampled with a density",
        )
    } else {
        CheckResult::measured(
            "chi2",
            "min p-value",
            min_p,
            Bound::AtLeast,
            level,
            chi2_detail.join("; "),
        )
    });
    out.push(if record_compared == 0 {
        CheckResult::skipped("sample_pdf", "no non-delta samples to compare")
    } else {
        CheckResult::measured(
            "sample_pdf",
            "share of records ≠ pdf()/eval()",
            record_mismatch as f64 / record_compared as f64,
            Bound::AtMost,
            1e-3,
            format!(
                "{record_mismatch} of {record_compared} differ by > 1e-3 relative; worst {record_worst:.3e}"
            ),
        )
    });
    out.push(CheckResult::measured(
        "pdf_integral",
        "max(∫pdf−1, |∫pdf−f|−5σ)",
        integral_excess,
        Bound::AtMost,
        0.01,
        integral_detail.join("; "),
    ));
    out.push(energy(m, calls));
    out.push(reciprocity(obj, &lambda, &surf));
    let (det, deterministic) = determinism(m);
    out.push(det);
    out.push(threads(m, &deterministic));
    out.push(state(m, calls, &deterministic));
    out
}

fn rel(a: f32, b: f32) -> f64 {
    let (a, b) = (a as f64, b as f64);
    let d = (a - b).abs();
    if d == 0.0 {
        0.0
    } else {
        d / a.abs().max(b.abs()).max(1e-6)
    }
}

fn energy(m: &MaterialBox, calls: &Calls<'_, MaterialObject>) -> CheckResult {
    let mut worst = f64::NEG_INFINITY;
    let mut detail = Vec::new();
    for (case, &(c, phi)) in WO.iter().enumerate() {
        let wo = v4(dir(c, phi));
        let mut rng = Rng::new(0x454e_4552 + case as u64);
        let mut per_lane: Vec<Vec<f64>> =
            (0..4).map(|_| Vec::with_capacity(ENERGY_SAMPLES)).collect();
        for _ in 0..ENERGY_SAMPLES {
            let u = [rng.f32(), rng.f32(), rng.f32()];
            let d = sample(m, &wo, u, TransportMode::Importance);
            let mut w = [0.0f64; 4];
            if d.status == status::WRITTEN && d.s.pdf > 0.0 && d.s.pdf.is_finite() {
                let cos = (d.s.wi.z as f64).abs();
                for (l, wl) in w.iter_mut().enumerate() {
                    let v = d.s.value[l] as f64 * cos / d.s.pdf as f64;
                    *wl = if v.is_finite() { v } else { 0.0 };
                }
            } else if d.status != status::WRITTEN && d.status != status::NONE {
                let _ = (calls.take_error)();
            }
            for l in 0..4 {
                per_lane[l].push(w[l]);
            }
        }
        let mut line = format!("cosθo {c}: albedo");
        for lane in &per_lane {
            let (mean, se) = mean_se(lane);
            worst = worst.max(mean - 5.0 * se);
            line.push_str(&format!(" {mean:.4}±{se:.1e}"));
        }
        detail.push(line);
    }
    CheckResult::measured(
        "energy",
        "max albedo − 5σ",
        worst,
        Bound::AtMost,
        1.001,
        detail.join("; "),
    )
}

fn reciprocity(obj: &MaterialObject, lambda: &Wavelengths, surf: &Surface) -> CheckResult {
    if !obj.flags.contains(material_flags::RECIPROCAL) {
        return CheckResult::skipped("reciprocity", "the material does not declare RECIPROCAL");
    }
    let m = &obj.material;
    let mut rng = Rng::new(0x5245_4349);
    let mut worst = 0.0f64;
    for _ in 0..2000 {
        let mut a = rng.sphere();
        let mut b = rng.sphere();
        a[2] = a[2].abs();
        b[2] = b[2].abs();
        let f1 = m.eval(&v4(a), &v4(b), surf, lambda, TransportMode::Radiance);
        let f2 = m.eval(&v4(b), &v4(a), surf, lambda, TransportMode::Radiance);
        for l in 0..4 {
            let r = rel(f1.v[l], f2.v[l]);
            worst = worst.max(if r.is_nan() { f64::INFINITY } else { r });
        }
    }
    CheckResult::measured(
        "reciprocity",
        "max rel |f(wo,wi) − f(wi,wo)|",
        worst,
        Bound::AtMost,
        1e-3,
        "2000 pairs of directions above the surface, radiance transport",
    )
}

/// The answers of a fixed list of calls, as bits, one vector per input.
fn answers(m: &MaterialBox) -> Vec<Vec<u32>> {
    let lambda = Wavelengths::at(LAMBDA);
    let surf = surface();
    let mut rng = Rng::new(0x4445_5445);
    (0..512)
        .map(|i| {
            let wo = v4(rng.sphere());
            let wi = v4(rng.sphere());
            let u = [rng.f32(), rng.f32(), rng.f32()];
            let mode = if i % 2 == 0 {
                TransportMode::Radiance
            } else {
                TransportMode::Importance
            };
            let d = sample(m, &wo, u, mode);
            let mut a = vec![d.status];
            if d.status == status::WRITTEN {
                let s = d.s;
                a.extend([
                    bits(s.wi.x),
                    bits(s.wi.y),
                    bits(s.wi.z),
                    bits(s.pdf),
                    s.flags.0,
                ]);
                a.extend(s.value.iter().map(|&v| bits(v)));
                a.push(bits(s.eta));
            }
            a.extend(
                m.eval(&wo, &wi, &surf, &lambda, mode)
                    .v
                    .iter()
                    .map(|&v| bits(v)),
            );
            a.push(bits(m.pdf(&wo, &wi, &surf, &lambda, mode)));
            a
        })
        .collect()
}

/// Compare two answer lists on the inputs marked in `mask`; the count of differences.
pub(crate) fn differences(a: &[Vec<u32>], b: &[Vec<u32>], mask: &[bool]) -> usize {
    a.iter()
        .zip(b)
        .zip(mask)
        .filter(|((x, y), &m)| m && x != y)
        .count()
}

fn determinism(m: &MaterialBox) -> (CheckResult, Vec<bool>) {
    let a = answers(m);
    let b = answers(m);
    let mask: Vec<bool> = a.iter().zip(&b).map(|(x, y)| x == y).collect();
    let n = mask.iter().filter(|&&s| !s).count();
    (
        CheckResult::measured(
            "determinism",
            "inputs answered differently",
            n as f64,
            Bound::AtMost,
            0.0,
            format!(
                "{} inputs (sample, eval, pdf with the same numbers), each asked twice",
                a.len()
            ),
        ),
        mask,
    )
}

fn threads(m: &MaterialBox, mask: &[bool]) -> CheckResult {
    let reference = answers(m);
    let diffs: usize = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4).map(|_| s.spawn(|| answers(m))).collect();
        handles
            .into_iter()
            .map(|h| match h.join() {
                Ok(a) => differences(&reference, &a, mask),
                Err(_) => reference.len(),
            })
            .sum()
    });
    CheckResult::measured(
        "threads",
        "answers differing across threads",
        diffs as f64,
        Bound::AtMost,
        0.0,
        format!(
            "4 threads at once, {} inputs each, compared with the calling thread's answers",
            reference.len()
        ),
    )
}

fn state(m: &MaterialBox, calls: &Calls<'_, MaterialObject>, mask: &[bool]) -> CheckResult {
    let Some(restore) = calls.restore else {
        return CheckResult::skipped("state", "no way to rebuild this object from state here");
    };
    let bytes = match m.save_state().into_result() {
        Ok(b) => b,
        Err(e) => return CheckResult::failed("state", format!("save_state failed: {e}")),
    };
    let restored = match restore(&bytes) {
        Ok(r) => r,
        Err(e) => {
            return CheckResult::failed("state", format!("rebuilding from its state failed: {e}"))
        }
    };
    let a = answers(m);
    let b = answers(&restored.material);
    let n = differences(&a, &b, mask);
    CheckResult::measured(
        "state",
        "answers differing after restore",
        n as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{} bytes of state, {} inputs compared",
            bytes.len(),
            a.len()
        ),
    )
}
