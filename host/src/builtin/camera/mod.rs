//! Built-in cameras.

pub mod perspective;
