//! The checks of a colour observer ([`ObserverObject`]).
//!
//! | check | statistic | threshold | why |
//! |---|---|---|---|
//! | `finite` | values of x̄, ȳ, z̄ that are NaN, ±∞ or < 0 (or calls that failed), every 0.25 nm over the declared range and 50 nm beyond | 0 | colour-matching functions of a physical observer are sensitivities: finite and not negative |
//! | `range` | values ≠ 0 outside the declared range, plus 1 when the range is empty, not finite or outside 100–5000 nm, plus 1 when every value inside is 0 | 0 | the host integrates only over the declared range, so what lies outside would be lost |
//! | `state` | answers of the object rebuilt from its saved state that differ | 0 | blobs rebuild objects from it |

use crate::report::{Bound, CheckResult};
use crate::subject::Calls;
use spectrace_plugin_api::ObserverObject;

/// Run every observer check.
pub fn run(obj: &ObserverObject, calls: &Calls<'_, ObserverObject>) -> Vec<CheckResult> {
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    let range_ok = a.is_finite() && b.is_finite() && a < b && a >= 100.0 && b <= 5000.0;
    let (lo, hi) = if range_ok { (a, b) } else { (360.0, 830.0) };
    let mut bad = 0u64;
    let mut outside = 0u64;
    let mut inside_nonzero = false;
    let mut first = String::new();
    let steps = ((hi - lo + 100.0) / 0.25).round() as usize;
    for i in 0..=steps {
        let nm = lo - 50.0 + 0.25 * i as f64;
        match obj.observer.xyz_bar(nm).into_result() {
            Ok(v) => {
                let vals = [v.x, v.y, v.z];
                if vals.iter().any(|x| !x.is_finite() || *x < 0.0) {
                    bad += 1;
                    if first.is_empty() {
                        first = format!("at {nm} nm: {vals:?}");
                    }
                }
                let inside = nm >= lo && nm <= hi;
                if inside && vals.iter().any(|x| *x != 0.0) {
                    inside_nonzero = true;
                }
                if !inside && vals.iter().any(|x| *x != 0.0) {
                    outside += 1;
                }
            }
            Err(e) => {
                bad += 1;
                if first.is_empty() {
                    first = format!("at {nm} nm: {e}");
                }
            }
        }
    }
    let range_faults = outside + u64::from(!range_ok) + u64::from(!inside_nonzero);
    vec![
        CheckResult::measured(
            "finite",
            "bad values",
            bad as f64,
            Bound::AtMost,
            0.0,
            format!(
                "{} wavelengths from {} to {} nm{}",
                steps + 1,
                lo - 50.0,
                hi + 50.0,
                if first.is_empty() {
                    String::new()
                } else {
                    format!("; first: {first}")
                }
            ),
        ),
        CheckResult::measured(
            "range",
            "faults of the declared range",
            range_faults as f64,
            Bound::AtMost,
            0.0,
            format!(
                "declared [{a}, {b}] nm; {outside} wavelengths outside it with values ≠ 0{}{}",
                if range_ok {
                    ""
                } else {
                    "; the range itself is unusable"
                },
                if inside_nonzero {
                    ""
                } else {
                    "; every value inside is 0"
                }
            ),
        ),
        state(obj, calls),
    ]
}

fn answers(obj: &ObserverObject) -> Vec<u64> {
    let (a, b) = (obj.range.min_nm, obj.range.max_nm);
    (0..512)
        .flat_map(|i| {
            let nm = a + (b - a) * (i as f64 + 0.37) / 512.0;
            match obj.observer.xyz_bar(nm).into_result() {
                Ok(v) => [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()],
                Err(_) => [1, 1, 1],
            }
        })
        .collect()
}

fn state(obj: &ObserverObject, calls: &Calls<'_, ObserverObject>) -> CheckResult {
    let Some(restore) = calls.restore else {
        return CheckResult::skipped("state", "no way to rebuild this object from state here");
    };
    let bytes = match obj.observer.save_state().into_result() {
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
    n += usize::from(obj.range != restored.range || obj.name != restored.name);
    CheckResult::measured(
        "state",
        "answers differing after restore",
        n as f64,
        Bound::AtMost,
        0.0,
        format!(
            "{} bytes of state, {} answers compared",
            bytes.len(),
            a.len()
        ),
    )
}
