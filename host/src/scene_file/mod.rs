//! The scene file and the contract its items are built through, below the registry and the
//! scene builder that both use it:
//! - what a scene file says: its RON format ([`description`]) and the pinned plugin libraries of
//!   its `plugins` list ([`pin`]);
//! - how an item's `params` are read: typed access with errors that name the parameter
//!   ([`params`]), lengths in the scene's unit converted to metres ([`units`]) and the
//!   representation of spectral data ([`representation`]);
//! - what every type declares, built in or loaded: its kind, name and parameter table
//!   ([`type_doc`]);
//! - [`ObjectFactory`] ([`factory`]): the trait through which an item's `type` and `params`
//!   become an object; the built-in types and the plugin registry implement it, and the scene
//!   builder asks the factories it is given, so neither the scene nor this floor imports them.

pub mod description;
pub mod factory;
pub mod params;
pub mod pin;
pub mod representation;
pub mod type_doc;
pub mod units;

pub use description::SceneDescription;
pub use factory::{FactoryContext, FactoryError, ObjectFactory, SpdFactories};
pub use representation::{ReflectanceSource, RepresentationOptions};
pub use type_doc::{Kind, ParamDoc, TypeDoc};
pub use units::LengthUnit;
