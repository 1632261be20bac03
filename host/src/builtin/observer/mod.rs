//! Built-in colour observers.

pub mod cie;
