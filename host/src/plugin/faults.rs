//! Where plugin failures go while rendering: [`PluginFaults`], shared by every adapter of one
//! scene, and [`Origin`], the object an adapter speaks for.

use super::checked;
use spectrace_plugin_api::abi::std_types::RResult;
use spectrace_plugin_api::PluginError;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Errors raised by plugin calls while rendering: the first message and how many there were;
/// per call site, how many and the first message; per object and reason, how many results
/// were dropped as invalid (see [`super::checked`]).
#[derive(Default, Debug)]
pub struct PluginFaults {
    first: Mutex<Option<String>>,
    count: AtomicU64,
    sites: Mutex<BTreeMap<(String, String), (u64, String)>>,
    invalid: Mutex<BTreeMap<(String, &'static str), u64>>,
    invalid_count: AtomicU64,
}

/// Distinct call sites remembered; beyond, failures are counted under one "other" entry, so a
/// plugin whose messages vary per call cannot grow the table without bound.
const MAX_SITES: usize = 64;

impl PluginFaults {
    /// A new, empty collector shared by every adapter of one scene.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// Record `error` raised by `who`. The call site is the message up to its first `": "`
    /// (for a caught panic: the call and the panic's file:line, see the API's `guard`).
    pub fn record(&self, who: &str, error: &PluginError) {
        if self.count.fetch_add(1, Ordering::Relaxed) == 0 {
            if let Ok(mut first) = self.first.lock() {
                first.get_or_insert_with(|| format!("{who}: {error}"));
            }
        }
        let site = error.message.split(": ").next().unwrap_or_default();
        if let Ok(mut sites) = self.sites.lock() {
            let mut key = (who.to_string(), site.chars().take(200).collect::<String>());
            if !sites.contains_key(&key) && sites.len() >= MAX_SITES {
                key = (who.to_string(), "(other call sites)".to_string());
            }
            sites.entry(key).or_insert_with(|| (0, error.to_string())).0 += 1;
        }
    }

    /// Record that a result of `who` was dropped as invalid, for `reason`.
    pub fn record_invalid(&self, who: &str, reason: &'static str) {
        self.invalid_count.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut invalid) = self.invalid.lock() {
            *invalid.entry((who.to_string(), reason)).or_insert(0) += 1;
        }
    }

    /// The first recorded error, if any.
    pub fn first(&self) -> Option<String> {
        self.first.lock().ok().and_then(|f| f.clone())
    }

    /// How many errors were recorded.
    pub fn count(&self) -> u64 {
        self.count.load(Ordering::Relaxed)
    }

    /// How many results were dropped as invalid.
    pub fn invalid_count(&self) -> u64 {
        self.invalid_count.load(Ordering::Relaxed)
    }

    /// Failed calls per (object, call site): `(who, site, count, first message)`, sorted.
    pub fn sites(&self) -> Vec<(String, String, u64, String)> {
        self.sites
            .lock()
            .map(|s| {
                s.iter()
                    .map(|((w, site), (n, msg))| (w.clone(), site.clone(), *n, msg.clone()))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Dropped results per (object, reason): `(who, reason, count)`, sorted.
    pub fn invalid(&self) -> Vec<(String, &'static str, u64)> {
        self.invalid
            .lock()
            .map(|s| s.iter().map(|((w, r), n)| (w.clone(), *r, *n)).collect())
            .unwrap_or_default()
    }

    /// The render summary's lines: one per call site that failed and one per (object, reason)
    /// whose results were dropped, each with its count. Empty when all went well.
    pub fn report(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .sites()
            .into_iter()
            .map(|(who, site, n, first)| {
                format!("{who}: {n} failed call(s) at `{site}`; first: {first}")
            })
            .collect();
        lines.extend(
            self.invalid()
                .into_iter()
                .map(|(who, reason, n)| format!("{who}: {n} result(s) dropped: {reason}")),
        );
        lines
    }

    /// How a command ends after rendering with plugins: `Err` when plugin calls failed (the
    /// image was still written; the message lists each failing call site once, with its
    /// count), else `Ok` with one warning line per (object, reason) whose results were dropped.
    pub fn outcome(&self) -> Result<Vec<String>, String> {
        if self.count() == 0 {
            return Ok(self.report());
        }
        Err(format!(
            "{} plugin call(s) failed during rendering (their samples contributed nothing; the \
             image was still written):\n  {}",
            self.count(),
            self.report().join("\n  ")
        ))
    }
}

/// Who an adapter speaks for, in error messages.
#[derive(Clone, Debug)]
pub struct Origin {
    /// e.g. "light `spot` (plugin point-light 0.1.0)".
    pub label: String,
    /// Where errors go.
    pub faults: Arc<PluginFaults>,
}

impl Origin {
    #[cold]
    #[inline(never)]
    pub(crate) fn fail<T>(&self, e: PluginError, fallback: T) -> T {
        self.faults.record(&self.label, &e);
        fallback
    }

    /// Record a result dropped for `reason` (kept out of the callers' hot code).
    #[cold]
    #[inline(never)]
    pub(crate) fn dropped(&self, reason: checked::Reason) {
        self.faults.record_invalid(&self.label, reason);
    }

    /// The call's value if it passes `check`; otherwise `None`, with the error or the
    /// dropped result recorded.
    pub(crate) fn checked<T>(
        &self,
        r: RResult<T, PluginError>,
        check: impl FnOnce(&T) -> Result<(), checked::Reason>,
    ) -> Option<T> {
        match r {
            RResult::ROk(v) => match check(&v) {
                Ok(()) => Some(v),
                Err(reason) => {
                    self.faults.record_invalid(&self.label, reason);
                    None
                }
            },
            RResult::RErr(e) => self.fail(e, None),
        }
    }
}
