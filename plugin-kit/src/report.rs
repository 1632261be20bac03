//! What the kit answers: one [`Report`] per object, one [`CheckResult`] per check, printed as a
//! table or as JSON.

use serde::Serialize;
use std::fmt;

/// A check's verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The statistic is within the threshold.
    Pass,
    /// It is not: the object breaks the contract the check tests.
    Fail,
    /// The check does not apply to this object (the detail says why), e.g. reciprocity for a
    /// material that does not declare it.
    Skip,
}

impl Status {
    fn as_str(self) -> &'static str {
        match self {
            Status::Pass => "pass",
            Status::Fail => "FAIL",
            Status::Skip => "n/a",
        }
    }
}

/// How a statistic compares with its threshold to pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Bound {
    /// Passes when statistic ≤ threshold.
    #[serde(rename = "<=")]
    AtMost,
    /// Passes when statistic ≥ threshold.
    #[serde(rename = ">=")]
    AtLeast,
}

/// One check of one object.
#[derive(Clone, Debug, Serialize)]
pub struct CheckResult {
    /// The check's name (`chi2`, `energy`, `state`, …; see the crate docs for the list).
    pub check: String,
    /// Verdict.
    pub status: Status,
    /// What the statistic is, e.g. "min p-value" or "max albedo − 1 − 5σ".
    pub statistic_name: String,
    /// Its value (NaN when the check could not compute it; such a check fails).
    pub statistic: f64,
    /// The bound it must meet.
    pub bound: Bound,
    /// The threshold.
    pub threshold: f64,
    /// What was measured, and where it went wrong when it did.
    pub detail: String,
}

impl CheckResult {
    /// A result from a statistic: passes when it meets the bound (a NaN statistic fails).
    pub fn measured(
        check: &str,
        statistic_name: &str,
        statistic: f64,
        bound: Bound,
        threshold: f64,
        detail: impl Into<String>,
    ) -> Self {
        let ok = match bound {
            Bound::AtMost => statistic <= threshold,
            Bound::AtLeast => statistic >= threshold,
        };
        Self {
            check: check.into(),
            status: if ok { Status::Pass } else { Status::Fail },
            statistic_name: statistic_name.into(),
            statistic,
            bound,
            threshold,
            detail: detail.into(),
        }
    }
    /// A check that does not apply, with the reason.
    pub fn skipped(check: &str, reason: impl Into<String>) -> Self {
        Self {
            check: check.into(),
            status: Status::Skip,
            statistic_name: String::new(),
            statistic: f64::NAN,
            bound: Bound::AtMost,
            threshold: f64::NAN,
            detail: reason.into(),
        }
    }
    /// A check that failed before it could measure (a call returned an error), with the reason.
    pub fn failed(check: &str, reason: impl Into<String>) -> Self {
        Self {
            check: check.into(),
            status: Status::Fail,
            statistic_name: "error".into(),
            statistic: f64::NAN,
            bound: Bound::AtMost,
            threshold: f64::NAN,
            detail: reason.into(),
        }
    }
}

/// Every check of one object: which plugin type, built from which parameters, and the results.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Object kind (`light`, `material`, `spd`, `observer`).
    pub kind: String,
    /// Type name.
    pub type_name: String,
    /// The parameters it was built from (RON).
    pub params: String,
    /// The results, in the order the checks ran.
    pub checks: Vec<CheckResult>,
}

impl Report {
    /// True when no check failed (skipped checks do not fail).
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.status != Status::Fail)
    }
    /// The result of the check named `check`, if it ran.
    pub fn get(&self, check: &str) -> Option<&CheckResult> {
        self.checks.iter().find(|c| c.check == check)
    }
    /// Names of the checks that failed.
    pub fn failures(&self) -> Vec<&str> {
        self.checks
            .iter()
            .filter(|c| c.status == Status::Fail)
            .map(|c| c.check.as_str())
            .collect()
    }
    /// For an author's `cargo test`: panic with the table when a check failed.
    #[track_caller]
    pub fn assert_pass(&self) {
        assert!(
            self.passed(),
            "conformance checks failed: {:?}\n{self}",
            self.failures()
        );
    }
    /// The report as JSON (the fields of [`Report`] and [`CheckResult`]; NaN as null).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}

fn number(v: f64) -> String {
    if v.is_nan() {
        "-".into()
    } else if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

impl fmt::Display for Report {
    /// The table: check, statistic, value, threshold, result, then the detail on the next line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} `{}` {}", self.kind, self.type_name, self.params)?;
        writeln!(
            f,
            "  {:<13} {:<34} {:>11} {:>13}  result",
            "check", "statistic", "value", "threshold"
        )?;
        for c in &self.checks {
            let threshold = if c.threshold.is_nan() {
                "-".to_string()
            } else {
                format!(
                    "{} {}",
                    match c.bound {
                        Bound::AtMost => "<=",
                        Bound::AtLeast => ">=",
                    },
                    number(c.threshold)
                )
            };
            writeln!(
                f,
                "  {:<13} {:<34} {:>11} {:>13}  {}",
                c.check,
                c.statistic_name,
                number(c.statistic),
                threshold,
                c.status.as_str()
            )?;
            if !c.detail.is_empty() {
                writeln!(f, "      {}", c.detail)?;
            }
        }
        Ok(())
    }
}
