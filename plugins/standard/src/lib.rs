//! The standard set as a library: the host's built-in SPD types (`spec`, `table`) and CIE
//! observers (`cie1931-2`, `cie1964-10`, `cie2015-2`, `cie2015-10`) exported through the plugin
//! API under their built-in names, built by the host's own constructors (see `Cargo.toml` for
//! the trade-off). Since the names clash with the built-ins, the host refuses this library next
//! to them; `--replace-builtins` makes its types replace the built-ins of the same name
//! (`--no-builtins` leaves the built-in materials, lights, SPDs and observers out altogether).
//!
//! The built-in materials and lights are not exported yet: wrapping a host light or material
//! as a plugin object means mapping every sampling routine onto the plugin interface.

pub mod observer;
pub mod spd;
mod wrap;

pub use observer::{Cie1931_2, Cie1964_10, Cie2015_10, Cie2015_2};
pub use spd::{SpecSpd, TableSpd};

spectrace_plugin_api::export_plugin! {
    name: "standard",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [SpecSpd, TableSpd],
    observers: [Cie1931_2, Cie1964_10, Cie2015_2, Cie2015_10],
    materials: [],
}
