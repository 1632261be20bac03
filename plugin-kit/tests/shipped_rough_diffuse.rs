//! A shipped plugin passes every check in-process, through the typed entry point an author's
//! `cargo test` uses.

#[test]
fn oren_nayar_passes() {
    let r = spectrace_plugin_kit::check_material::<spectrace_rough_diffuse::OrenNayar>(
        "(roughness: 0.8)",
    );
    println!("{r}");
    r.assert_pass();
}
