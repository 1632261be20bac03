//! A shipped plugin passes every check in-process, through the typed entry point an author's
//! `cargo test` uses (its default spectrum `"e"` resolved by the kit's stand-in host).

#[test]
fn point_and_spot_pass() {
    for r in [
        spectrace_plugin_kit::check_light::<spectrace_point_light::PointLight>(
            "(position: (0, 1, 0), power_w: 25)",
        ),
        spectrace_plugin_kit::check_light::<spectrace_point_light::SpotLight>(
            "(position: (0, 1, 0), direction: (0, -1, 0), power_w: 25)",
        ),
    ] {
        println!("{r}");
        r.assert_pass();
    }
}
