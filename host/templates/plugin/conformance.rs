//! The conformance kit on this plugin's type: the checks `spectrace plugins check` runs on the
//! built library, here in-process with `cargo test`. Each check has a statistic and a
//! threshold; a failure prints the whole table.

#[test]
fn __TYPE___passes_the_conformance_kit() {
    let report = spectrace_plugin_kit::__CHECK__::<__CRATE__::__RUST_TYPE__>("()");
    println!("{report}");
    report.assert_pass();
}

/// The same type through the plugin's root module, as the host loads it.
#[test]
fn the_root_module_passes_the_conformance_kit() {
    for report in spectrace_plugin_kit::check_module(__CRATE__::root_module(), &Default::default()) {
        report.assert_pass();
    }
}
