//! The standard set as a library: the host's built-in materials (`lambertian`, `mirror`,
//! `dielectric`, `rough_dielectric`, `conductor`, `plastic`, `rough_plastic`, `emissive`,
//! `fluorescent`), lights (`point`, `spot`,
//! `directional`, `environment`), SPD types (`spec`, `table`) and CIE observers (`cie1931-2`,
//! `cie1964-10`, `cie2015-2`, `cie2015-10`) exported through the plugin API under their built-in
//! names, built by the host's own constructors (see `Cargo.toml` for the trade-off). Since the
//! names clash with the built-ins, the host refuses this library next to them;
//! `--replace-builtins` makes its types replace the built-ins of the same name (`--no-builtins`
//! leaves the built-in materials, lights, SPDs and observers out altogether).
//!
//! What makes the library render bit for bit like the built-ins: emitters hand over their own
//! SPD objects, lights learn the scene's bounds, materials see the surface's normals and compute
//! in the host's own layout, and `fluorescent` hands over its re-radiation.

pub mod light;
pub mod material;
pub mod observer;
pub mod spd;
mod wrap;

pub use light::{Directional, Environment, Point, Spot};
pub use material::{
    Conductor, Dielectric, Emissive, Fluorescent, Lambertian, Mirror, Plastic, RoughDielectric,
    RoughPlastic,
};
pub use observer::{Cie1931_2, Cie1964_10, Cie2015_10, Cie2015_2};
pub use spd::{SpecSpd, TableSpd};

spectrace_plugin_api::export_plugin! {
    name: "standard",
    version: env!("CARGO_PKG_VERSION"),
    lights: [Point, Spot, Directional, Environment],
    spds: [SpecSpd, TableSpd],
    observers: [Cie1931_2, Cie1964_10, Cie2015_2, Cie2015_10],
    materials: [Lambertian, Mirror, Dielectric, RoughDielectric, Conductor, Plastic, RoughPlastic, Emissive, Fluorescent],
}
