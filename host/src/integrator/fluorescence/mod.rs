//! Fluorescence along a path: the re-radiation events and joining fluorescent subpaths.

pub mod events;
pub mod join;
