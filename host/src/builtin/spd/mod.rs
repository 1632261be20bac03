//! Built-in SPD types (for `spd: (type: .., params: ..)`), one per file.

pub mod spec;
pub mod table;
