//! The checks of an SPD ([`SpdObject`]).
//!
//! | check | statistic | threshold | why |
//! |---|---|---|---|
//! | `integral` | ∣∫ value dλ + Σ line weights − 1∣, Simpson on a 0.05 nm grid over the declared range; a negative or non-finite value makes it ∞ | ≤ 2·10⁻³ | an SPD is normalised (absolute power belongs to whoever uses it); 2·10⁻³ covers tables integrated by another rule |
//! | `chi2` | p-value of 10⁵ samples' continuous part (those not on a line) against `pdf`, 64 bins over the range, with every sample inside the range and its `pdf` equal to `pdf(nm)` | ≥ 1 % | hero wavelength sampling divides by the density `sample` reports |
//! | `lines` | largest ∣share of samples on a line − its weight∣ / (5σ + 10⁻⁴), a wavelength drawn more than 10 times and not declared counting as a line of weight 0 | ≤ 1 | the host weighs declared lines exactly; an undeclared line is a delta it would treat as a density |
//! | `state` | answers of the object rebuilt from its saved state that differ | 0 | blobs rebuild objects from it |

use crate::report::{Bound, CheckResult};
use crate::rng::Rng;
use crate::stats::{interval_cells, pearson, simpson, SIGNIFICANCE};
use crate::subject::Calls;
use spectrace_plugin_api::SpdObject;
use std::collections::HashMap;

/// Samples drawn for `chi2` and `lines`.
pub const SAMPLES: usize = 100_000;

/// Run every SPD check.
pub fn run(obj: &SpdObject, calls: &Calls<'_, SpdObject>) -> Vec<CheckResult> {
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    let line_only = a == b && !obj.lines.is_empty();
    if !(a.is_finite() && b.is_finite() && (a < b || line_only)) {
        return vec![CheckResult::failed(
            "integral",
            format!("the declared range [{a}, {b}] nm is empty or not finite"),
        )];
    }
    // Samples, shared by chi2 and lines.
    let mut rng = Rng::new(0x5350_4431);
    let mut samples = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        match obj.spd.sample(rng.f64()).into_result() {
            Ok(s) => samples.push(s),
            Err(e) => {
                let f = CheckResult::failed("chi2", format!("sample failed: {e}"));
                return vec![
                    integral(obj),
                    f,
                    CheckResult::failed("lines", "no samples"),
                    state(obj, calls),
                ];
            }
        }
    }
    vec![
        integral(obj),
        chi2(obj, &samples),
        lines(obj, &samples),
        state(obj, calls),
    ]
}

fn integral(obj: &SpdObject) -> CheckResult {
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    // A spectrum of lines alone may declare a range of zero width: no continuous part.
    let n = (((b - a) / 0.05).ceil() as usize).max(2);
    let mut bad = 0u64;
    let mut error = None;
    let cont = simpson(a, b, n, &mut |x| match obj.spd.value(x).into_result() {
        Ok(v) if v.is_finite() && v >= 0.0 => v,
        Ok(_) => {
            bad += 1;
            0.0
        }
        Err(e) => {
            error.get_or_insert(e.to_string());
            bad += 1;
            0.0
        }
    });
    let lines: f64 = obj.lines.iter().map(|l| l.weight).sum();
    let total = cont + lines;
    CheckResult::measured(
        "integral",
        "|∫value + Σlines − 1|",
        if bad > 0 {
            f64::INFINITY
        } else {
            (total - 1.0).abs()
        },
        Bound::AtMost,
        2e-3,
        format!(
            "∫ value dλ over [{a}, {b}] nm = {cont:.6}, lines {lines:.6}{}{}",
            if bad > 0 {
                format!("; {bad} values negative, non-finite or failed")
            } else {
                String::new()
            },
            error
                .map(|e| format!(" (first error: {e})"))
                .unwrap_or_default()
        ),
    )
}

fn on_line(obj: &SpdObject, nm: f64) -> bool {
    obj.lines.iter().any(|l| l.nm == nm)
}

