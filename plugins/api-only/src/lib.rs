//! Two of spectrace's built-in types written again by an outsider: from the plugin API alone
//! (`spectrace-plugin-api`), without linking the host crate, to show that a third-party plugin
//! can match a built-in (issue 27, item 4). `plugins/standard`, by contrast, wraps the host's
//! own code, so its bit-identity shows only that values cross the boundary intact.
//!
//! | type | re-implements | what |
//! |---|---|---|
//! | material `api_conductor` ([`conductor`]) | built-in `conductor` / `rough_conductor` | GGX (Trowbridge–Reitz) microfacets, visible-normal sampling, conductor Fresnel with measured n, k of gold, silver, copper, aluminium |
//! | light `api_spot` ([`spot`]) | built-in `spot` | point light in a cone with a smoothstep falloff between two half-angles; power in W, lm or cd |
//!
//! Their parameters, units and conventions are the built-ins' (same names, same defaults, same
//! checks), so a scene switches by changing `type:` alone (`scenes/api_only/`). The data they
//! need is in this crate's tree with its source (`data/`): the metals' complex indices and the
//! CIE 1931 V(λ) for photometric powers. They agree with the built-ins to f32 rounding
//! (`tests/tests/api_only.rs`); see `docs/plugins.md`, "An API-only plugin matches the built-ins".

pub mod conductor;
pub mod fresnel;
pub mod ggx;
pub mod metals;
pub mod params;
pub mod photometry;
pub mod spectrum;
pub mod spot;
pub mod vec;

pub use conductor::Conductor;
pub use spot::Spot;

spectrace_plugin_api::export_plugin! {
    name: "api-only",
    version: env!("CARGO_PKG_VERSION"),
    lights: [Spot],
    spds: [],
    observers: [],
    materials: [Conductor],
}
