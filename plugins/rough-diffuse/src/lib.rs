//! A material type shipped as a plugin: Oren–Nayar rough diffuse reflection. Plaster, clay,
//! concrete and the moon look flatter than a Lambertian surface predicts, because their
//! microfacets mask and shadow each other and retro-reflect; a lighting designer wants that
//! flattening when judging how a wall reads under a grazing light.

pub mod oren_nayar;

pub use oren_nayar::OrenNayar;

spectrace_plugin_api::export_plugin! {
    name: "rough-diffuse",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [],
    observers: [],
    materials: [OrenNayar],
}
