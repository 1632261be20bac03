//! SPD and observer types shipped as a plugin: a Lorentzian emission line (the shape of a
//! pressure-broadened gas-discharge line) and a three-channel camera sensor with Gaussian
//! sensitivities, usable wherever the host takes an SPD or an observer.

pub mod gaussian_sensor;
pub mod lorentzian;

pub use gaussian_sensor::GaussianSensor;
pub use lorentzian::Lorentzian;

spectrace_plugin_api::export_plugin! {
    name: "sensor-spectra",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [Lorentzian],
    observers: [GaussianSensor],
    materials: [],
}