fn chi2(obj: &SpdObject, samples: &[spectrace_plugin_api::WavelengthSample]) -> CheckResult {
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    let atoms = atoms(samples);
    let cont: Vec<f64> = samples
        .iter()
        .map(|s| s.nm)
        .filter(|&nm| !on_line(obj, nm) && !atoms.contains_key(&nm.to_bits()))
        .collect();
    let mut pdf_mismatch = 0u64;
    for s in samples.iter().take(5000) {
        if on_line(obj, s.nm) || atoms.contains_key(&s.nm.to_bits()) {
            continue;
        }
        let p = obj.spd.pdf(s.nm).into_result().unwrap_or(f64::NAN);
        if !((p - s.pdf).abs() <= 1e-6 * p.abs().max(s.pdf.abs())) {
            pdf_mismatch += 1;
        }
    }
    if cont.is_empty() || !(b > a) {
        return CheckResult::skipped("chi2", "every sample is on a line: no continuous part");
    }
    let (counts, integrals, outside) = interval_cells(&cont, a, b, 64, &mut |x| {
        obj.spd.pdf(x).into_result().unwrap_or(f64::NAN)
    });
    let t = pearson(&counts, &integrals);
    let p = if outside > 0 || pdf_mismatch > 0 {
        0.0
    } else {
        t.p_value
    };
    CheckResult::measured(
        "chi2",
        "p-value",
        p,
        Bound::AtLeast,
        SIGNIFICANCE,
        format!(
            "χ² {:.1}, dof {}, p {:.3e} over {} continuous samples; {outside} outside the range; \
             {pdf_mismatch} samples whose pdf ≠ pdf(nm)",
            t.statistic,
            t.dof,
            t.p_value,
            cont.len()
        ),
    )
}

/// Wavelengths drawn more than 10 times: at 10⁵ draws from a continuous density in f64, even
/// one repeat is unlikely, so these are lines.
fn atoms(samples: &[spectrace_plugin_api::WavelengthSample]) -> HashMap<u64, usize> {
    let mut count: HashMap<u64, usize> = HashMap::new();
    for s in samples {
        *count.entry(s.nm.to_bits()).or_default() += 1;
    }
    count.retain(|_, c| *c > 10);
    count
}

fn lines(obj: &SpdObject, samples: &[spectrace_plugin_api::WavelengthSample]) -> CheckResult {
    let n = samples.len() as f64;
    let mut worst = 0.0f64;
    let mut detail = Vec::new();
    for l in obj.lines.iter() {
        let hits: Vec<_> = samples.iter().filter(|s| s.nm == l.nm).collect();
        let share = hits.len() as f64 / n;
        let sigma = (l.weight * (1.0 - l.weight) / n).max(0.0).sqrt();
        let z = (share - l.weight).abs() / (5.0 * sigma + 1e-4);
        let wrong_pdf = hits.iter().filter(|s| s.pdf != l.weight).count();
        worst = worst.max(if wrong_pdf > 0 { f64::INFINITY } else { z });
        detail.push(format!(
            "line {} nm: weight {:.4}, drawn {share:.4}{}",
            l.nm,
            l.weight,
            if wrong_pdf > 0 {
                format!(", {wrong_pdf} samples with pdf ≠ weight")
            } else {
                String::new()
            }
        ));
        if !(l.weight > 0.0 && l.weight <= 1.0) {
            worst = f64::INFINITY;
        }
    }
    for (nm, c) in atoms(samples) {
        let nm = f64::from_bits(nm);
        if on_line(obj, nm) {
            continue;
        }
        let share = c as f64 / n;
        worst = worst.max(share / 1e-4);
        detail.push(format!("UNDECLARED line at {nm} nm: drawn {share:.4}"));
    }
    if detail.is_empty() {
        detail.push("no lines declared, none drawn".into());
    }
    CheckResult::measured(
        "lines",
        "max |share − weight| / (5σ + 1e-4)",
        worst,
        Bound::AtMost,
        1.0,
        detail.join("; "),
    )
}

fn answers(obj: &SpdObject) -> Vec<u64> {
    let mut rng = Rng::new(0x5354_5350);
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    let mut out = Vec::new();
    for _ in 0..256 {
        let nm = a + (b - a) * rng.f64();
        let u = rng.f64();
        let v = obj
            .spd
            .value(nm)
            .into_result()
            .map(f64::to_bits)
            .unwrap_or(1);
        let p = obj.spd.pdf(nm).into_result().map(f64::to_bits).unwrap_or(1);
        let s = obj
            .spd
            .sample(u)
            .into_result()
            .map(|s| s.nm.to_bits() ^ s.pdf.to_bits().rotate_left(17))
            .unwrap_or(1);
        out.extend([v, p, s]);
    }
    out
}

fn state(obj: &SpdObject, calls: &Calls<'_, SpdObject>) -> CheckResult {
    let Some(restore) = calls.restore else {
        return CheckResult::skipped("state", "no way to rebuild this object from state here");
    };
    let bytes = match obj.spd.save_state().into_result() {
        Ok(b) => b,
        Err(e) => return CheckResult::failed("state", format!("save_state failed: {e}")),
    };
    let restored = match restore(&bytes) {
        Ok(r) => r,
        Err(e) => {
            return CheckResult::failed("state", format!("rebuilding from its state failed: {e}"))
        }
    };
    let a = answers(obj);
    let b = answers(&restored);
    let mut n = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    n += usize::from(obj.range != restored.range || obj.lines != restored.lines);
    CheckResult::measured(
        "state",
        "answers differing after restore",
        n as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{} bytes of state, {} answers and the declarations compared",
            bytes.len(),
            a.len()
        ),
    )
}
