//! Point and spot lights, as a spectrace plugin library.
//!
//! Both take their spectrum as an SPD spec that the host resolves (`"d65"`, `"blackbody:3000"`,
//! a CSV path, or an SPD type from another plugin), so colour and geometry come from different
//! authors in one scene.

mod frame;
pub mod point;
pub mod spot;

pub use point::PointLight;
pub use spot::SpotLight;

spectrace_plugin_api::export_plugin! {
    name: "point-light",
    version: env!("CARGO_PKG_VERSION"),
    lights: [PointLight, SpotLight],
    spds: [],
    observers: [],
    materials: [],
}
