//! Helpers of the kit's tests (one test binary per plugin crate: each crate exports the same
//! root-module symbol, so two cannot be linked into one binary).

use spectrace_plugin_api::PluginModuleRef;
use spectrace_plugin_kit::{check_module, Options, Report};

#[allow(dead_code)]
pub fn check(module: PluginModuleRef, type_name: &str) -> Report {
    let mut r = check_module(
        module,
        &Options {
            type_name: Some(type_name.into()),
            params: None,
        },
    );
    assert_eq!(r.len(), 1);
    r.remove(0)
}

/// The report fails exactly `check` (every other check passes or does not apply).
#[allow(dead_code)]
pub fn assert_only(r: &Report, check: &str) {
    assert_eq!(
        r.failures(),
        vec![check],
        "{} `{}` should fail `{check}` alone:\n{r}",
        r.kind,
        r.type_name
    );
}
